"""The coarsest raster relaxation handed from the late proof to the plan's regrasp bound.

A plan whose search is slow to find a path asks the late proof
(:class:`~pivot_ompl.analysis.late_proof.LateProof`), which on most scenes builds the coarsest
raster cover of the scene and its graph
(:func:`~pivot_ompl.analysis.turning_raster.raster_turning_place`) and finds that they join
start and goal: nothing to prove. When that plan regrasps, its quality block then asks the
regrasp bound (:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound`), whose first
level builds the very same cover and graph (same cell, clearance, tolerance and bins) a
second time: about 0.1 s of a shipped scene's first plan. :func:`keep_coarse` keeps them for
the bound instead and :func:`take_coarse` hands them over once (then forgets them: the guided
refinement frees the graph after its first round). Only small covers are kept
(:data:`MAX_KEPT_CELLS`): a large floor's cover would be held through the whole search, a
larger peak than building it again costs.

The graph's regrasp checks are lazy and deterministic, so a graph the late proof has already
searched answers every later search as a new one would (its walk checks already made).
"""

from __future__ import annotations

from pivot_ompl.analysis.raster_bound import RasterGraph
from pivot_ompl.analysis.raster_cover import RasterCover
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import drop_shared, keep_shared, shared_value

__all__ = ["MAX_KEPT_CELLS", "keep_coarse", "take_coarse"]

#: Largest cover kept (cells times layers: 4 bytes each in its labels, 32 MB).
MAX_KEPT_CELLS = 8_000_000


def _what(cell: float, clearance: float) -> tuple[str, float, float]:
    return ("coarse raster", cell, clearance)


def keep_coarse(scene: Scene, cover: RasterCover, graph: RasterGraph, *, cell: float,
                clearance: float) -> bool:
    """Keep ``cover`` and its ``graph`` for the bound of ``scene``; whether they were kept.

    Both built with ``cell`` and ``clearance``, every other argument the default; kept
    only when small (:data:`MAX_KEPT_CELLS`).
    """
    nx, ny = cover.raster.shape
    if nx * ny * len(cover.layers) > MAX_KEPT_CELLS:
        return False
    keep_shared(scene, _what(cell, clearance), (cover, graph))
    return True


def take_coarse(scene: Scene, *, cell: float, clearance: float
                ) -> tuple[RasterCover, RasterGraph] | None:
    """The cover and graph kept for ``scene`` with ``cell`` and ``clearance``, now forgotten.

    ``None`` when none is kept.
    """
    what = _what(cell, clearance)
    kept = shared_value(scene, what)
    if kept is None:
        return None
    drop_shared(scene, what)
    cover, graph = kept
    return cover, graph

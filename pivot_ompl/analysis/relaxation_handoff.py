"""The late proof's relaxations handed to the plan's regrasp bound: built once, not twice.

A plan whose search is slow to find a path asks the late proof
(:class:`~pivot_ompl.analysis.late_proof.LateProof`), which builds a relaxation of the scene
and its graph, and on a scene with a plan finds that they join start and goal: nothing to
prove. When that plan regrasps, its quality block then asks the regrasp bound
(:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound`), which builds the very same
relaxations (same cells or yaw bins, clearance and tolerance) a second time: about 0.1 s of
a shipped scene's first plan for the coarsest raster, 0.3-1 s for the exact polygons. So the
late proof keeps what it built (:func:`keep_coarse`: the raster's
:class:`~pivot_ompl.analysis.raster_cover.RasterCover` and graph, from
:func:`~pivot_ompl.analysis.turning_raster.raster_turning_place`; :func:`keep_exact`: the
polygons' :class:`~pivot_ompl.analysis.regrasp_bound.FreeCover` and graph, from
:func:`~pivot_ompl.analysis.turning.turning_place`), and the bound takes them
(:func:`take_coarse`, :func:`take_exact`): once, then they are forgotten (the guided
refinement frees the raster's graph after its first round); a plan whose bound needs no
relaxation (no regrasps, or a bound the cache holds) forgets them (:func:`forget_kept`).
Only small relaxations are kept (:data:`MAX_KEPT_CELLS`, :data:`MAX_KEPT_PIECES`): a large
floor's would be held through the whole search, a larger peak than building it again costs.

The graphs' regrasp checks are lazy and deterministic, so a graph the late proof has already
searched answers every later search as a new one would (its walk checks already made): the
bound is the same, only sooner.
"""

from __future__ import annotations

from collections.abc import Hashable
from typing import Any

from pivot_ompl.analysis.raster_bound import RasterGraph
from pivot_ompl.analysis.raster_cover import RasterCover
from pivot_ompl.analysis.regrasp_bound import CoverGraph, FreeCover
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import drop_shared, keep_shared, shared_value

__all__ = ["MAX_KEPT_CELLS", "MAX_KEPT_PIECES", "forget_kept", "keep_coarse", "keep_exact",
           "take_coarse", "take_exact"]

#: Largest raster cover kept (cells times layers: 1 to 4 bytes each in its labels, at most
#: 16 MB; a shipped scene's is about 1.2 million).
MAX_KEPT_CELLS = 4_000_000
#: Largest polygon cover kept (its pieces, every bin and grasp).
MAX_KEPT_PIECES = 50_000
#: What each is kept under (one of each kind per scene: a later one replaces it).
_COARSE, _EXACT = ("late proof: coarse raster",), ("late proof: exact polygons",)


def keep_coarse(scene: Scene, cover: RasterCover, graph: RasterGraph, *, cell: float,
                clearance: float) -> bool:
    """Keep ``cover`` and its ``graph`` for the bound of ``scene``; whether they were kept.

    Both built with ``cell`` and ``clearance``, every other argument the default; kept
    only when small (:data:`MAX_KEPT_CELLS`).
    """
    nx, ny = cover.raster.shape
    if nx * ny * len(cover.layers) > MAX_KEPT_CELLS:
        return False
    keep_shared(scene, _COARSE, (cell, clearance, cover, graph))
    return True


def take_coarse(scene: Scene, *, cell: float, clearance: float
                ) -> tuple[RasterCover, RasterGraph] | None:
    """The raster cover and graph kept for ``scene``, now forgotten (``None``: none is).

    Those kept with ``cell`` and ``clearance`` (:func:`keep_coarse`).
    """
    return _take(scene, _COARSE, (cell, clearance))


def keep_exact(scene: Scene, cover: FreeCover, graph: CoverGraph, *, resolution: float,
               clearance: float) -> bool:
    """Keep the polygon ``cover`` and its ``graph`` for the bound of ``scene``; whether kept.

    Both built with ``resolution`` and ``clearance``, every other argument the default
    (walks checked); kept only when small (:data:`MAX_KEPT_PIECES`).
    """
    if len(graph.nodes) > MAX_KEPT_PIECES:
        return False
    keep_shared(scene, _EXACT, (resolution, clearance, cover, graph))
    return True


def take_exact(scene: Scene, *, resolution: float, clearance: float
               ) -> tuple[FreeCover, CoverGraph] | None:
    """The polygon cover and graph kept for ``scene``, now forgotten (``None``: none is).

    Those kept with ``resolution`` and ``clearance`` (:func:`keep_exact`).
    """
    return _take(scene, _EXACT, (resolution, clearance))


def forget_kept(scene: Scene) -> None:
    """Forget whatever is kept for ``scene`` (a plan whose bound needs no relaxation)."""
    for what in (_COARSE, _EXACT):
        drop_shared(scene, what)


def _take(scene: Scene, what: tuple[Hashable, ...], args: tuple[float, float]) -> Any:
    """The relaxation and graph kept for ``scene`` and ``what``, forgotten.

    ``None`` when none is, or when it was built with other ``args``.
    """
    kept = shared_value(scene, what)
    if kept is None:
        return None
    drop_shared(scene, what)
    return kept[2:] if kept[:2] == args else None

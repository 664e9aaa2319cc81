"""The place where the held box cannot turn, on the raster relaxation (large floors).

For floors too large for the exact polygons in the time a plan has. The same construction
as :func:`~pivot_ompl.analysis.turning.turning_place` on the raster cover of
:mod:`~pivot_ompl.analysis.raster_bound` (its pieces are cells of one yaw bin and grasp):
the cells reachable from the start and those from which the goal is reachable; when the goal
is not among the first, no plan exists (the raster relaxation's proof), and the place is the
middle of their largest overlap (the cells both reach, at different yaws), else the midpoint
of their nearest cells. The yaws are those of the pieces within
:data:`~pivot_ompl.analysis.turning.NEAR` of the place.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from scipy import ndimage

from pivot_ompl.analysis.raster_bound import CELL, RasterGraph, raster_graph
from pivot_ompl.analysis.raster_cover import RasterCover, raster_cover
from pivot_ompl.analysis.relaxation_handoff import keep_coarse
from pivot_ompl.analysis.turning import (
    NEAR,
    TurningPlace,
    assembly_outline,
    widest_circle,
    yaw_arc,
)
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE

_EIGHT = np.ones((3, 3), dtype=bool)

#: The pieces of each layer ``(grasp % 2, bin)`` reached, by their ``(bin, grasp)``.
Reached = dict[tuple[int, int], set[int]]


def raster_turning_place(scene: Scene, *, cell: float = CELL,
                         clearance: float = KEEP_CLEARANCE,
                         should_stop: Callable[[], bool] | None = None,
                         keep: bool = False) -> TurningPlace | None:
    """The place where the held box cannot turn (module docstring), when no plan exists.

    ``None`` when the raster relaxation joins start and goal (nothing is proven), or when
    ``should_stop`` said stop. A place returned is a proof that no plan exists. ``keep``:
    a cover and graph that join start and goal are kept for the plan's regrasp bound
    (:func:`~pivot_ompl.analysis.relaxation_handoff.keep_coarse`).
    """
    try:
        return _place(scene, cell, clearance, should_stop, keep)
    except Interrupted:
        return None


def _place(scene: Scene, cell: float, clearance: float,
           should_stop: Callable[[], bool] | None, keep: bool) -> TurningPlace | None:
    cover = raster_cover(scene, cell=cell, clearance=clearance, should_stop=should_stop)
    if cover is None:
        return None
    joined = raster_graph(scene, cover, clearance=clearance, should_stop=should_stop)
    starts, goals = joined.holding(scene.start), joined.holding(scene.goal)
    if not starts or not goals:
        return None
    # a goal reached proves nothing, so the regrasps beyond it go unchecked (where none is
    # reached, check_beyond never applies: the pieces reached are the same)
    best, from_start = joined.graph.fewest_regrasps(starts, set(goals), joined.allowed,
                                                    should_stop, check_beyond=False)
    if best is not None:
        if keep:
            keep_coarse(scene, cover, joined, cell=cell, clearance=clearance)
        return None
    _, to_goal = joined.graph.fewest_regrasps(goals, set(), joined.allowed, should_stop)
    s_reached, g_reached = _by_layer(joined, from_start), _by_layer(joined, to_goal)
    s_mask = _mask(cover, joined, s_reached, should_stop)
    g_mask = _mask(cover, joined, g_reached, should_stop)
    (i, j), reach = _meeting_cell(s_mask, g_mask)
    (x0, y0), h = cover.raster.origin, cover.raster.cell
    centre = shapely.Point(x0 + (i + 0.5) * h, y0 + (j + 0.5) * h)
    w, length = assembly_outline(scene.model, clearance=clearance)
    rad = reach + max(1, int(np.ceil(NEAR / h)))
    return TurningPlace((float(centre.x), float(centre.y)),
                        widest_circle(scene, centre, 0.5 * length, should_stop), w, length,
                        yaw_arc(_bins_near(cover, joined, s_reached, (i, j), rad), cover.bins),
                        yaw_arc(_bins_near(cover, joined, g_reached, (i, j), rad), cover.bins))


def _by_layer(joined: RasterGraph, nodes: set[int]) -> Reached:
    """The labels of ``nodes`` by their ``(bin, grasp)``."""
    keys = sorted(joined.base.items(), key=lambda kv: kv[1])
    starts = np.array([v for _, v in keys], dtype=np.int64)
    ids = np.array(sorted(nodes), dtype=np.int64)
    out: Reached = {}
    for u, pos in zip(ids.tolist(), (np.searchsorted(starts, ids, side="right") - 1).tolist(),
                      strict=True):
        key, first = keys[pos]
        out.setdefault(key, set()).add(u - first + 1)
    return out


def _mask(cover: RasterCover, joined: RasterGraph, reached: Reached,
          should_stop: Callable[[], bool] | None) -> np.ndarray:
    """The cells of the reached pieces (any bin, any grasp)."""
    per_layer: dict[tuple[int, int], set[int]] = {}
    for (b, k), labels in reached.items():
        per_layer.setdefault(joined.layer(b, k), set()).update(labels)
    mask = np.zeros(cover.raster.shape, dtype=bool)
    for lay, labels in per_layer.items():
        if should_stop is not None and should_stop():
            raise Interrupted("the turning place")
        lab = cover.layers[lay][0]
        mask |= np.isin(lab, np.fromiter(labels, dtype=np.int32)) & (lab > 0)
    return mask


def _meeting_cell(a: np.ndarray, b: np.ndarray) -> tuple[tuple[int, int], int]:
    """The middle cell of the largest overlap of masks ``a`` and ``b``, and a reach of 0.

    Without overlap: the cell halfway between their nearest cells, and the cells from it to
    them.
    """
    both = a & b
    if both.any():
        labels, count = ndimage.label(both, structure=_EIGHT)
        big = 1 + int(np.argmax(ndimage.sum(both, labels, index=np.arange(1, count + 1))))
        ii, jj = np.nonzero(labels == big)
        k = int(np.argmin((ii - ii.mean()) ** 2 + (jj - jj.mean()) ** 2))
        return (int(ii[k]), int(jj[k])), 0
    dist, (ni, nj) = ndimage.distance_transform_edt(~b, return_indices=True)
    d = np.where(a, dist, np.inf)
    i, j = np.unravel_index(int(np.argmin(d)), d.shape)
    gi, gj = int(ni[i, j]), int(nj[i, j])
    return ((int(i) + gi) // 2, (int(j) + gj) // 2), int(np.ceil(0.5 * float(d[i, j]))) + 1


def _bins_near(cover: RasterCover, joined: RasterGraph, reached: Reached,
               cell: tuple[int, int], rad: int) -> list[int]:
    """The bins of the reached pieces with a cell within ``rad`` cells of ``cell``."""
    i, j = cell
    nx, ny = cover.raster.shape
    win = (slice(max(0, i - rad), min(nx, i + rad + 1)),
           slice(max(0, j - rad), min(ny, j + rad + 1)))
    out = set()
    for (b, k), labels in reached.items():
        lab = cover.layers[joined.layer(b, k)][0][win]
        if np.isin(lab, np.fromiter(labels, dtype=np.int32)).any():
            out.add(b)
    return sorted(out)

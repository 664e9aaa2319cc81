"""A lower bound on the length of the box's route: the shortest path through its free cover.

Every configuration a valid plan passes through has its box centre in the projection ``P`` of
the :class:`~pivot_ompl.analysis.regrasp_bound.FreeCover` (the union, over yaw bins and grasps,
of the positions where the held assembly may be free): ``P`` over-approximates the free
positions, so the shortest path from the start's centre to the goal's inside ``P`` is at most
the length of any plan's box route (regrasps cost nothing here). It is measured on a raster of
cells of side ``cell`` that meet ``P`` (:class:`~pivot_ompl.analysis.raster.FloorRaster`: no
passage is lost however narrow), with moves to the 16 neighbours (one or two cells away,
straight, diagonal or a knight's move) from cell centre to cell centre. Grid paths stay
within 2.7 % of the continuous one plus one cell's diagonal at each end; the result is
reduced by both (:data:`GRID_SLACK`), so it stays a lower bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose

#: Cells at most on the raster (a larger floor gets larger cells).
MAX_CELLS = 400_000
#: Estimated seconds per graph edge of the route's graph search (building the graph and
#: Dijkstra, one call that cannot be stopped): about three times what a 2-core machine takes.
SECONDS_PER_EDGE = 1.5e-7
#: Smallest cell side (m).
MIN_CELL = 0.05
#: Relative excess of a 16-neighbour grid path over the straight line (1 / cos(pi / 16) - 1,
#: at most, for the worst direction between two neighbour directions).
GRID_SLACK = 1.0 / math.cos(math.pi / 16) - 1.0

_MOVES = ((1, 0), (0, 1), (1, 1), (1, -1), (1, 2), (2, 1), (1, -2), (2, -1))


def shortest_route(free: list, bounds: tuple[float, float, float, float], start: Pose,
                   goal: Pose, *, should_stop: Callable[[], bool] | None = None
                   ) -> float | None:
    """Lower bound (m) on the box centre's route from ``start`` to ``goal`` through ``free``.

    Args:
        free: the cover's pieces (shapely polygons) of every bin and grasp.
        bounds: the floor ``(xmin, ymin, xmax, ymax)``.
        start: the box's start pose.
        goal: the box's goal pose.

        should_stop: polled between the steps (the union, the raster, the graph).

    Returns:
        The bound, or ``None`` when the raster joins no path (start or goal outside ``P``).

    Raises:
        Interrupted: ``should_stop()`` said stop.
    """

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the route bound")

    raster = FloorRaster(bounds, min_cell=MIN_CELL, max_cells=MAX_CELLS)
    poll()
    union = shapely.union_all(free)
    poll()
    return route_on(raster, raster.meeting(union), start, goal, poll=poll)


def route_on(raster: FloorRaster, mask: np.ndarray, start: Pose, goal: Pose, *,
             poll: Callable[[], None] = lambda: None,
             time_left: Callable[[], float] | None = None) -> float | None:
    """Lower bound (m) on a route from ``start`` to ``goal`` through the cells of ``mask``.

    ``mask``: every cell a route's points may lie in (cells that meet the free region, or
    more), over ``raster``. ``None`` when the cells join no path. ``poll`` may raise to stop
    (it is called between the steps); ``time_left()``, the seconds left, if known: the graph
    search (one call that cannot be stopped) is not started when its estimate
    (:data:`SECONDS_PER_EDGE` a graph edge) exceeds them.

    Raises:
        Interrupted: stopped by ``poll``, or too little time left for the graph search.
    """
    cell, (nx, ny) = raster.cell, raster.shape
    poll()
    ends = []
    for p in (start, goal):
        i, j = raster.index(p[0], p[1])
        if not mask[i, j]:
            return None
        ends.append(i * ny + j)
    r, c, steps = neighbour_edges(mask, poll=poll)
    w = cell * steps
    if time_left is not None and SECONDS_PER_EDGE * len(r) > time_left():
        raise Interrupted(f"the route bound (its graph search of {len(r)} edges would take "
                          f"about {SECONDS_PER_EDGE * len(r):.2f} s)")
    graph = coo_matrix((w, (r, c)), shape=(nx * ny, nx * ny)).tocsr()
    poll()
    d = float(dijkstra(graph, directed=False, indices=ends[0])[ends[1]])
    if not math.isfinite(d):
        return None
    return grid_bound(d, cell)


def grid_bound(length: float, cell: float) -> float:
    """A lower bound (m) on a continuous route whose raster path is ``length`` m at best.

    Less the grid's excess (:data:`GRID_SLACK`) and a cell's diagonal at each end.
    """
    return max(0.0, length / (1.0 + GRID_SLACK) - 2.0 * cell * math.sqrt(2.0))


def neighbour_edges(mask: np.ndarray, *, poll: Callable[[], None] = lambda: None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The raster graph's edges between the cells of ``mask``: ``(rows, cols, steps)``.

    Flat cell indices of both ends (``i * ny + j``) and each move's length in cells, for the
    16 neighbours (a knight's move only where both cells it passes are in ``mask`` too).
    ``poll`` is called between the moves (it may raise to stop).
    """
    nx, ny = mask.shape
    index = np.arange(nx * ny).reshape(nx, ny)
    rows, cols, steps = [], [], []
    for di, dj in _MOVES:
        src = (slice(max(0, -di), nx - max(0, di)), slice(max(0, -dj), ny - max(0, dj)))
        both = mask[src] & _seen(mask, src, di, dj)
        if abs(di) == 2:  # a knight's move also needs both cells it passes
            both &= _seen(mask, src, di // 2, 0) & _seen(mask, src, di // 2, dj)
        elif abs(dj) == 2:
            both &= _seen(mask, src, 0, dj // 2) & _seen(mask, src, di, dj // 2)
        poll()
        ia = index[src][both]
        rows.append(ia)
        cols.append(ia + di * ny + dj)
        steps.append(np.full(ia.shape, math.hypot(di, dj)))
    return np.concatenate(rows), np.concatenate(cols), np.concatenate(steps)


def _seen(mask: np.ndarray, src: tuple[slice, slice], di: int, dj: int) -> np.ndarray:
    """``mask`` at the cells ``(di, dj)`` away from those of the block ``src``."""
    a, b = src
    return mask[a.start + di:a.stop + di, b.start + dj:b.stop + dj]

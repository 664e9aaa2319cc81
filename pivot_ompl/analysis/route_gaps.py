"""The route bound with the passages no held pose fits closed, round by round along its path.

The disk relaxation's cells (:func:`~pivot_ompl.analysis.plan_bounds.disk_cells`) hold every
box centre of every plan, but they keep only the box's inscribed disk off the walls: a gap
the disk passes and the held assembly (box and robot) never does stays open, and the
shortest route through it is shorter than any plan's. The box moves only while it is held
(a regrasp leaves it where it was held), so every point of any plan's box route is the
centre of a held pose; a cell proven to hold no such centre
(:class:`~pivot_ompl.analysis.held_cells.HeldCells`, conservative at every yaw and grasp)
holds no point of any route and can be removed: the shortest path through the cells left
(:func:`~pivot_ompl.analysis.route_bound.route_on`'s graph and grid slack) is still a lower
bound, and at least the disk's.

Testing every cell of a floor would cost too much; only the path's cells matter.
:func:`gap_closed_route` works in rounds: the shortest path through the cells kept; its
cells not tested yet are tested, but for those surely open (farther from every cell outside
the disk cells than any held body reaches, plus the clearance and a cell: every yaw fits
there); from each cell closed, its untested neighbours are tested in turn (a flood through
the closed cells, so a gap closes across its whole width in one round); the closed cells are
removed and the next round starts. The rounds end when a path passes only cells tested open
or surely open (``complete``), at the budgets (:data:`MAX_ROUNDS`, :data:`MAX_TESTS`), when
the next graph search's estimate exceeds the time left, or when stopped: each round's path
is a proof, and the last one found is the bound.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.analysis.held_cells import HeldCells
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import SECONDS_PER_EDGE, grid_bound, neighbour_edges
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

__all__ = ["MAX_ROUNDS", "MAX_TESTS", "GapRoute", "gap_closed_route"]

log = logging.getLogger(__name__)

#: Most rounds (graph searches) of one bound.
MAX_ROUNDS = 40
#: Most cells tested by one bound (about a millisecond each where a gap is tested).
MAX_TESTS = 4000
#: How far (m, along either axis) from the round's path the flood tests cells: about half
#: the widest gap the disk passes and the held assembly does not (wider gaps close over
#: several rounds).
FLOOD_REACH = 0.6

_UNTESTED, _OPEN, _CLOSED = 0, 1, 2


@dataclass(frozen=True)
class GapRoute:
    """Outcome of :func:`gap_closed_route`.

    Attributes:
        route: lower bound (m) on any plan's box route (the last round's path, reduced by
            the grid's slack); ``None`` when the cells join no path from the start.
        plain: the same through the disk cells alone (the first round's).
        closed: cells proven to hold no held pose's centre.
        tested: cells tested.
        rounds: graph searches made.
        complete: the last path passes only cells tested or surely open (``False``: a budget,
            the time or the stop ended the rounds first; ``route`` is still a bound).
        seconds: wall-clock time (s).
        stopped: the stop or the time left ended the rounds (a budget did not).
    """

    route: float | None
    plain: float | None
    closed: int
    tested: int
    rounds: int
    complete: bool
    seconds: float
    stopped: bool = False


def gap_closed_route(scene: Scene, raster: FloorRaster, mask: np.ndarray, *,
                     start: Pose | None = None, goal: Pose | None = None,
                     tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                     max_rounds: int = MAX_ROUNDS, max_tests: int = MAX_TESTS,
                     should_stop: Callable[[], bool] | None = None,
                     time_left: Callable[[], float] | None = None) -> GapRoute:
    """The route bound through ``mask`` with the cells no held pose fits closed (module doc).

    Args:
        scene: the scene (its bodies, obstacles and bounds; its start and goal by default).
        raster: the cells.
        mask: cells holding every box centre of every plan (the disk relaxation's).
        start: the box's start pose (default the scene's).
        goal: the box's goal pose (default the scene's).
        tolerance: the swept checks' tolerance (m).
        clearance: distance (m) the checkers keep every body from the obstacles.
        max_rounds: most graph searches.
        max_tests: most cells tested.
        should_stop: polled between the rounds and inside the cells' tests.
        time_left: seconds left, if known: a graph search whose estimate
            (:data:`~pivot_ompl.analysis.route_bound.SECONDS_PER_EDGE` an edge) exceeds them
            is not started.

    Raises:
        Interrupted: stopped (or too little time) before the first path was found.
    """
    t0 = time.perf_counter()
    start = scene.start if start is None else start
    goal = scene.goal if goal is None else goal
    nx, ny = raster.shape
    ends = [raster.index(p[0], p[1]) for p in (start, goal)]
    flat_ends = [i * ny + j for i, j in ends]

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the gap-closed route bound")

    poll()
    if not all(mask[i, j] for i, j in ends):
        return GapRoute(None, None, 0, 0, 0, True, time.perf_counter() - t0)
    kept = mask.copy()  # the cells not closed
    status = np.zeros(nx * ny, dtype=np.int8)
    status[flat_ends] = _OPEN  # valid poses: never closed
    room = ndimage.distance_transform_edt(mask) * raster.cell
    test: HeldCells | None = None
    best: float | None = None
    plain: float | None = None
    closed = tested = rounds = 0
    complete = stopped = False
    while rounds < max_rounds:
        try:
            length, chain = _path(raster, kept, flat_ends[0], flat_ends[1], poll, time_left)
        except Interrupted:
            if rounds == 0:
                raise
            stopped = True
            break
        rounds += 1
        if chain is None:  # only a failed proof could cut every way: keep the last bound
            log.warning("the gap-closed route bound found no path after %d rounds", rounds)
            break
        found = grid_bound(length, raster.cell)
        best = found if best is None else max(best, found)
        plain = best if plain is None else plain
        if test is None:
            test = HeldCells(scene, tolerance=tolerance, clearance=clearance)
            sure = room.ravel() >= test.reach + clearance + raster.half_diag + raster.cell
            status[sure & (status == _UNTESTED)] = _OPEN
        todo = chain[status[chain] == _UNTESTED]
        if not len(todo):
            complete = True
            break
        near = _near(raster, chain, FLOOD_REACH) & mask
        try:
            new, spent = _flood(test, raster, near, status, todo, max_tests - tested, poll)
        except Interrupted:
            stopped = True
            break
        tested += spent
        if not new:  # the path passes open cells only, unless the budget cut the tests
            complete = not (status[chain] == _UNTESTED).any()
            break
        closed += new
        kept &= (status != _CLOSED).reshape(kept.shape)
    seconds = time.perf_counter() - t0
    log.debug("gap-closed route %s m (disk %s m): %d cells closed of %d tested, %d rounds, "
              "%.2f s", best, plain, closed, tested, rounds, seconds)
    return GapRoute(best, plain, closed, tested, rounds, complete, seconds, stopped)


def _near(raster: FloorRaster, chain: np.ndarray, reach: float) -> np.ndarray:
    """The cells at most ``reach`` m (along either axis) from a cell of ``chain``."""
    nx, ny = raster.shape
    r = max(1, math.ceil(reach / raster.cell))
    i, j = np.divmod(chain, ny)
    i0, i1 = max(0, int(i.min()) - r), min(nx, int(i.max()) + r + 1)
    j0, j1 = max(0, int(j.min()) - r), min(ny, int(j.max()) + r + 1)
    out = np.zeros((nx, ny), dtype=bool)
    seed = np.zeros((i1 - i0, j1 - j0), dtype=bool)
    seed[i - i0, j - j0] = True
    out[i0:i1, j0:j1] = ndimage.maximum_filter(seed, size=2 * r + 1, mode="constant")
    return out


def _flood(test: HeldCells, raster: FloorRaster, mask: np.ndarray, status: np.ndarray,
           todo: np.ndarray, budget: int, poll: Callable[[], None]) -> tuple[int, int]:
    """Test the cells ``todo``, then the untested neighbours in ``mask`` of every cell closed.

    Marks ``status`` (flat); ``(cells closed, cells tested)``, at most ``budget`` tested.
    """
    nx, ny = raster.shape
    flat_mask = mask.ravel()
    closed = spent = 0
    while len(todo) and spent < budget:
        todo = todo[:budget - spent]
        shut = test.closed(raster.gx.ravel()[todo], raster.gy.ravel()[todo], 0.5 * raster.cell,
                           should_stop=lambda: _polled(poll))
        spent += len(todo)
        status[todo] = np.where(shut, _CLOSED, _OPEN)
        closed += int(shut.sum())
        i, j = np.divmod(todo[shut], ny)
        near = [(i + di) * ny + (j + dj) for di in (-1, 0, 1) for dj in (-1, 0, 1)
                if (di, dj) != (0, 0)]
        ok = [((i + di >= 0) & (i + di < nx) & (j + dj >= 0) & (j + dj < ny))
              for di in (-1, 0, 1) for dj in (-1, 0, 1) if (di, dj) != (0, 0)]
        cand = np.unique(np.concatenate([c[o] for c, o in zip(near, ok, strict=True)])
                         if near else np.zeros(0, dtype=np.int64))
        todo = cand[flat_mask[cand] & (status[cand] == _UNTESTED)]
    return closed, spent


def _polled(poll: Callable[[], None]) -> bool:
    """``poll`` as a stop condition (it raises to stop)."""
    poll()
    return False


def _path(raster: FloorRaster, mask: np.ndarray, a: int, b: int, poll: Callable[[], None],
          time_left: Callable[[], float] | None) -> tuple[float, np.ndarray | None]:
    """A shortest path between the flat cells ``a`` and ``b`` through ``mask``.

    Its length on the raster graph (m) and its flat cells (``None``: no path). The graph is
    :func:`~pivot_ompl.analysis.route_bound.route_on`'s (a knight's move only where both
    cells it passes are in ``mask``), made again each round: a round's cost is one
    :func:`~pivot_ompl.analysis.route_bound.route_on`.

    Raises:
        Interrupted: ``poll`` stopped it, or the search's estimate exceeds ``time_left()`` (s).
    """
    rows, cols, steps = neighbour_edges(mask, poll=poll)
    estimate = SECONDS_PER_EDGE * len(rows)
    if time_left is not None and estimate > time_left():
        raise Interrupted("the gap-closed route bound (its graph search would take about "
                          f"{estimate:.2f} s)")
    n = mask.size
    graph = coo_matrix((raster.cell * steps, (rows, cols)), shape=(n, n)).tocsr()
    poll()
    dist, pred = dijkstra(graph, directed=False, indices=a, return_predecessors=True)
    length = float(dist[b])
    if not math.isfinite(length):
        return length, None
    chain = [b]
    while chain[-1] != a:
        chain.append(int(pred[chain[-1]]))
    return length, np.array(chain[::-1], dtype=np.int64)

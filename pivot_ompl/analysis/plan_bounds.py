"""The lower bounds a plan's quality block carries, computed only as exactly as the plan needs.

A plan's ``regrasps_lower_bound`` and ``shortest_route`` (:func:`pivot_ompl.api.plan`) are
proofs: every plan of the scene needs at least that many regrasps and moves its box at least
that far. The full relaxation (:mod:`~pivot_ompl.analysis.regrasp_bound`) gives both but is
slow on large floors; :func:`plan_bounds` asks it only where the answer depends on it:

* a plan without regrasps: no plan needs fewer than 0, whatever the relaxation says (it
  says 0: this plan exists), so the regrasp bound is 0 at once; the route bound is then the
  *disk relaxation*'s (:func:`disk_route`), or the full bound's where that is known and
  longer;
* a plan with regrasps: the relaxation coarse to fine
  (:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound`): its raster cover first
  (about a second on a 2000-box map), the exact polygons only when the raster's bound is
  below the plan's regrasps and they are estimated to fit in 2.5 seconds (small scenes);
  with ``guided``, on larger floors, while the raster's bound is below the plan's regrasps,
  the raster refined where its best path passes narrow places
  (:mod:`~pivot_ompl.analysis.guided_refine`) when, by estimate, it ends within the time
  left of the bound's share (``time_left``; ``should_stop`` still polled: the rounds done
  stand, each a proof). ``plan`` asks for it by default for a plan with regrasps, with
  the time its limit leaves (``prove=None``; ``prove=True``: whatever the estimate, stopped
  at the limit; ``prove=False``: never): where it reaches the plan's count it costs a few
  seconds (the Willow Garage office: about 5 s for its 2). Where the held poses' count
  (:mod:`~pivot_ompl.analysis.pose_regrasps`) is estimated cheap (a floor of few boxes:
  rooms joined by a tight corridor) it runs instead (:func:`~pivot_ompl.analysis.
  bound_levels.may_pose`): the refinement proved 0 there, the count proves 2. Either way
  once per scene: a scene's bound once refined (by a plan or ``pivot-ompl bound
  --guided``) is read from the cache by every later plan.
* a plan with regrasps whose box route is over 1.3 times its route bound: the layered
  route on finer cells where the time left allows (:mod:`~pivot_ompl.analysis.route_refine`).

Every result comes from the bound cache when it holds it
(:mod:`~pivot_ompl.analysis.bound_cache`).

**The disk relaxation.** At any yaw the box's footprint holds the disk of radius ``b / 2``
(``b``: its short side) round its centre, and every body is kept ``clearance`` from the
obstacles but for the swept checks' tolerance: so in every configuration of any plan the
box's centre is at least ``b / 2 + clearance - tolerance`` from every obstacle piece (subsets
of the obstacles) and ``b / 2 - tolerance`` inside the bounds. The raster cells
(:class:`~pivot_ompl.analysis.raster.FloorRaster`) whose centres are within half a cell
diagonal of such positions hold every box centre of every plan; the cells kept are those
whose centre is that much less far from the pieces (no polygon is grown: a rectangle's
distance by arithmetic, axis-aligned or turned,
:func:`~pivot_ompl.analysis.rect_cells.near_rectangles` and
:func:`~pivot_ompl.analysis.rect_cells.near_turned_rectangles`, an STRtree query for other
pieces and within round-off of the distance), a superset. The
shortest path through them (:func:`~pivot_ompl.analysis.route_bound.route_on`), and the
straight line from start to goal, are lower bounds of every plan's box route, however the
held assembly turns. Cells no held pose of the box fits (the disk passes, the held assembly
does not) are then closed along that path
(:func:`~pivot_ompl.analysis.route_gaps.gap_closed_route`): still a lower bound, and the one
every plan carries (the larger of it and the full relaxation's route, once per scene in the
process).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable

import numpy as np
import shapely

from pivot_ompl.analysis.bound_cache import (
    cached_bound,
    forget,
    lower_bound,
    refuted_by,
    route_problem,
)
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.rect_cells import (
    axis_rectangles,
    near_rectangles,
    near_turned_rectangles,
    turned_rectangles,
)
from pivot_ompl.analysis.regrasp_bound import RegraspBound
from pivot_ompl.analysis.relaxation_handoff import forget_kept
from pivot_ompl.analysis.route_bound import MAX_CELLS, MIN_CELL, route_on
from pivot_ompl.analysis.route_cache import forget_route, keep_route, kept_route
from pivot_ompl.analysis.route_gaps import GapRoute, gap_closed_route
from pivot_ompl.analysis.route_refine import finer_route
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import keep_shared, shared_value
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces, piece_bounds, piece_polygons

log = logging.getLogger(__name__)

#: What :func:`~pivot_ompl.scene.shared.keep_shared` keeps a scene's disk route under (m,
#: run to its end: one per scene in the process, a later plan's is it).
DISK_ROUTE = ("disk route",)

#: Added to the disk relaxation's erosions (m): keeps it on the safe side of round-off.
ROUND_OFF = 1e-7
#: Raster cells per STRtree query of the disk relaxation (the stop polled between them).
QUERY_CHUNK = 32_768


def disk_route(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
               tolerance: float = SWEEP_TOLERANCE,
               should_stop: Callable[[], bool] | None = None,
               time_left: Callable[[], float] | None = None, gaps: bool = True
               ) -> float | None:
    """Lower bound (m) on any plan's box route by the disk relaxation (module docstring).

    ``gaps``: with the cells no held pose fits closed along the route
    (:func:`~pivot_ompl.analysis.route_gaps.gap_closed_route`; stopped partway, the rounds
    done stand). ``None`` when stopped by ``should_stop`` before a first route or when the
    relaxation joins no path; also when ``time_left()`` (seconds, if known) is less than the
    graph search's estimate (:func:`~pivot_ompl.analysis.route_bound.route_on`).
    """
    found = held_route(scene, clearance=clearance, tolerance=tolerance,
                       should_stop=should_stop, time_left=time_left, gaps=gaps)
    return None if found is None else found.route


def held_route(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
               tolerance: float = SWEEP_TOLERANCE,
               should_stop: Callable[[], bool] | None = None,
               time_left: Callable[[], float] | None = None, gaps: bool = True
               ) -> GapRoute | None:
    """:func:`disk_route` with how it was found (its ``route`` never below the straight line).

    ``None`` when stopped (or out of time) before a first route.
    """
    t0 = time.perf_counter()
    cells = disk_cells(scene, clearance=clearance, tolerance=tolerance,
                       should_stop=should_stop)
    if cells is None:
        return None
    raster, mask = cells
    try:
        if gaps:
            found = gap_closed_route(scene, raster, mask, tolerance=tolerance,
                                     clearance=clearance, should_stop=should_stop,
                                     time_left=time_left)
        else:
            route = route_on(raster, mask, scene.start, scene.goal,
                             poll=_poller(should_stop), time_left=time_left)
            found = GapRoute(route, route, 0, 0, 1, True, 0.0)
    except Interrupted:
        return None
    # no route is shorter than the straight line either
    line = math.dist(scene.start[:2], scene.goal[:2])
    return dataclasses.replace(
        found, route=None if found.route is None else max(found.route, line),
        plain=None if found.plain is None else max(found.plain, line),
        seconds=time.perf_counter() - t0)


def disk_cells(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
               tolerance: float = SWEEP_TOLERANCE,
               should_stop: Callable[[], bool] | None = None,
               max_cells: int = MAX_CELLS) -> tuple[FloorRaster, np.ndarray] | None:
    """The disk relaxation's raster and cells (module docstring); ``None`` when stopped.

    Every box centre of every plan lies in a cell of the mask; ``max_cells``: the raster's
    most cells (fewer: larger cells, still a superset).
    """
    if should_stop is not None and should_stop():
        return None
    half = 0.5 * min(scene.model.object_size[0], scene.model.object_size[1])
    x0, y0, x1, y1 = scene.bounds
    raster = FloorRaster(scene.bounds, min_cell=MIN_CELL, max_cells=max_cells)
    # a cell meets the free region if its centre is within half a diagonal of it: it is
    # then at least ``grow - half_diag`` from every piece and within the shrunk bounds
    # grown by half a diagonal (keeping every such cell keeps more: still a lower bound)
    inner = half - tolerance - ROUND_OFF - raster.half_diag
    gx, gy = raster.gx, raster.gy
    mask = (gx >= x0 + inner) & (gx <= x1 - inner) & (gy >= y0 + inner) & (gy <= y1 - inner)
    grow = half + clearance - tolerance - ROUND_OFF - raster.half_diag
    raw = obstacle_pieces(scene.obstacles)
    pieces = piece_polygons(raw)
    if should_stop is not None and should_stop():
        return None
    if len(pieces) and grow > 0:
        # a cell far from every piece's box is far from every piece: only the others are
        # queried (a fifth to two fifths of a building's floor)
        boxes = piece_bounds(raw)
        idx = np.flatnonzero((mask & near_boxes(raster, boxes, grow)).ravel())
        flat = mask.ravel()
        # a map's pieces are axis-aligned rectangles: their distances by arithmetic, GEOS
        # asked only within round-off of ``grow`` (and for cells near other pieces)
        rect = axis_rectangles(raw)
        surely, maybe = near_rectangles(raster, boxes[rect], idx, grow)
        turned = turned_rectangles(raw) & ~rect  # a turned map's: in their own axes
        if turned.any():
            corners = np.array([raw[n] for n in np.flatnonzero(turned)], dtype=float)
            more, also = near_turned_rectangles(raster, corners, idx, grow)
            surely, maybe = surely | more, maybe | also
        flat[idx[surely]] = False
        idx = idx[maybe & ~surely] if (rect | turned).all() else idx[~surely]
        tree = shapely.STRtree(pieces) if len(idx) else None
        for a in range(0, len(idx), QUERY_CHUNK):  # the stop polled between the chunks
            if should_stop is not None and should_stop():
                return None
            part = idx[a:a + QUERY_CHUNK]
            points = shapely.points(gx.ravel()[part], gy.ravel()[part])
            near = tree.query(points, predicate="dwithin",  # type: ignore[union-attr]
                              distance=grow)[0]
            flat[part[near]] = False
        mask = flat.reshape(mask.shape)
    if should_stop is not None and should_stop():
        return None
    return raster, mask


def near_boxes(raster: FloorRaster, boxes: np.ndarray, distance: float) -> np.ndarray:
    """The cells whose centre may lie within ``distance`` of one of the ``boxes``.

    ``boxes``: ``(n, 4)`` bounding boxes ``x0, y0, x1, y1``. A boolean ``raster.shape``
    array holding every cell whose centre lies within ``distance`` of a box along both axes
    (and one more cell each way, against round-off): a superset of the cells within
    ``distance`` of anything inside the boxes.
    """
    nx, ny = raster.shape
    xs, ys = raster.gx[:, 0], raster.gy[0, :]
    i0 = np.clip(np.searchsorted(xs, boxes[:, 0] - distance, side="left") - 1, 0, nx)
    i1 = np.clip(np.searchsorted(xs, boxes[:, 2] + distance, side="right") + 1, 0, nx)
    j0 = np.clip(np.searchsorted(ys, boxes[:, 1] - distance, side="left") - 1, 0, ny)
    j1 = np.clip(np.searchsorted(ys, boxes[:, 3] + distance, side="right") + 1, 0, ny)
    marks = np.zeros((nx + 1, ny + 1), dtype=np.int64)  # each box's block, summed up
    for di, dj, sign in ((i0, j0, 1), (i1, j0, -1), (i0, j1, -1), (i1, j1, 1)):
        np.add.at(marks, (di, dj), sign)
    return np.cumsum(np.cumsum(marks, axis=0), axis=1)[:nx, :ny] > 0


def _poller(should_stop: Callable[[], bool] | None) -> Callable[[], None]:
    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the disk route bound")
    return poll


def plan_bounds(scene: Scene, regrasps: int, *, route_length: float | None = None,
                should_stop: Callable[[], bool] | None = None,
                time_left: Callable[[], float] | None = None, guided: bool = False,
                guided_by_estimate: bool = True, places: tuple[tuple[float, float], ...] = ()
                ) -> tuple[int | None, float | None]:
    """``(regrasps_lower_bound, shortest_route)`` for a plan of ``scene`` with ``regrasps``.

    Each ``None`` when not proven before ``should_stop`` said stop, or (the disk route)
    when ``time_left()`` s are too few for its graph search (module docstring). A
    relaxation's bound that the plan itself refutes (more regrasps than ``regrasps``, a
    route longer than ``route_length`` m, or "no plan") is dropped from the caches and not
    given: a relaxation of every plan cannot lie above a valid one. ``guided``: refine the
    raster where its best path cheats when that fits ``time_left()`` (module docstring);
    ``guided_by_estimate`` ``False``: whenever the bound is still wanted, stopped by
    ``should_stop`` (its rounds done stand). ``places``: where the plan regrasps (m), refined
    first by the guided refinement (cost only).
    """
    known = cached_bound(scene)
    if known is not None and known.solvable:
        if not _refuted(known, scene, regrasps, route_length) and (
                regrasps == 0 or known.exhaustive or (known.regrasps or 0) >= regrasps):
            forget_kept(scene)  # the late proof's relaxations: not needed
            return known.regrasps, _finer(scene, regrasps, _longer(
                known.shortest_route, _shared_held_route(
                    scene, route_length, should_stop, time_left)),
                route_length, should_stop, time_left)
    if regrasps == 0:  # the disk route: one per scene in the process (a later plan's is it)
        forget_kept(scene)
        return 0, _shared_held_route(scene, route_length, should_stop, time_left)
    full = lower_bound(scene, target=regrasps, should_stop=should_stop,
                       guided_seconds=0.0 if not guided else
                       math.inf if time_left is None or not guided_by_estimate
                       else time_left(), places=places)
    if full.solvable is None or _refuted(full, scene, regrasps, route_length):
        return None, None
    return full.regrasps, _finer(scene, regrasps, _longer(
        full.shortest_route, _shared_held_route(scene, route_length, should_stop, time_left)),
        route_length, should_stop, time_left)


def route_bound(scene: Scene, *, should_stop: Callable[[], bool] | None = None,
                use_cache: bool = True) -> float | None:
    """The disk route with its gaps closed, as a plan's ``shortest_route`` takes it (m).

    Read from and kept in the caches (``use_cache`` ``False``: computed afresh, nothing
    kept); ``None`` when stopped before a first route or when no path joins start and goal.
    """
    if not use_cache:
        return disk_route(scene, should_stop=should_stop)
    return _shared_held_route(scene, None, should_stop, None)


def keep_route_bound(scene: Scene, route: float) -> bool:
    """Keep ``route`` (m), :func:`route_bound` computed by another process, for ``scene``'s plans.

    Kept where it is a possible route bound of ``scene``
    (:func:`~pivot_ompl.analysis.bound_cache.route_problem`); whether kept.
    """
    if route_problem(route, scene, name="route") is not None:
        return False
    keep_shared(scene, DISK_ROUTE, route)
    return True


def _shared_held_route(scene: Scene, route_length: float | None,
                       should_stop: Callable[[], bool] | None,
                       time_left: Callable[[], float] | None) -> float | None:
    """The disk route with its gaps closed (:func:`held_route`), once per scene.

    Once per process, and kept on disk for later ones (:mod:`~pivot_ompl.analysis.route_cache`).
    ``None`` when stopped before a first route, and (with a warning) when the plan's
    ``route_length`` refutes it.
    """
    route = shared_value(scene, DISK_ROUTE)
    if route is None and (route := kept_route(scene)) is not None:  # an earlier process's
        keep_shared(scene, DISK_ROUTE, route)
    if route is None:
        found = held_route(scene, should_stop=should_stop, time_left=time_left)
        route = None if found is None else found.route
        if found is not None and route is not None and not found.stopped:
            keep_shared(scene, DISK_ROUTE, route)  # a stopped one may be weaker
            keep_route(scene, route)
    if _refutes(route_length, route):
        log.warning("route bound dropped: this plan refutes it (bound %.3f m, route %.3f m)",
                    route, route_length)
        forget_route(scene)
        return None
    return route


def _finer(scene: Scene, regrasps: int, route: float | None, route_length: float | None,
           should_stop: Callable[[], bool] | None,
           time_left: Callable[[], float] | None) -> float | None:
    """``route``, or the layered route on finer cells where that is longer.

    (:mod:`~pivot_ompl.analysis.route_refine`: only where the plan's route ratio is high.)
    A finer route the plan refutes is dropped with a warning.
    """
    finer = finer_route(scene, route, route_length=route_length, regrasps=regrasps,
                        should_stop=should_stop, time_left=time_left)
    if _refutes(route_length, finer):
        log.warning("finer route bound dropped: this plan refutes it (bound %.3f m, "
                    "route %.3f m)", finer, route_length)
        return route
    return _longer(route, finer)


def _refutes(route_length: float | None, bound: float | None) -> bool:
    """Whether a plan whose box route is ``route_length`` m refutes the route ``bound`` (m)."""
    return (bound is not None and route_length is not None
            and bound > route_length * (1.0 + 1e-9) + 1e-6)


def _longer(a: float | None, b: float | None) -> float | None:
    """The larger of two lower bounds, either unknown (``None``)."""
    known = [r for r in (a, b) if r is not None]
    return max(known) if known else None


def _refuted(bound: RegraspBound, scene: Scene, regrasps: int,
             route_length: float | None) -> bool:
    """Whether the plan refutes ``bound`` (then forgotten by the caches, with a warning)."""
    if bound.solvable is not False and route_length is None:
        return False
    if not refuted_by(bound, regrasps=regrasps, route=math.inf if route_length is None
                      else route_length):
        return False
    log.warning("regrasp bound dropped: this plan refutes it (bound %s regrasps, route %s)",
                bound.regrasps, bound.shortest_route)
    forget(scene)
    return True

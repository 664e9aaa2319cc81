"""Each transfer phase re-planned along the route bound's shortest route, kept if cheaper.

The route bound of a plan's quality block is the length of the shortest path of the box's
centre through the disk relaxation's free cells
(:func:`~pivot_ompl.analysis.plan_bounds.disk_cells`). :func:`follow_route` takes that path
itself between the two ends of every transfer phase of a path (same grasp, same regrasp
poses: :func:`~pivot_ompl.analysis.route_path.route_polyline`) and tries to follow it, two
ways: the car (the supporting edge's centre) turns in place to face the next corner of the
polyline, pushes (or pulls, its back to the way) straight to it, turns again, and at the
phase's end turns to the end pose's heading (long straight pushes at the ideal rate, few
turns: few pivots); or it passes each corner heading halfway between the corner's two
segments, the steering's arcs joining them. The shortest path hugs the walls, where the
held assembly, wider than the relaxation's disk, passes only by small rotations or not at
all: the route is also taken kept off them by each of :data:`MARGINS` (shares of the room a
turn in place needs) where there is room, and the cheapest of the variants that pass wins
(the margin chosen by the cost, per phase, not fixed to fit one scene).

A variant is estimated first (:meth:`~pivot_ompl.cost.CostModel.spin_estimate`,
:meth:`~pivot_ompl.cost.CostModel.transfer_estimate`) and checked only when the estimate is
below the phase's real seconds, cheapest estimate first: its turned poses and the cheap
test of its legs (:meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.path_free`), then
every leg in full by the same checks as every transfer, given up once the steering has
solved more pieces than the phase's seconds could pay rotations for. A phase is replaced
only when its checked seconds are lower: the result is valid, has the same ends, grasps
and regrasp poses, and is never costlier. ``should_stop`` is polled between the steps and
passed to the checks; stopped, the best path so far is returned.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.analysis.plan_bounds import disk_cells
from pivot_ompl.analysis.route_path import FreeField, route_polyline
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["MARGINS", "FollowStats", "follow_route"]

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]

#: Clearances the followed route keeps from the relaxation's walls where there is room, as
#: shares of the room a turn in place needs beyond the relaxation's disk (:func:`_excess`):
#: each gives a variant, the cost chooses (0: the bound's own shortest route).
MARGINS = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25)
#: Most raster cells of the route's field (a coarser raster than the bound's: a guide).
MAX_CELLS = 100_000
#: Most variants checked per phase.
TRIES_PER_PHASE = 4
#: Least estimated saving (s) for a variant to be checked.
MIN_SAVING = 2.0
#: Corners a variant may lose to failing legs before it is given up (:func:`_checked`).
MAX_DROPS = 4
#: Pieces the steering may solve per rotation the phase's seconds could pay for.
PIECES_PER_ROTATION = 1.0
#: Turns smaller than this (rad) are left out; corners closer than this (m) merged.
NO_TURN = 1e-6
NO_MOVE = 1e-3

_fields: dict[int, tuple[Scene, FreeField]] = {}


@dataclass
class FollowStats:
    """What :func:`follow_route` did.

    Attributes:
        phases: transfer phases looked at.
        tried: variants checked (the cheap tests or in full).
        applied: phases replaced.
        seconds_saved: cost saved (s).
    """

    phases: int = 0
    tried: int = 0
    applied: int = 0
    seconds_saved: float = 0.0


def follow_route(checker: PivotChecker, states: list[State], *, costs: CostModel,
                 should_stop: Stop, margins: tuple[float, ...] = MARGINS,
                 stats: FollowStats | None = None) -> list[State]:
    """``states`` with transfer phases re-planned along the shortest route (module docstring).

    Args:
        checker: the checks of transfers (its caches make repeats free).
        states: a valid path of ``(object pose, grasp)`` states.
        costs: the cost model a replacement must be cheaper by.
        should_stop: the termination condition (polled between steps, passed to checks).
        margins: the clearances of the variants tried, as shares of the room a turn in
            place needs beyond the relaxation's disk (the box's inscribed one).
        stats: filled with what was done, if given.

    Returns:
        A valid path with the same ends, grasps and regrasp poses, never costlier.
    """
    st = stats if stats is not None else FollowStats()
    field = _field(checker.scene, should_stop)
    if field is None:
        return list(states)
    evaluate = Evaluator(checker, costs)
    path = list(states)
    for s, e in reversed(_phases(path)):  # from the end: earlier indices stay valid
        if should_stop():
            break
        st.phases += 1
        found = _best(evaluate, field, path[s:e + 1], margins, should_stop, st)
        if found is not None:
            path[s:e + 1] = found
    if st.applied:
        log.debug("followed the shortest route in %d of %d phases (%d variants checked): "
                  "%.1f s saved", st.applied, st.phases, st.tried, st.seconds_saved)
    return path


def _field(scene: Scene, should_stop: Stop) -> FreeField | None:
    """The free field of ``scene``'s disk relaxation (kept for the last scenes asked)."""
    known = _fields.get(id(scene))
    if known is not None and known[0] is scene:
        return known[1]
    cells = disk_cells(scene, should_stop=should_stop, max_cells=MAX_CELLS)
    if cells is None or should_stop():
        return None
    field = FreeField.of(*cells)
    if len(_fields) >= 4:
        _fields.clear()
    _fields[id(scene)] = (scene, field)
    return field


def _phases(path: list[State]) -> list[tuple[int, int]]:
    """``(first, last)`` state indices of each run of one grasp with two poses or more."""
    out, s = [], 0
    for k in range(1, len(path) + 1):
        if k == len(path) or path[k][1] != path[s][1]:
            if k - 1 > s:
                out.append((s, k - 1))
            s = k
    return out


def _best(evaluate: Evaluator, field: FreeField, phase: list[State],
          margins: tuple[float, ...], should_stop: Stop, st: FollowStats
          ) -> list[State] | None:
    """The cheapest checked variant of ``phase`` if it is cheaper; else ``None``."""
    old = 0.0
    for u, v in zip(phase, phase[1:], strict=False):
        e = evaluate.step(u, v)
        if not e.valid:
            return None
        old += e.cost
    (a, g), (b, _) = phase[0], phase[-1]
    variants: dict[tuple[Pose, ...], float] = {}
    excess = _excess(evaluate.checker, g)
    for share in margins:
        m = share * excess
        if should_stop():
            return None
        try:
            poly = route_polyline(field, (a[0], a[1]), (b[0], b[1]), margin=m,
                                  poll=lambda: _poll(should_stop))
        except Interrupted:
            return None
        if poly is None:
            return None
        for back in (False, True):
            for spin in (True, False):
                poses = _poses(evaluate.checker, a, b, g, poly, back=back, spin=spin)
                if poses not in variants:
                    variants[poses] = _estimate(evaluate, poses, g)
    best, best_cost = None, old - 1e-9
    ranked = sorted(variants.items(), key=lambda kv: kv[1])
    for poses, est in ranked[:TRIES_PER_PHASE]:
        if est > best_cost - MIN_SAVING or should_stop():
            break
        st.tried += 1
        new = _checked(evaluate, poses, g, should_stop, best_cost)
        if new is not None and new[1] < best_cost:
            best, best_cost = new
    if best is None:
        return None
    st.applied += 1
    st.seconds_saved += old - best_cost
    return [(q, g) for q in best]


def _excess(checker: PivotChecker, grasp: int) -> float:
    """How much farther (m) the held assembly reaches from the car than the relaxation's disk.

    The farthest corner of the box (ahead of the car) or of the robot's footprint (behind
    it) from the car's position, less half the box's short side: the clearance a turn in
    place about the car needs beyond the disk the route bound keeps off the walls.
    """
    m = checker.model
    o: Pose = (0.0, 0.0, 0.0)
    car, robot = m.car_pose(o, grasp), m.robot_pose(o, grasp)
    ahead = 2.0 * math.hypot(car[0], car[1])  # the box's depth in front of the car
    behind = math.hypot(robot[0] - car[0], robot[1] - car[1])
    depth, width = m.robot_footprint[0], m.robot_footprint[1]
    reach = max(math.hypot(ahead, m.edge_half_length(grasp)),
                math.hypot(behind + 0.5 * depth, 0.5 * width))
    return max(0.0, reach - 0.5 * min(m.object_size[0], m.object_size[1]))


def _poll(should_stop: Stop) -> None:
    if should_stop():
        raise Interrupted("the followed route")


def _poses(checker: PivotChecker, a: Pose, b: Pose, grasp: int,
           poly: list[tuple[float, float]], *, back: bool, spin: bool) -> tuple[Pose, ...]:
    """Object poses from ``a`` to ``b`` through the corners of ``poly``.

    The car's corners are the polyline's inner points between the car's own ends; ``back``:
    the car faces away from its way (a pull). ``spin``: a turn in place at every corner and
    straight pushes between them; else one pose at each corner, heading halfway between its
    two segments', joined by the steering's arcs.
    """
    m = checker.model
    ca, cb = m.car_pose(a, grasp), m.car_pose(b, grasp)
    pts = [(ca[0], ca[1])]
    for p in [*poly[1:-1], (cb[0], cb[1])]:
        if math.hypot(p[0] - pts[-1][0], p[1] - pts[-1][1]) > NO_MOVE:
            pts.append(p)
    if len(pts) > 1 and math.hypot(cb[0] - pts[-1][0], cb[1] - pts[-1][1]) > 0:
        pts[-1] = (cb[0], cb[1])
    cars: list[Pose] = [ca]
    if not spin:
        heads = [math.atan2(q[1] - p[1], q[0] - p[0]) + (math.pi if back else 0.0)
                 for p, q in zip(pts, pts[1:], strict=False)]
        for k in range(1, len(pts) - 1):
            h = heads[k - 1] + 0.5 * wrap_angle(heads[k] - heads[k - 1])
            cars.append((pts[k][0], pts[k][1], h))
        cars.append(cb)
        return (a, *(m.object_from_car(c, grasp) for c in cars[1:-1]), b)
    for p, q in zip(pts, pts[1:], strict=False):
        h = math.atan2(q[1] - p[1], q[0] - p[0]) + (math.pi if back else 0.0)
        h = cars[-1][2] + wrap_angle(h - cars[-1][2])
        if abs(h - cars[-1][2]) > NO_TURN:
            cars.append((p[0], p[1], h))
        cars.append((q[0], q[1], h))
    if abs(wrap_angle(cb[2] - cars[-1][2])) > NO_TURN or len(cars) == 1:
        cars.append(cb)
    poses = [a, *(m.object_from_car(c, grasp) for c in cars[1:-1]), b]
    return tuple(poses)


def _estimate(evaluate: Evaluator, poses: tuple[Pose, ...], grasp: int) -> float:
    """Estimated seconds of the variant ``poses`` (spins and straight pushes)."""
    m, costs = evaluate.checker.model, evaluate.costs
    alpha, ell = evaluate.checker.scene.alpha_max, m.edge_half_length(grasp)
    total = 0.0
    for p, q in zip(poses, poses[1:], strict=False):
        u, v = m.car_pose(p, grasp), m.car_pose(q, grasp)
        d = math.hypot(v[0] - u[0], v[1] - u[1])
        total += costs.transfer_estimate(d, ell, alpha) if d > NO_MOVE else \
            costs.spin_estimate(wrap_angle(v[2] - u[2]), alpha)
    return total


def _checked(evaluate: Evaluator, poses: tuple[Pose, ...], grasp: int, should_stop: Stop,
             ceiling: float) -> tuple[tuple[Pose, ...], float] | None:
    """The variant as checked, with its seconds; ``None`` if it fails, costs more, or stopped.

    Its corner poses that collide are left out and the steering joins their neighbours;
    a leg that fails (its cheap test, then in full) loses its far corner the same way, up
    to :data:`MAX_DROPS` times. The full checks are given up once the steering has solved
    more pieces than rotations worth ``ceiling`` seconds could need (counts, not seconds: a
    seed gives the same plan on any machine).
    """
    ck = evaluate.checker
    kept = [poses[0], *(q for q in poses[1:-1] if ck.state_valid(q, grasp)), poses[-1]]
    pieces = [0]
    limit = PIECES_PER_ROTATION * ceiling / evaluate.costs.durations.per_pivot + 8

    def stop() -> bool:
        pieces[0] += 1
        return pieces[0] > limit or should_stop()

    drops, k, done = 0, 0, [0.0] * len(kept)  # done[k]: seconds of the legs before pose k
    while k < len(kept) - 1:
        if should_stop():
            return None
        p, q = kept[k], kept[k + 1]
        e = evaluate.transfer(p, q, grasp, should_stop=stop) if ck.path_free(p, q, grasp) \
            else None
        if e is not None and e.status is Status.STOPPED:
            return None
        if e is None or not e.valid:
            if drops >= MAX_DROPS or len(kept) <= 2:
                return None
            drops += 1
            if k + 1 < len(kept) - 1:
                del kept[k + 1]  # the far corner left out
            else:
                del kept[k]  # the last leg: its near corner
                k = max(0, k - 1)
            continue
        done[k + 1] = done[k] + e.cost
        if done[k + 1] >= ceiling:
            return None
        k += 1
    return tuple(kept), done[len(kept) - 1]

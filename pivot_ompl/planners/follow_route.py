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
segments, the steering's arcs joining them; each with the car's corners on the polyline's,
and with them placed so that the box's centre passes the polyline's corners
(:func:`~pivot_ompl.planners.route_poses.route_poses`: the car stands behind the box's
centre). The shortest path hugs the walls, where the
held assembly, wider than the relaxation's disk, passes only by small rotations or not at
all: the route is also taken kept off them by each of :data:`MARGINS` (shares of the room a
turn in place needs) where there is room, and the cheapest of the variants that pass wins
(the margin chosen by the cost, per phase, not fixed to fit one scene).

The variants are not taken whole: a corner where the assembly cannot turn, or a leg it
cannot push along, would refuse every one. Each margin's cheapest estimated variant
(:meth:`~pivot_ompl.cost.CostModel.spin_estimate`,
:meth:`~pivot_ompl.cost.CostModel.transfer_estimate`), if its estimate is below the phase's
real seconds and most of its corner poses are free, gives its poses; they and the phase's
own, in one order along the route, are the waypoints of the path optimiser
(:func:`~pivot_ompl.planners.optimiser.optimise_over`, the phase's grasp only), which finds
the cheapest mix (a variant's legs, the phase's own, shortcuts between them) by the same
checks as every transfer. The result is valid, has the same ends, grasps and regrasp
poses, and is never costlier. ``should_stop`` is polled between the steps and passed to the
checks; stopped, the best path so far is returned.

The field and its routes (kept per scene) are :mod:`~pivot_ompl.planners.route_field`'s;
the merge of the poses into the optimiser's waypoints is
:mod:`~pivot_ompl.planners.route_waypoints`'.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.analysis.route_path import Route
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.optimiser import optimise_over
from pivot_ompl.planners.route_field import RouteField, free_route, route_field
from pivot_ompl.planners.route_poses import (
    NO_MOVE,
    car_corner_poses,
    route_poses,
    turns_and_legs,
)
from pivot_ompl.planners.route_waypoints import merged
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["MARGINS", "FollowStats", "follow_route", "free_route"]

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]

#: Clearances the followed route keeps from the relaxation's walls where there is room, as
#: shares of the room a turn in place needs beyond the relaxation's disk (:func:`_excess`):
#: each gives a variant, the cost chooses (0: the bound's own shortest route).
MARGINS = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25)
#: Most share of a variant's corner poses that may collide for it to be offered (a route
#: whose every corner hugs a wall is not one the assembly can follow).
INVALID_SHARE = 0.3
#: Variants of turns in place and straight legs offered, the cheapest estimated first,
#: where the margins' cheapest variants gave nothing cheaper (their estimates rank the
#: arcs' straight-line legs below the turns that win once checked).
SPIN_VARIANTS = 2
#: Longest transfer between two poses that are not consecutive in their own sequence (m).
FOLLOW_REACH = 4.0
#: Least estimated saving (s) for a variant to be checked.
MIN_SAVING = 2.0




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
    field = route_field(checker, should_stop)
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


def _phases(path: list[State]) -> list[tuple[int, int]]:
    """``(first, last)`` state indices of each run of one grasp with two poses or more."""
    out, s = [], 0
    for k in range(1, len(path) + 1):
        if k == len(path) or path[k][1] != path[s][1]:
            if k - 1 > s:
                out.append((s, k - 1))
            s = k
    return out


def _best(evaluate: Evaluator, known: RouteField, phase: list[State],
          margins: tuple[float, ...], should_stop: Stop, st: FollowStats
          ) -> list[State] | None:
    """The cheapest path over the phase's and its variants' poses if cheaper; else ``None``."""
    old = evaluate.path(phase).cost
    if not math.isfinite(old):
        return None
    (a, g), (b, _) = phase[0], phase[-1]
    chosen: list[tuple[Pose, ...]] = []
    spins: list[tuple[float, tuple[Pose, ...]]] = []
    excess = _excess(evaluate.checker, g)
    guide: list[tuple[float, float]] | None = None
    first: Route | None = None
    for share in margins:  # each margin's cheapest estimated variant that mostly holds
        if should_stop():
            return None
        try:
            route = known.found((a[0], a[1]), (b[0], b[1]), first=margins[0] * excess,
                                margin=share * excess, via=first, should_stop=should_stop)
        except Interrupted:
            return None
        if route is None:
            return None
        poly = route.points
        if first is None:
            first, guide = route, poly
        ways = sorted((_estimate(evaluate, p, g), p) for p in {
            place(evaluate.checker, a, b, g, poly, back=back, spin=spin)
            for back in (False, True) for spin in (True, False)
            for place in (car_corner_poses, route_poses)})
        chosen += [p for est, p in ways if est < old - MIN_SAVING and p not in chosen
                   and _mostly_valid(evaluate.checker, p, g)][:1]
        spins += [(est, p) for est, p in ways if turns_and_legs(evaluate.checker, p, g)]
    if guide is None:
        return None
    out = _offered(evaluate, guide, phase, old, chosen, st, should_stop)
    if out is None:  # the turns in place the estimates ranked below the arcs
        more = [p for est, p in sorted(spins) if est < old - MIN_SAVING and p not in chosen
                and _mostly_valid(evaluate.checker, p, g)]
        out = _offered(evaluate, guide, phase, old, list(dict.fromkeys(more))[:SPIN_VARIANTS],
                       st, should_stop)
    return out


def _offered(evaluate: Evaluator, guide: list[tuple[float, float]], phase: list[State],
             old: float, variants: list[tuple[Pose, ...]], st: FollowStats, should_stop: Stop
             ) -> list[State] | None:
    """The cheapest path over the phase's and ``variants``' poses if cheaper; else ``None``.

    ``old``: the phase's cost (s), which the path must beat.
    """
    if not variants:
        return None
    g = phase[0][1]
    st.tried += len(variants)
    poses, path, links = merged(guide, [p for p, _ in phase], variants, g)
    out = optimise_over(evaluate.checker, poses, path, should_stop=should_stop,
                        costs=evaluate.costs, grasps=(g,), reach=FOLLOW_REACH,
                        start_grasp=g, end_grasp=g, links=links)
    new = evaluate.path(out).cost
    if not new < old - 1e-9:
        return None
    st.applied += 1
    st.seconds_saved += old - new
    return out


def _mostly_valid(checker: PivotChecker, poses: tuple[Pose, ...], grasp: int) -> bool:
    """Whether at most :data:`INVALID_SHARE` of the variant's corner poses collide."""
    bad = sum(not checker.state_valid(q, grasp) for q in poses[1:-1])
    return bad <= INVALID_SHARE * max(1, len(poses) - 2)


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

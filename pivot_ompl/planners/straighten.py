"""Detours straightened: a stretch of a phase replaced by a turn, a straight push and a turn.

The pivoting car's reference path between two poses is a Reeds-Shepp curve of the turning
radius (2 m by default): where the heading must change much over a short distance its arcs
swing wide, and a shortcut between two waypoints of a path loops out and back. The robot and
box can do better wherever there is room to turn in place: a **spin** (a turn of the car
about its own position, :class:`~pivot_ompl.pivoting.curves.CarPaths`) to face the far
pose, the straight push (or pull) to it, and a spin to its heading. That is the shortest
route between the two positions, and it takes few pivots: a straight push runs at the ideal
rate, a spin needs about one rotation per ``alpha_max`` turned.

:func:`straighten` tries this for every stretch ``i .. j`` of every transfer phase of a path
(its waypoints ``i`` and ``j`` kept, any number of waypoints between them dropped: detours
at every scale, not only between neighbours), the stretch with the most estimated saving
first (:meth:`~pivot_ompl.cost.CostModel.spin_estimate`,
:meth:`~pivot_ompl.cost.CostModel.transfer_estimate` against the stretch's real seconds);
the straight leg's cheap test (:meth:`PivotChecker.path_free`) before the full checks. A
replacement is kept only when its checked seconds are lower
(:class:`~pivot_ompl.cost.CostModel`): the result is valid, has the same ends and grasps,
and is never costlier. Stopped by ``should_stop``, it returns the best path it has.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["MIN_SAVING", "StraightenStats", "straighten"]

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]

#: Least estimated saving (s) for a stretch to be tried: below it the checks cost more
#: planning time than the plan gains.
MIN_SAVING = 2.0

#: Pieces the steering may solve per rotation the replaced stretch's seconds could pay for,
#: before a replacement is given up (:func:`_checked`).
PIECES_PER_ROTATION = 1.0

#: Turns smaller than this (rad) are left out (the straight leg starts at the pose itself).
NO_TURN = 1e-6


@dataclass
class StraightenStats:
    """What :func:`straighten` did.

    Attributes:
        tried: stretches whose replacement was checked (the cheap test or in full).
        applied: stretches replaced.
        seconds_saved: cost saved (s).
    """

    tried: int = 0
    applied: int = 0
    seconds_saved: float = 0.0


@dataclass(frozen=True)
class _Candidate:
    """A stretch ``i .. j`` (indices into the path's states) and its replacement."""

    saving: float  # estimated (s)
    i: int
    j: int
    grasp: int
    poses: tuple[Pose, ...]  # the replacement's waypoints, both ends included


def _replacements(checker: PivotChecker, costs: CostModel, a: Pose, b: Pose,
                  grasp: int) -> list[tuple[float, tuple[Pose, ...]]]:
    """Ways from object pose ``a`` to ``b`` by turns in place: ``(estimate, poses)``.

    For both directions of travel (the car facing its way, or its back to it): a turn, the
    straight push and a turn; or one of the two turns only, the other end reached by the
    Reeds-Shepp path (a small heading change costs less on the way than as a turn). Cheapest
    estimate first.
    """
    m, alpha = checker.model, checker.scene.alpha_max
    ell = m.edge_half_length(grasp)
    paths = checker.steering.paths
    ca, cb = m.car_pose(a, grasp), m.car_pose(b, grasp)
    dx, dy = cb[0] - ca[0], cb[1] - ca[1]
    d = math.hypot(dx, dy)
    if d <= 1e-6:
        return []  # a turn in place already is its own reference path

    def spin(turn: float) -> float:
        return costs.spin_estimate(turn, alpha) if abs(turn) > NO_TURN else 0.0

    def leg(u: Pose, v: Pose) -> float:
        return costs.transfer_estimate(paths.distance(u, v), ell, alpha)

    out: dict[tuple[Pose, ...], float] = {}
    for heading in (math.atan2(dy, dx), math.atan2(-dy, -dx)):
        t1, t2 = wrap_angle(heading - ca[2]), wrap_angle(cb[2] - heading)
        u, v = (ca[0], ca[1], ca[2] + t1), (cb[0], cb[1], ca[2] + t1)
        pu, pv = m.object_from_car(u, grasp), m.object_from_car(v, grasp)
        if abs(t1) > NO_TURN:  # turn, then the Reeds-Shepp path to b
            out[(a, pu, b)] = spin(t1) + leg(u, cb)
        if abs(t2) > NO_TURN:  # the Reeds-Shepp path, then the turn at b
            out[(a, pv, b)] = leg(ca, v) + spin(t2)
        poses = tuple(p for p, keep in ((a, True), (pu, abs(t1) > NO_TURN),
                                        (pv, abs(t2) > NO_TURN), (b, True)) if keep)
        out[poses] = spin(t1) + costs.transfer_estimate(d, ell, alpha) + spin(t2)
    return sorted(((e, p) for p, e in out.items()), key=lambda e: e[0])


_Ways = dict[tuple[Pose, Pose, int], list[tuple[float, tuple[Pose, ...]]]]


def _candidates(checker: PivotChecker, costs: CostModel, states: list[State],
                edge_cost: list[float], refused: set[tuple[Pose, ...]],
                ways: _Ways) -> list[_Candidate]:
    """Every stretch of every phase with its best replacement, most estimated saving first.

    ``ways``: the replacements of each pair of poses found before (asked again every round).
    """
    out: list[_Candidate] = []
    n = len(states)
    start = 0
    while start < n - 1:
        g = states[start][1]
        end = start
        while end + 1 < n and states[end + 1][1] == g:
            end += 1
        for i in range(start, end):
            run = 0.0
            for j in range(i + 1, end + 1):
                run += edge_cost[j - 1]
                key = (states[i][0], states[j][0], g)
                found = ways.get(key)
                if found is None:
                    found = ways[key] = _replacements(checker, costs, *key)
                for est, poses in found:
                    if len(poses) == 2 and j == i + 1:
                        continue  # the stretch's own transfer
                    if run - est > MIN_SAVING and poses not in refused:
                        out.append(_Candidate(run - est, i, j, g, poses))
                        break  # the cheapest untried replacement of the stretch
        start = end + 1 if end > start else start + 1
    out.sort(key=lambda c: -c.saving)
    return out


def straighten(checker: PivotChecker, states: list[State], *, costs: CostModel,
               should_stop: Stop, max_tries: int = 32,
               stats: StraightenStats | None = None) -> list[State]:
    """``states`` with stretches of its phases straightened (see the module docstring).

    Args:
        checker: the checks of transfers (its caches make repeats free).
        states: a valid path of ``(object pose, grasp)`` states.
        costs: the cost model the replacement must be cheaper by.
        should_stop: the termination condition (polled between checks, passed to them).
        max_tries: most stretches checked (the cheap test or in full).
        stats: filled with what was done, if given.

    Returns:
        A valid path with the same ends and grasps, never costlier than ``states``.
    """
    st = stats if stats is not None else StraightenStats()
    evaluate = Evaluator(checker, costs)
    path = list(states)

    def costs_of(p: list[State]) -> list[float] | None:
        out = []
        for a, b in zip(p, p[1:], strict=False):
            e = evaluate.step(a, b)
            if not e.valid:
                return None
            out.append(e.cost)
        return out

    edge_cost = costs_of(path)
    if edge_cost is None:
        return path
    refused: set[tuple[Pose, ...]] = set()
    ways: _Ways = {}
    while st.tried < max_tries and not should_stop():
        cands = _candidates(checker, costs, path, edge_cost, refused, ways)
        applied = False
        for c in cands:
            if st.tried >= max_tries or should_stop():
                break
            st.tried += 1
            refused.add(c.poses)
            old = sum(edge_cost[c.i:c.j])
            new = _checked(evaluate, c, checker, should_stop, old)
            if new is None:
                continue
            if sum(new) < old - 1e-9:
                path[c.i:c.j + 1] = [(q, c.grasp) for q in c.poses]
                edge_cost[c.i:c.j] = new
                st.applied += 1
                st.seconds_saved += old - sum(new)
                applied = True
                break
        if not applied:
            break
    if st.applied:
        log.debug("straightened %d stretches of %d tried: %.1f s saved", st.applied, st.tried,
                  st.seconds_saved)
    return path


def _checked(evaluate: Evaluator, c: _Candidate, checker: PivotChecker, should_stop: Stop,
             ceiling: float) -> list[float] | None:
    """The replacement's checked transfer costs; ``None`` if one fails, or stopped.

    The turned poses' and the legs' cheap tests first, then the legs in full, given up once
    the steering has solved more pieces than rotations worth ``ceiling`` seconds could need
    (a leg that squeezes past an obstacle by many small rotations cannot be cheaper: counts,
    not seconds, so a seed gives the same plan on any machine).
    """
    if not all(checker.state_valid(q, c.grasp) for q in c.poses[1:-1]):
        return None  # a turned pose collides
    legs = list(zip(c.poses, c.poses[1:], strict=False))
    for a, b in legs:
        if not checker.path_free(a, b, c.grasp):
            return None
    # a piece adds at least one rotation; the refinement may solve a stretch a few times
    pieces = [0]
    limit = PIECES_PER_ROTATION * ceiling / evaluate.costs.durations.per_pivot + 8

    def stop() -> bool:
        pieces[0] += 1
        return pieces[0] > limit or should_stop()

    out = []
    for a, b in legs:
        e = evaluate.transfer(a, b, c.grasp, should_stop=stop)
        if e.status is not Status.VALID:
            return None
        out.append(e.cost)
    return out

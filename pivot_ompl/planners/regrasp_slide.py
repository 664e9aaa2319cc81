"""Regrasps slid along the route: each regrasp may move to a pose of the transfers beside it.

The search places a regrasp where its sampling happened to connect two grasps: often in the
middle of a slot, where the transfer that follows still squeezes out of it by small
rotations, or short of the place where the next phase could turn freely. The path
optimiser (:func:`~pivot_ompl.planners.optimiser.optimise_over`) moves a regrasp to any
waypoint of the path where the walk is valid, but a path's waypoints are few and far apart.

:func:`slide_regrasps` offers it more: for every regrasp of the path, the box poses that the
transfer just before it and the transfer just after it pass through (their checked pivot
sequences), at the distances :data:`SLIDE_DISTANCES` from the regrasp's pose along each.
Those poses become waypoints between the path's own (in the order the path passes them), so
the optimiser may regrasp earlier (at a pose the box reached before, the next grasp from
there), later (the first grasp pushes on to a pose the box passed after) or where it was,
and shortcut from there: the cheapest mix under the planner's cost model, checked by the
same checks as every transfer and walk. The path's start, goal and grasps at both ends stay;
the result is valid and never costlier. ``should_stop`` is passed to the optimiser (polled
between edge checks); stopped, the best path found so far is returned.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.optimiser import optimise_over
from pivot_ompl.se2 import Pose

__all__ = ["SLIDE_DISTANCES", "SlideStats", "slide_regrasps"]

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]

#: Distances (m, along the box centre's pivot poses) from a regrasp's pose at which a pose of
#: the transfer before it and of the transfer after it is offered as a waypoint.
SLIDE_DISTANCES = (0.5,)
#: Longest shortcut (m) from or to an offered pose: a slid regrasp's new transfers are short
#: (the rest of the path is the later stages' to straighten), and each one checked costs.
SLIDE_REACH = 2.5


@dataclass
class SlideStats:
    """What :func:`slide_regrasps` did.

    Attributes:
        regrasps: regrasps looked at.
        offered: waypoints offered (poses of the transfers beside them).
        seconds_saved: cost saved (s).
    """

    regrasps: int = 0
    offered: int = 0
    seconds_saved: float = 0.0


def slide_regrasps(checker: PivotChecker, states: list[State], *, costs: CostModel,
                   should_stop: Stop, grasps: tuple[int, ...] = (0, 1, 2, 3),
                   reach: float = SLIDE_REACH, start_grasp: int | None = None,
                   end_grasp: int | None = None,
                   distances: tuple[float, ...] = SLIDE_DISTANCES,
                   stats: SlideStats | None = None) -> list[State]:
    """``states`` with its regrasps free to slide along the transfers beside them.

    Args:
        checker: the checks of transfers and walks (its caches make repeats free).
        states: a valid path of ``(object pose, grasp)`` states.
        costs: the cost model the result must be cheaper by.
        should_stop: the termination condition (passed to the optimiser).
        grasps: the grasps the robot may use.
        reach: the longest shortcut (m) the optimiser tries (the path's own transfers are
            kept whatever their length).
        start_grasp: the grasp the path must start with (``None``: any).
        end_grasp: the grasp the path must end with (``None``: any).
        distances: the distances (m) from each regrasp's pose of the poses offered.
        stats: filled with what was done, if given.

    Returns:
        A valid path with the same ends, never costlier than ``states`` (``states`` itself
        when there is no regrasp or nothing cheaper was found).
    """
    st = stats if stats is not None else SlideStats()
    if len(states) < 3 or should_stop():
        return list(states)
    poses: list[Pose] = []
    path: list[tuple[int, int]] = []
    for k, (pose, g) in enumerate(states):
        if k > 0 and pose == states[k - 1][0]:
            if g != states[k - 1][1]:
                st.regrasps += 1
            path.append((len(poses) - 1, g))
            continue
        if k > 0 and states[k - 1][1] == g:
            extra = _offered(checker, states, k, distances)
            st.offered += len(extra)
            poses += extra
        poses.append(pose)
        path.append((len(poses) - 1, g))
    if not st.offered:
        return list(states)
    before = _cost(checker, costs, states)
    used = tuple(g for g in grasps if any(g == h for _, h in states))
    out = optimise_over(checker, poses, path, should_stop=should_stop, costs=costs,
                        grasps=used, reach=reach, start_grasp=start_grasp,
                        end_grasp=end_grasp)
    after = _cost(checker, costs, out)
    if after < before:
        st.seconds_saved += before - after
        log.debug("regrasps slid: %d regrasps, %d poses offered, %.1f s saved", st.regrasps,
                  st.offered, before - after)
    return out


def _cost(checker: PivotChecker, costs: CostModel, states: list[State]) -> float:
    return Evaluator(checker, costs).path(states).cost


def _offered(checker: PivotChecker, states: list[State], k: int,
             distances: tuple[float, ...]) -> list[Pose]:
    """Poses of the transfer ``states[k - 1] -> states[k]`` near a regrasp at either end.

    At each of ``distances`` from the end that is a regrasp's pose (the state before
    ``k - 1`` or after ``k`` has the same pose and another grasp), the first pivot pose of
    the transfer's checked sequence that far along it; in the transfer's order.
    """
    (a, g), (b, _) = states[k - 1], states[k]
    regrasp_before = k >= 2 and states[k - 2][0] == a and states[k - 2][1] != g
    regrasp_after = k + 1 < len(states) and states[k + 1][0] == b and states[k + 1][1] != g
    if not (regrasp_before or regrasp_after):
        return []
    res = checker.transfer(a, b, g)
    if not res.valid:
        return []
    m = checker.model
    seq = [m.object_from_car(r.car, g) for r in res.sequence.rotations][:-1]
    picked: set[int] = set()
    if regrasp_before:
        picked |= _at_distances([a, *seq], distances)
    if regrasp_after:
        back = _at_distances([b, *seq[::-1]], distances)
        picked |= {len(seq) + 1 - i for i in back}
    # indices into [a, *seq]: 0 is ``a`` itself, never offered
    return [seq[i - 1] for i in sorted(picked) if 0 < i <= len(seq)]


def _at_distances(run: list[Pose], distances: tuple[float, ...]) -> set[int]:
    """Indices into ``run`` of its first pose at least each distance (m) from ``run[0]``."""
    out: set[int] = set()
    travelled, want = 0.0, sorted(distances)
    for i in range(1, len(run)):
        travelled += math.dist(run[i - 1][:2], run[i][:2])
        while want and travelled >= want[0]:
            out.add(i)
            want.pop(0)
        if not want:
            break
    return out

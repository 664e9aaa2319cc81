"""Each transfer phase re-routed at every other grasp: the same plan whatever the seed.

Seeds differ mostly in the grasp the search happened to find first: on the shipped corridor
three seeds gave one phase at grasps 0, 2 and 1, costing 245, 254 and 190 s, while the
lattice route at grasp 1 costs 185 s from any of them. :func:`choose_grasps` takes each phase
of a path (a run of states at one grasp between regrasps) and routes it between its own end
poses at every other grasp valid there (a :data:`~.eliminate.Router`, e.g. the held
assembly's lattice, :func:`~.eliminate.lattice_router`); the regrasps at the phase's ends
become walks to and from the new grasp (or vanish when a neighbour holds it already). A
candidate is priced with the planner's cost model (:meth:`~.evaluation.Evaluator.path`, which
checks every edge) and kept when it is cheaper. The result is always a valid path, never
costlier than the input.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.eliminate import Router, Stop
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]


@dataclass
class GraspChoiceStats:
    """What :func:`choose_grasps` did.

    Attributes:
        routed: phases routed at another grasp.
        changed: phases whose grasp changed (the path became cheaper).
        cost_before, cost_after: path cost (s, :class:`~pivot_ompl.cost.CostModel`).
    """

    routed: int = 0
    changed: int = 0
    cost_before: float = 0.0
    cost_after: float = 0.0


def _phases(states: list[State]) -> list[tuple[int, int]]:
    """``(first, last)`` index of each run of states at one grasp."""
    out: list[tuple[int, int]] = []
    a = 0
    for k in range(1, len(states) + 1):
        if k == len(states) or states[k][1] != states[a][1]:
            out.append((a, k - 1))
            a = k
    return out


def _joined(parts: list[list[State]]) -> list[State]:
    out: list[State] = []
    for part in parts:
        for s in part:
            if not out or out[-1] != s:
                out.append(s)
    return out


def choose_grasps(checker: PivotChecker, states: list[State], *, router: Router,
                  should_stop: Stop, grasps: tuple[int, ...] = (0, 1, 2, 3),
                  costs: CostModel | None = None, start_grasp: int | None = None,
                  stats: GraspChoiceStats | None = None) -> list[State]:
    """``states`` with each phase at its cheapest grasp (see the module docstring).

    Args:
        checker: validity of states, transfers and walks.
        states: a valid path of ``(object pose, grasp)`` states.
        router: routes a phase between two poses at one grasp (``[]``: none).
        should_stop: termination condition, polled before each route.
        grasps: the grasps the robot may use.
        costs: the cost model (default :class:`~pivot_ompl.cost.CostModel`).
        start_grasp: the grasp the robot holds the box with (the path must start with
            it, as ``states`` does); ``None``: any.
        stats: filled with what was done, if given.
    """
    w = costs or CostModel()
    st = stats if stats is not None else GraspChoiceStats()
    path = list(states)
    cost = st.cost_before = st.cost_after = Evaluator(checker, w).path(path).cost
    if len(path) < 2 or cost == float("inf"):
        return path
    k = 0
    while k < len(phases := _phases(path)):
        a, b = phases[k]
        k += 1
        first, last = path[a][0], path[b][0]
        if first == last:
            continue  # a regrasp's own pose: nothing to route
        for g in grasps:
            if should_stop():
                log.debug("grasp choice stopped after %d phases routed", st.routed)
                st.cost_after = cost
                return path
            if g == path[a][1] or (start_grasp is not None and a == 0 and g != path[0][1]) or \
                    not (checker.state_valid(first, g) and checker.state_valid(last, g)):
                continue
            st.routed += 1
            route = router(first, last, g, should_stop)
            if not route:
                continue
            new = _joined([path[:a], [(q, g) for q in route], path[b + 1:]])
            c = Evaluator(checker, w).path(new).cost
            if c < cost - 1e-9:
                path, cost = new, c
                st.changed += 1
                k = 0  # the phases changed: from the start again
                break
    st.cost_after = cost
    log.debug("grasp choice: cost %.1f -> %.1f, %d phases routed, %d changed",
              st.cost_before, st.cost_after, st.routed, st.changed)
    return path

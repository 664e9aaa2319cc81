"""Regrasp elimination: every regrasp of a path tried for removal, kept only if it pays.

A path is a list of ``(object pose, grasp)`` states (:mod:`.optimiser`); a regrasp is two
consecutive states at one pose with different grasps. For each regrasp, the *stretch* around
it, from the first pose of the transfer phase before it to the last pose of the phase after
it, is re-planned as ONE transfer phase, at the grasp of either side:

1. along the stretch's own poses, at that grasp (no search: often the regrasp served
   nothing, and the checker's caches make the check cheap), else
2. along the held assembly's lattice route between the stretch's ends
   (:func:`lattice_router`: :class:`~.routes.lattice.TransferLattice`, certified into a chain
   of checked transfers as the re-routing does), when a router is given (a query between
   the lattice's connected components costs nothing: a forced regrasp is kept cheaply), or
   else by the single-grasp RRT-Connect (:class:`~.single_grasp.SingleGraspConnect`)
   between the stretch's ends, within a budget of motion checks.

The candidate path (the regrasps at the stretch's ends joined to the new grasp, or gone when
the grasps then agree) is priced with the planner's cost model
(:meth:`~.evaluation.Evaluator.path`, which checks every edge) and replaces the path only when it is
cheaper. Stretches are tried regrasp by regrasp until none can be removed or
``should_stop``. The result is always a valid path, never costlier than the input; the
:class:`EliminationReport` says for each regrasp left why it stayed.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.chain import corners, shortened  # refine's certification
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.single_grasp import SingleGraspConnect
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]
#: ``router(start, goal, grasp, should_stop)``: object poses joined by checked transfers at
#: ``grasp`` from ``start`` to ``goal``, or ``[]``.
Router = Callable[[Pose, Pose, int, Stop], list[Pose]]

#: Why a regrasp stayed: removing it made the path costlier.
COSTLIER = "costlier"
#: Why a regrasp stayed: no single-grasp route of the stretch was found within the budget.
NO_ROUTE = "no single-grasp route found"
#: Why a regrasp stayed: the time or check budget ran out before it was tried.
UNTRIED = "not tried (budget)"


@dataclass
class KeptRegrasp:
    """One regrasp the path keeps, and why.

    Attributes:
        pose: the object pose where the robot walks round the box.
        from_grasp, to_grasp: the grasps before and after it.
        reason: :data:`COSTLIER`, :data:`NO_ROUTE` or :data:`UNTRIED`.
    """

    pose: Pose
    from_grasp: int
    to_grasp: int
    reason: str


@dataclass
class EliminationReport:
    """What :func:`eliminate_regrasps` did.

    Attributes:
        regrasps_before, regrasps_after: regrasps of the input and of the result.
        removed: regrasps removed.
        tried: re-planned stretches (each grasp of each regrasp counts once).
        cost_before, cost_after: path cost (s, :class:`~pivot_ompl.cost.CostModel`).
        kept: the result's regrasps, each with the reason it stayed.
        seconds: wall-clock time (s).
    """

    regrasps_before: int = 0
    regrasps_after: int = 0
    removed: int = 0
    tried: int = 0
    cost_before: float = 0.0
    cost_after: float = 0.0
    kept: list[KeptRegrasp] = field(default_factory=list)
    seconds: float = 0.0


def lattice_router(checker: PivotChecker, lattice: TransferLattice, costs: CostModel, *,
                   run_spacing: int) -> Router:
    """A :data:`Router` along ``lattice``'s cheapest route, certified transfer by transfer.

    ``run_spacing``: along a straight run of the route, a pose is kept to join every this
    many lattice motions (:func:`~.routes.chain.corners`).
    """
    def route(start: Pose, goal: Pose, grasp: int, should_stop: Stop) -> list[Pose]:
        try:
            poses, _ = lattice.route(start, goal, grasp, should_stop=should_stop)
            if len(poses) < 2:
                return []
            found = shortened(Evaluator(checker, costs), corners(poses, spacing=run_spacing), grasp,
                              should_stop)
        except Interrupted:
            return []
        if found.status is not Status.VALID or found.path is None:
            return []
        return found.path[0]
    return route


def regrasp_indices(states: list[State]) -> list[int]:
    """Indices ``k`` where ``states[k] -> states[k + 1]`` is a regrasp."""
    return [k for k in range(len(states) - 1)
            if states[k][0] == states[k + 1][0] and states[k][1] != states[k + 1][1]]


def _stretch(states: list[State], k: int) -> tuple[int, int]:
    """First and last index of the two transfer phases around the regrasp at ``k``."""
    a = k
    while a > 0 and states[a - 1][1] == states[k][1]:
        a -= 1
    b = k + 1
    while b + 1 < len(states) and states[b + 1][1] == states[k + 1][1]:
        b += 1
    return a, b


def _joined(head: list[State], middle: list[State], tail: list[State]) -> list[State]:
    """``head + middle + tail`` without repeated states (a regrasp that became none)."""
    out: list[State] = []
    for s in (*head, *middle, *tail):
        if not out or out[-1] != s:
            out.append(s)
    return out


def _distinct(poses: list[Pose]) -> list[Pose]:
    out: list[Pose] = []
    for q in poses:
        if not out or out[-1] != q:
            out.append(q)
    return out


def eliminate_regrasps(checker: PivotChecker, states: list[State], *, should_stop: Stop,
                       rng: np.random.Generator, costs: CostModel | None = None,
                       checks: int = 60, step: float = 1.5, start_grasp: int | None = None,
                       router: Router | None = None,
                       report: EliminationReport | None = None) -> list[State]:
    """``states`` with every regrasp that does not save cost removed (module docstring).

    Args:
        checker: validity of states, transfers and walks (its caches make re-checks free).
        states: a valid path of ``(object pose, grasp)`` states.
        should_stop: termination condition, polled between stretches and passed to every
            check.
        rng: random generator of the single-grasp searches (spawned from, left as it was).
        costs: the cost model (default :class:`~pivot_ompl.cost.CostModel`).
        checks: motion checks each single-grasp search may make.
        step: the single-grasp search's longest extension (m).
        start_grasp: the grasp the robot holds the box with (the path must start with
            it, as ``states`` does); ``None``: any.
        router: re-plans a stretch instead of the single-grasp search (e.g.
            :func:`lattice_router`); ``None``: the search.
        report: filled with what was done, if given.

    Returns:
        A valid path between the same poses, never costlier than ``states``.
    """
    w = costs or CostModel()
    rep = report if report is not None else EliminationReport()
    t0 = time.perf_counter()
    path = list(states)
    cost = Evaluator(checker, w).path(path).cost
    rep.regrasps_before = len(regrasp_indices(path))
    rep.cost_before = rep.cost_after = cost
    reasons: dict[tuple[Pose, int, int], str] = {}
    if math.isfinite(cost):
        failed: set[tuple[Pose, int, int]] = set()  # regrasps tried in vain
        progress = True
        while progress and not should_stop():
            progress = False
            for k in regrasp_indices(path):
                key = (path[k][0], path[k][1], path[k + 1][1])
                if key in failed:
                    continue
                if should_stop():
                    break
                better, why = _try(checker, path, k, cost, w, _Search(rng, checks, step, router),
                                   start_grasp, should_stop, rep)
                if better is None:
                    failed.add(key)
                    reasons[key] = why
                    continue
                path, cost = better
                rep.removed += 1
                progress = True
                break  # the indices changed: scan again
    rep.cost_after = cost
    rep.kept = [KeptRegrasp(path[k][0], path[k][1], path[k + 1][1],
                            reasons.get((path[k][0], path[k][1], path[k + 1][1]), UNTRIED))
                for k in regrasp_indices(path)]
    rep.regrasps_after = len(rep.kept)
    rep.seconds = time.perf_counter() - t0
    log.debug("regrasp elimination: %d -> %d regrasps, cost %.1f -> %.1f, %d stretches "
              "re-planned, %.3f s; kept: %s", rep.regrasps_before, rep.regrasps_after,
              rep.cost_before, rep.cost_after, rep.tried, rep.seconds,
              [(k.from_grasp, k.to_grasp, k.reason) for k in rep.kept])
    return path


@dataclass(frozen=True)
class _Search:
    """How a stretch is re-planned: the router, or RRT-Connect (``checks``, ``step``)."""

    rng: np.random.Generator
    checks: int
    step: float
    router: Router | None

    def route(self, checker: PivotChecker, first: Pose, last: Pose, g: int,
              should_stop: Stop) -> list[Pose]:
        """A single-grasp route from ``first`` to ``last`` at ``g``, or ``[]``."""
        if self.router is not None:  # the lattice knows the floor: no blind search after it
            return self.router(first, last, g, should_stop)
        rrt = SingleGraspConnect(checker, first, last, g, self.rng.spawn(1)[0], step=self.step)
        found = rrt.run(self.checks, should_stop)
        return found.path if found.status is Status.VALID and found.path is not None else []


def _try(checker: PivotChecker, path: list[State], k: int, cost: float, w: CostModel,
         search: _Search, start_grasp: int | None, should_stop: Stop, rep: EliminationReport
         ) -> tuple[tuple[list[State], float] | None, str]:
    """The cheaper path without the regrasp at ``k`` and its cost, or ``None`` and why."""
    a, b = _stretch(path, k)
    poses = _distinct([q for q, _ in path[a:b + 1]])
    first, last = poses[0], poses[-1]
    why = NO_ROUTE
    for g in (path[k][1], path[k + 1][1]):
        if should_stop():
            return None, UNTRIED
        if start_grasp is not None and a == 0 and g != path[0][1]:
            continue  # the robot holds the box with the first grasp at the start
        if not (checker.state_valid(first, g) and checker.state_valid(last, g)):
            continue
        rep.tried += 1
        own = poses if all(checker.state_valid(q, g) for q in poses[1:-1]) else []
        for make in (lambda: own,  # noqa: B023 (called within the iteration)
                     lambda: search.route(checker, first, last, g, should_stop)):  # noqa: B023
            if should_stop():
                return None, UNTRIED
            route = make()
            if not route:
                continue
            new = _joined(path[:a], [(q, g) for q in route], path[b + 1:])
            c = Evaluator(checker, w).path(new).cost
            if c < cost - 1e-9:
                return (new, c), ""
            if math.isfinite(c):
                why = COSTLIER
    return None, why

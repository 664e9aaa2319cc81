"""A path's phases re-planned on the held assembly's lattice: cheaper routes, fewer regrasps.

A path found by the multiplexed search is a sequence of *phases* (transfers at one grasp)
joined by regrasps. :func:`refine` looks at every run of consecutive phases ``i .. j`` whose
grasps differ by a half turn or not at all (the robot ends on the box's other side, or the
same): such a run can be one phase at phase ``i``'s grasp, the regrasps inside it replaced by
turns of the box with the robot, wherever the lattice finds room
(:class:`~.lattice.TransferLattice`: pushes, pulls and turns in place, the cheapest route the
lattice knows). After a run whose grasps differ by a half turn the rest of the path is written
in the turned frame (the same motions), and its last phase, which must end at the goal as
given, is routed again from there. ``i == j`` re-routes one phase.

Candidates are priced (:mod:`.run_pricing`) with the lattice's seconds
(:class:`~pivot_ompl.cost.CostModel`) against the path's real ones, by branch and bound:
every run gets an optimistic saving from the lattice's admissible bound (no search), and
only the runs whose bound could beat the best saving found so far are routed (a route asked
again is free), so each round chooses the run that routing every run would choose
(:func:`~.run_pricing.best_run`). The most promising is then made real: each new route
shortened into the cheapest chain of certified transfers between its poses (each pose joined
to the poses 1, 2, 4, ... further on and to the end, found lazily). A candidate whose real
cost is not lower, or that the exact checks refuse somewhere, is dropped. The result is
always a valid path, never costlier than the input; the optimiser afterwards may still
shortcut it.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator, Found, Status
from pivot_ompl.planners.routes.chain import TOO_DEAR, made_real
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.lattice_ends import between_headings
from pivot_ompl.planners.routes.run_pricing import (
    Leg,
    Phase,
    Pricer,
    best_candidate,
    phases_of,
    states_of,
)
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]


@dataclass
class RefineStats:
    """What :func:`refine` did.

    Attributes:
        candidates: runs of phases routed on the lattice (those whose bound could beat the
            best saving, :func:`~.run_pricing.best_candidate`).
        tried: candidates made real (their routes checked).
        applied: candidates that made the path cheaper.
        regrasps_removed: regrasps replaced by turns.
        seconds_saved: cost saved (s).
    """

    candidates: int = 0
    tried: int = 0
    applied: int = 0
    regrasps_removed: int = 0
    seconds_saved: float = 0.0


def refine(checker: PivotChecker, lattice: TransferLattice, states: list[State], *,
           costs: CostModel, should_stop: Stop, run_spacing: int,
           stats: RefineStats | None = None, start_grasp: int | None = None,
           grasps: tuple[int, ...] = (), min_saving: float = 0.0,
           whole_min_saving: float = 0.0) -> list[State]:
    """``states`` with runs of phases re-planned on the lattice (see the module docstring).

    Stopped by ``should_stop`` (polled between lattice queries and checks), it returns the
    best path it has: valid, never costlier than ``states``. ``start_grasp``: the grasp the
    robot holds the box with (``states`` starts with it, and so does the result); ``None``:
    the first grasp is free, and the whole path is also routed as one phase at each of
    ``grasps`` (seeds that found the path at different grasps then meet on the same route).
    ``run_spacing``: along a straight run of a lattice route, a pose is kept to join every
    this many lattice motions (:func:`~.chain.corners`). ``min_saving``: a run whose
    estimated saving is at most this share of the path's cost is not re-planned;
    ``whole_min_saving``: the same for the run of every phase (the whole path as one
    phase), when larger.
    """
    st = stats if stats is not None else RefineStats()
    pricer = Pricer(checker, costs)
    phases = phases_of(states)
    if not phases:
        return states
    current = pricer.path(phases)
    if not math.isfinite(current):
        return states
    refused: set[tuple[int, int, int, tuple[Pose, ...]]] = set()
    chains: _Chains = {}  # a route asked again in a later round is made real once
    try:
        while not should_stop():
            best, routed = best_candidate(lattice, pricer, phases, current, refused,
                                          should_stop, start_grasp, grasps,
                                          least=min_saving * current,
                                          least_whole=whole_min_saving * current)
            st.candidates += routed
            if best is None:
                break
            i, j, g, _saving, plan = best
            refused.add((i, j, g, phases[i].poses))
            st.tried += 1
            real = _made_real(checker, lattice, plan, costs, should_stop, run_spacing, chains,
                              ceiling=_ceiling(pricer, costs, plan, current))
            if real is None or real[-1].poses[-1] != phases[-1].poses[-1]:
                log.debug("phases %d..%d at grasp %d: the checks refuse the route", i, j, g)
                continue
            cost = pricer.path(real)
            if cost >= current - 1e-9:
                log.debug("phases %d..%d at grasp %d: %.0f s, not below %.0f s", i, j, g, cost,
                          current)
            if cost < current - 1e-9:
                st.applied += 1
                st.regrasps_removed += len(phases) - len(real)
                st.seconds_saved += current - cost
                log.debug("refined phases %d..%d: %.0f -> %.0f s", i, j, current, cost)
                phases, current = real, cost
    except Interrupted:
        pass
    return states_of(phases)


#: :func:`~.chain.shortened`'s answers by route ``(start, end, grasp)``
_Chains = dict[tuple[Pose, Pose, int, bool], Found[tuple[list[Pose], float]]]


def _ceiling(pricer: Pricer, costs: CostModel, plan: list, current: float) -> float:
    """Seconds the one leg of ``plan`` must cost less than for the plan to beat ``current``.

    The rest of the plan at its real seconds, a regrasp next to the leg at the least any
    regrasp costs: a chain at or above the ceiling is refused whatever the walks cost.
    ``inf`` for a plan of several legs (their costs are known only together).
    """
    legs = [k for k, item in enumerate(plan) if isinstance(item, Leg)]
    if len(legs) != 1:
        return math.inf
    rest = sum(pricer.phase(p) for p in plan if isinstance(p, Phase))
    for a, b in zip(plan, plan[1:], strict=False):
        if isinstance(a, Phase) and isinstance(b, Phase):
            rest += pricer.regrasp(a, b)
        elif a.grasp != b.grasp:
            rest += costs.regrasp_seconds(0.0)
    return current - rest


def _leg_chain(checker: PivotChecker, lattice: TransferLattice, leg: Leg, costs: CostModel,
               should_stop: Stop, run_spacing: int, chains: _Chains,
               ceiling: float = math.inf) -> list[Pose]:
    """The leg as a chain of certified transfers (``[]`` if none): whole, else anchored.

    Where an end lies between two lattice headings, last the whole leg again with its ends
    joined where the lattice can turn across them (``leads``, :mod:`.lattice_ends`).

    ``chains``: the routes' chains found before (a route asked again is not checked again).
    ``ceiling``: a chain that cannot cost less is not made (:func:`~.chain.shortened`).
    """
    tries: list[tuple[tuple[Pose, ...], Pose, Pose, tuple[Pose, ...], bool]] = [
        ((), leg.start, leg.end, (), False)]
    if leg.head or leg.tail:
        tries.append((leg.head[:1], leg.head[-1] if leg.head else leg.start,
                      leg.tail[0] if leg.tail else leg.end, leg.tail[1:], False))
    m = checker.model
    if any(between_headings(m.car_pose(q, leg.grasp)[2]) for q in (leg.start, leg.end)):
        tries.append(((), leg.start, leg.end, (), True))  # ends joined where they can turn
    for before, a, b, after, leads in tries:
        route, _ = lattice.route(a, b, leg.grasp, should_stop=should_stop, leads=leads)
        if len(route) < 2:
            continue
        key = (a, b, leg.grasp, leads)
        found = chains.get(key)
        if found is None:
            found = made_real(Evaluator(checker, costs), route, leg.grasp, should_stop,
                              spacing=run_spacing, ceiling=ceiling, cache=lattice.chains,
                              leads=leads)
            if found.status is Status.STOPPED:
                raise Interrupted("route refinement")
            if found is TOO_DEAR:  # as the whole chain refused for its cost: no anchored try
                return []
            chains[key] = found
        if found.path is not None:
            return [*before, *found.path[0], *after]
    return []


def _made_real(checker: PivotChecker, lattice: TransferLattice, plan: list,
               costs: CostModel, should_stop: Stop, run_spacing: int,
               chains: _Chains, *, ceiling: float = math.inf) -> list[Phase] | None:
    """The plan's routed legs as chains of certified transfers; ``None`` if one fails.

    ``chains``: the routes' chains found before (:func:`_leg_chain`); ``ceiling``: the one
    leg's (:func:`_ceiling`).
    """
    out: list[Phase] = []
    for item in plan:
        if isinstance(item, Phase):
            out.append(item)
            continue
        grasp = item.grasp
        chain = _leg_chain(checker, lattice, item, costs, should_stop, run_spacing, chains,
                           ceiling)
        if not chain:
            return None
        if out and out[-1].grasp == grasp:  # a regrasp the run removed: one phase
            out[-1] = Phase(grasp, out[-1].poses + tuple(chain[1:]))
        else:
            out.append(Phase(grasp, tuple(chain)))
    return out

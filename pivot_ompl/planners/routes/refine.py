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

Candidates are priced with the lattice's seconds (:class:`~pivot_ompl.cost.CostModel`) against
the path's real ones, by branch and bound: every run gets an optimistic saving from the
lattice's admissible bound (no search), and only the runs whose bound could beat the best
saving found so far are routed (a route asked again is free), so each round chooses the run
that routing every run would choose. The most promising is then made real: each new route
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
from pivot_ompl.planners.objects.roadmap import half_turn
from pivot_ompl.planners.routes.chain import TOO_DEAR, corners, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]


@dataclass
class RefineStats:
    """What :func:`refine` did.

    Attributes:
        candidates: runs of phases routed on the lattice (those whose bound could beat the
            best saving, :func:`_best_candidate`).
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


@dataclass(frozen=True)
class _Phase:
    grasp: int
    poses: tuple[Pose, ...]

    def turned(self) -> _Phase:
        """The same motion written in the half-turned frame."""
        return _Phase((self.grasp + 2) % 4, tuple(half_turn(q) for q in self.poses))


def _phases(states: list[State]) -> list[_Phase]:
    out: list[_Phase] = []
    for q, g in states:
        if out and out[-1].grasp == g:
            if out[-1].poses[-1] != q:
                out[-1] = _Phase(g, out[-1].poses + (q,))
        else:
            out.append(_Phase(g, (q,)))
    return out


def _states(phases: list[_Phase]) -> list[State]:
    return [(q, p.grasp) for p in phases for q in p.poses]


class _Pricer:
    """Real seconds of phases and regrasps (the checker's caches make repeats free)."""

    def __init__(self, checker: PivotChecker, costs: CostModel) -> None:
        self.evaluate = Evaluator(checker, costs)

    def phase(self, p: _Phase) -> float:
        return self.evaluate.path([(q, p.grasp) for q in p.poses]).cost

    def regrasp(self, a: _Phase, b: _Phase) -> float:
        return self.evaluate.walk(a.poses[-1], a.grasp, b.grasp).cost

    def path(self, phases: list[_Phase]) -> float:
        return sum(self.phase(p) for p in phases) + sum(
            self.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False))


def refine(checker: PivotChecker, lattice: TransferLattice, states: list[State], *,
           costs: CostModel, should_stop: Stop, stats: RefineStats | None = None,
           start_grasp: int | None = None, grasps: tuple[int, ...] = ()) -> list[State]:
    """``states`` with runs of phases re-planned on the lattice (see the module docstring).

    Stopped by ``should_stop`` (polled between lattice queries and checks), it returns the
    best path it has: valid, never costlier than ``states``. ``start_grasp``: the grasp the
    robot holds the box with (``states`` starts with it, and so does the result); ``None``:
    the first grasp is free, and the whole path is also routed as one phase at each of
    ``grasps`` (seeds that found the path at different grasps then meet on the same route).
    """
    st = stats if stats is not None else RefineStats()
    pricer = _Pricer(checker, costs)
    phases = _phases(states)
    if not phases:
        return states
    current = pricer.path(phases)
    if not math.isfinite(current):
        return states
    refused: set[tuple[int, int, int, tuple[Pose, ...]]] = set()
    chains: _Chains = {}  # a route asked again in a later round is made real once
    try:
        while not should_stop():
            best = _best_candidate(lattice, pricer, phases, current, refused, should_stop, st,
                                   start_grasp, grasps)
            if best is None:
                break
            i, j, g, plan = best
            refused.add((i, j, g, phases[i].poses))
            st.tried += 1
            real = _made_real(checker, lattice, plan, costs, should_stop, pricer, current,
                              chains)
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
    return _states(phases)


def _candidates(phases: list[_Phase], start_grasp: int | None = None,
                grasps: tuple[int, ...] = ()) -> list[tuple[int, int, int]]:
    """Runs ``i .. j`` and the grasp ``g`` to plan each at.

    Runs whose grasps differ by zero or a half turn, at phase ``i``'s grasp; and, since the
    grasp at the start (unless ``start_grasp`` is held) and at the goal is free,
    runs from the start planned at phase ``j``'s grasp and runs to the goal planned at phase
    ``i``'s, whatever their grasps (a regrasp after the start or before the goal that only
    changed the face is removed); with the start's grasp free, the whole path as one
    phase at each of ``grasps`` too.
    """
    last = len(phases) - 1
    out = []
    for i in range(len(phases)):
        for j in range(i, len(phases)):
            gi, gj = phases[i].grasp, phases[j].grasp
            if (gj - gi) % 2 == 0:
                out.append((i, j, gi))
                continue
            if i == 0 and start_grasp is None:
                out.append((i, j, gj))
            if j == last:
                out.append((i, j, gi))
    if start_grasp is None:
        out += [(0, last, g) for g in grasps if (0, last, g) not in out]
    return out


def _best_candidate(lattice: TransferLattice, pricer: _Pricer, phases: list[_Phase],
                    current: float, refused: set, should_stop: Stop, st: RefineStats,
                    start_grasp: int | None = None, grasps: tuple[int, ...] = ()
                    ) -> tuple[int, int, int, list[_Phase | _Leg]] | None:
    """The run whose lattice re-plan saves the most (estimated), as a plan to make real.

    ``start_grasp``: the plan keeps the first phase's grasp (:func:`_candidates`).

    A plan is the new phase list where the phases to route are legs (:class:`_Leg`). The
    regrasps a plan keeps are the path's own (a turned phase's regrasp is the same walk
    written in the other frame), so they are priced by the path's walks.

    Branch and bound: every run gets an optimistic saving from the lattice's admissible
    bound (:meth:`~.lattice.TransferLattice.lower_bound`, no search), and runs are routed in
    the order of that bound until the best saving found is above the next bound. The run
    chosen is the one pricing every run would choose (ties to the earlier run of
    :func:`_candidates`), at the cost of routing only the runs that could beat it.
    """
    cost = [pricer.phase(p) for p in phases]
    regrasp = [0.0] + [pricer.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False)]
    bounds = _bounds(lattice, phases, cost, regrasp, current, refused, start_grasp, grasps)
    best: tuple[float, int, int, int, int, list] | None = None
    for optimistic, idx, i, j, g in bounds:
        if best is not None and optimistic < best[0] - _BOUND_SLACK:
            break
        if should_stop():
            raise Interrupted("route refinement")
        st.candidates += 1
        priced = _priced(lattice, phases, cost, regrasp, current, (i, j, g), should_stop)
        if priced is None:
            continue
        saving, plan = priced
        if saving > 1e-9 and (best is None or saving > best[0]
                              or (saving == best[0] and idx < best[1])):
            best = (saving, idx, i, j, g, plan)
    return None if best is None else (best[2], best[3], best[4], best[5])


#: Seconds of rounding the optimistic savings may be off by (they are summed in another
#: order than the estimates): a run is routed unless its bound is this much below the best.
_BOUND_SLACK = 1e-6
#: Seconds above the path's cost a plan's bound must reach to drop it (:func:`_made_real`).
_CEILING_SLACK = 1e-6


def _run_ends(phases: list[_Phase], i: int, j: int, g: int) -> tuple[bool, Pose, Pose]:
    """Whether the run ``i .. j`` planned at grasp ``g`` ends half turned, and its route's ends.

    A half-turned run that is not the last ends at its last pose's half turn (the rest of
    the path is written in the turned frame).
    """
    turned = (phases[j].grasp - g) % 4 == 2
    start, end = phases[i].poses[0], phases[j].poses[-1]
    if turned and j < len(phases) - 1:
        end = half_turn(end)
    return turned, start, end


def _bounds(lattice: TransferLattice, phases: list[_Phase], cost: list[float],
            regrasp: list[float], current: float, refused: set, start_grasp: int | None,
            grasps: tuple[int, ...] = ()) -> list[tuple[float, int, int, int, int]]:
    """``(optimistic saving, index, i, j, g)`` of the runs that may save, best first.

    The optimistic saving is ``current`` less the run's estimate with every lattice route
    replaced by its lower bound; runs whose bound saves nothing are left out.
    """
    last = len(phases) - 1
    before = [0.0]
    for k in range(last + 1):
        before.append(before[-1] + cost[k] + (regrasp[k + 1] if k < last else 0.0))
    after = [0.0] * (last + 2)
    for k in range(last, -1, -1):
        after[k] = after[k + 1] + cost[k] + regrasp[k]
    out = []
    for idx, (i, j, g) in enumerate(_candidates(phases, start_grasp, grasps)):
        if (i, j, g, phases[i].poses) in refused:
            continue
        turned, start, end = _run_ends(phases, i, j, g)
        low = before[i] + lattice.lower_bound(start, end, g) + after[j + 1]
        if turned and j < last:
            lp = phases[last].turned()
            low += lattice.lower_bound(lp.poses[0], phases[-1].poses[-1], lp.grasp) - cost[last]
        if current - low > 1e-9:
            out.append((current - low, idx, i, j, g))
    out.sort(key=lambda b: (-b[0], b[1]))
    return out


def _priced(lattice: TransferLattice, phases: list[_Phase], cost: list[float],
            regrasp: list[float], current: float, run: tuple[int, int, int],
            should_stop: Stop) -> tuple[float, list] | None:
    """The estimated saving of re-planning ``run = (i, j, g)`` and its plan (``None``: none).

    Estimated with the lattice's routes (:func:`_best_candidate`).
    """
    i, j, g = run
    last = len(phases) - 1
    turned, start, end = _run_ends(phases, i, j, g)
    estimate = sum(cost[:i]) + sum(regrasp[1:i + 1])
    if estimate >= current:
        return None
    _route, seconds = lattice.route(start, end, g, should_stop=should_stop)
    estimate += seconds + sum(cost[j + 1:]) + sum(regrasp[j + 1:])
    head = phases[i].poses[:2] if g == phases[i].grasp else ()
    tail_poses = phases[j].poses[-2:]
    turned_tail = turned and j < last  # a last phase still ends at the goal as given
    if turned_tail:
        tail_poses = tuple(half_turn(q) for q in tail_poses)
    anchor = tail_poses if (g == phases[j].grasp or turned_tail) else ()
    if i == j and len(phases[i].poses) < 4:
        head, anchor = (), ()
    plan: list = list(phases[:i]) + [_Leg(start, end, g, head, anchor)]
    tail: list = list(phases[j + 1:])
    if turned and tail:
        tail = [p.turned() for p in tail]
        lp = tail[-1]
        if estimate - cost[last] >= current:
            return None
        _route, seconds = lattice.route(lp.poses[0], phases[-1].poses[-1], lp.grasp,
                                        should_stop=should_stop)
        estimate += seconds - cost[last]
        tail[-1] = _Leg(lp.poses[0], phases[-1].poses[-1], lp.grasp,
                        lp.poses[:2] if len(lp.poses) >= 4 else (), ())
    plan += tail
    return current - estimate, plan


@dataclass(frozen=True)
class _Leg:
    """A phase to route on the lattice from ``start`` to ``end`` at ``grasp``.

    ``head`` and ``tail``: the path's own first two and last two poses of the run (certified
    transfers, written at ``grasp``; empty when they cannot serve). Where the lattice's route
    cannot be certified at the run's ends (a pose inside a tight slot, say), the leg is
    routed from ``head``'s second pose to ``tail``'s first and keeps the path's own motions
    at both ends.
    """

    start: Pose
    end: Pose
    grasp: int
    head: tuple[Pose, ...]
    tail: tuple[Pose, ...]


#: :func:`~.chain.shortened`'s answers by route ``(start, end, grasp)``, with their ceilings
_Chains = dict[tuple[Pose, Pose, int], tuple[Found[tuple[list[Pose], float]], float]]


def _leg_chain(checker: PivotChecker, lattice: TransferLattice, leg: _Leg, costs: CostModel,
               should_stop: Stop, ceiling: float = math.inf, chains: _Chains | None = None
               ) -> tuple[list[Pose], float]:
    """The leg as a chain of certified transfers (whole, else anchored) and its cost.

    ``([], inf)`` if there is none, or once it is proven to cost at least ``ceiling`` s
    (:data:`~.chain.TOO_DEAR`; no anchored try follows, as none follows a whole chain too
    dear). ``chains``: the routes' chains found before (one too dear at a ceiling serves below).
    """
    tries: list[tuple[tuple[Pose, ...], Pose, Pose, tuple[Pose, ...]]] = [
        ((), leg.start, leg.end, ())]
    if leg.head or leg.tail:
        tries.append((leg.head[:1], leg.head[-1] if leg.head else leg.start,
                      leg.tail[0] if leg.tail else leg.end, leg.tail[1:]))
    for before, a, b, after in tries:
        route, _ = lattice.route(a, b, leg.grasp, should_stop=should_stop)
        if len(route) < 2:
            continue
        key = (a, b, leg.grasp)
        known, above = (chains or {}).get(key, (None, -math.inf))
        if known is not None and (known is not TOO_DEAR or above >= ceiling):
            found = known  # the same route's chain (a dear one: dearer than asked now)
        else:
            found = shortened(Evaluator(checker, costs), corners(route), leg.grasp,
                              should_stop, ceiling=ceiling)
            if found.status is Status.STOPPED:
                raise Interrupted("route refinement")
            if chains is not None:
                chains[key] = (found, ceiling)
        if found is TOO_DEAR:
            return [], math.inf
        if found.path is not None:
            return [*before, *found.path[0], *after], found.path[1]
    return [], math.inf


def _made_real(checker: PivotChecker, lattice: TransferLattice, plan: list,
               costs: CostModel, should_stop: Stop, pricer: _Pricer | None = None,
               current: float = math.inf, chains: _Chains | None = None
               ) -> list[_Phase] | None:
    """The plan's routed legs as chains of certified transfers; ``None`` if one fails.

    Also ``None`` as soon as the plan is proven to cost at least ``current`` (priced by
    ``pricer``; the phases it keeps and the legs made real so far, plus a bound on the leg
    at hand): the caller would drop it, and its remaining checks are saved. ``chains``:
    the routes' chains found before (:func:`_leg_chain`).
    """
    out: list[_Phase] = []
    spent = 0.0 if pricer is None else sum(pricer.phase(p) for p in plan
                                           if isinstance(p, _Phase))
    for item in plan:
        if isinstance(item, _Phase):
            out.append(item)
            continue
        grasp = item.grasp
        chain, cost = _leg_chain(checker, lattice, item, costs, should_stop,
                                 current + _CEILING_SLACK - spent, chains)
        spent += cost
        if not chain:
            return None
        if out and out[-1].grasp == grasp:  # a regrasp the run removed: one phase
            out[-1] = _Phase(grasp, out[-1].poses + tuple(chain[1:]))
        else:
            out.append(_Phase(grasp, tuple(chain)))
    return out

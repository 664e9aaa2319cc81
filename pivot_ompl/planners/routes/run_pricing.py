"""The pricing of runs of a path's phases for :mod:`.refine`: which run to re-plan first.

A path is a sequence of *phases* (transfers at one grasp) joined by regrasps
(:func:`phases_of`). A *run* ``i .. j`` of them, planned at a grasp ``g`` (:func:`_candidates`),
is priced by the lattice's route between its ends (:class:`~.lattice.TransferLattice`), the
rest of the path at its real seconds (:class:`Pricer`). :func:`best_candidate` chooses the run
saving the most by branch and bound over the lattice's admissible bound; :func:`best_run` is
its public face, and with ``exhaustive=True`` prices every run (the reference the branch and
bound must agree with).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.objects.roadmap import half_turn
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.se2 import Pose

__all__ = ["Leg", "Phase", "Pricer", "RunRound", "best_candidate", "best_run", "phases_of",
           "states_of"]

State = tuple[Pose, int]
Stop = Callable[[], bool]


@dataclass(frozen=True)
class Phase:
    """Transfers at one grasp: ``poses`` joined in turn, held at ``grasp``."""

    grasp: int
    poses: tuple[Pose, ...]

    def turned(self) -> Phase:
        """The same motion written in the half-turned frame."""
        return Phase((self.grasp + 2) % 4, tuple(half_turn(q) for q in self.poses))


def phases_of(states: list[State]) -> list[Phase]:
    """A path's states as phases (consecutive states at one grasp, repeats dropped)."""
    out: list[Phase] = []
    for q, g in states:
        if out and out[-1].grasp == g:
            if out[-1].poses[-1] != q:
                out[-1] = Phase(g, out[-1].poses + (q,))
        else:
            out.append(Phase(g, (q,)))
    return out


def states_of(phases: list[Phase]) -> list[State]:
    """The phases as a path's states again."""
    return [(q, p.grasp) for p in phases for q in p.poses]


class Pricer:
    """Real seconds of phases and regrasps (the checker's caches make repeats free)."""

    def __init__(self, checker: PivotChecker, costs: CostModel) -> None:
        self.evaluate = Evaluator(checker, costs)

    def phase(self, p: Phase) -> float:
        """Seconds of the phase's transfers (inf if one fails)."""
        return self.evaluate.path([(q, p.grasp) for q in p.poses]).cost

    def regrasp(self, a: Phase, b: Phase) -> float:
        """Seconds of the walk from ``a``'s grasp to ``b``'s at ``a``'s last pose."""
        return self.evaluate.walk(a.poses[-1], a.grasp, b.grasp).cost

    def path(self, phases: list[Phase]) -> float:
        """Seconds of the phases and the regrasps between them."""
        return sum(self.phase(p) for p in phases) + sum(
            self.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False))


def _candidates(phases: list[Phase], start_grasp: int | None = None,
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


def best_candidate(lattice: TransferLattice, pricer: Pricer, phases: list[Phase],
                   current: float, refused: set, should_stop: Stop,
                   start_grasp: int | None = None, grasps: tuple[int, ...] = (),
                   least: float = 0.0, least_whole: float = 0.0
                   ) -> tuple[tuple[int, int, int, float, list[Phase | Leg]] | None, int]:
    """The run whose lattice re-plan saves the most (estimated), as a plan to make real.

    ``start_grasp``: the plan keeps the first phase's grasp (:func:`_candidates`).
    ``least`` (s): a run saving no more than this by the estimate is not chosen, nor routed
    when its optimistic saving is not above it; ``least_whole`` (s): the same for the run
    of every phase (the whole path as one), when larger.

    A plan is the new phase list where the phases to route are legs (:class:`Leg`). The
    regrasps a plan keeps are the path's own (a turned phase's regrasp is the same walk
    written in the other frame), so they are priced by the path's walks.

    Branch and bound: every run gets an optimistic saving from the lattice's admissible
    bound (:meth:`~.lattice.TransferLattice.lower_bound`, no search), and runs are routed in
    the order of that bound until the best saving found is above the next bound. The run
    chosen is the one pricing every run would choose (ties to the earlier run of
    :func:`_candidates`), at the cost of routing only the runs that could beat it.

    Returns ``(i, j, g, saving, plan)`` (``None``: no run saves) and the runs routed.
    """
    cost = [pricer.phase(p) for p in phases]
    regrasp = [0.0] + [pricer.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False)]
    last = len(phases) - 1

    def floor(i: int, j: int) -> float:  # the least saving of run i .. j
        return max(least, least_whole) if i == 0 and j == last else least

    bounds = [b for b in _bounds(lattice, phases, cost, regrasp, current, refused, start_grasp,
                                 grasps) if b[0] > floor(b[2], b[3])]
    best: tuple[float, int, int, int, int, list] | None = None
    routed = 0
    for optimistic, idx, i, j, g in bounds:
        if best is not None and optimistic < best[0] - _BOUND_SLACK:
            break
        if should_stop():
            raise Interrupted("route refinement")
        routed += 1
        priced = _priced(lattice, phases, cost, regrasp, current, (i, j, g), should_stop)
        if priced is None:
            continue
        saving, plan = priced
        if saving > max(1e-9, floor(i, j)) and (best is None or saving > best[0]
                              or (saving == best[0] and idx < best[1])):
            best = (saving, idx, i, j, g, plan)
    if best is None:
        return None, routed
    return (best[2], best[3], best[4], best[0], best[5]), routed


#: Seconds of rounding the optimistic savings may be off by (they are summed in another
#: order than the estimates): a run is routed unless its bound is this much below the best.
_BOUND_SLACK = 1e-6


def _run_ends(phases: list[Phase], i: int, j: int, g: int) -> tuple[bool, Pose, Pose]:
    """Whether the run ``i .. j`` planned at grasp ``g`` ends half turned, and its route's ends.

    A half-turned run that is not the last ends at its last pose's half turn (the rest of
    the path is written in the turned frame).
    """
    turned = (phases[j].grasp - g) % 4 == 2
    start, end = phases[i].poses[0], phases[j].poses[-1]
    if turned and j < len(phases) - 1:
        end = half_turn(end)
    return turned, start, end


def _bounds(lattice: TransferLattice, phases: list[Phase], cost: list[float],
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


def _priced(lattice: TransferLattice, phases: list[Phase], cost: list[float],
            regrasp: list[float], current: float, run: tuple[int, int, int],
            should_stop: Stop) -> tuple[float, list] | None:
    """The estimated saving of re-planning ``run = (i, j, g)`` and its plan (``None``: none).

    Estimated with the lattice's routes (:func:`best_candidate`).
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
    plan: list = list(phases[:i]) + [Leg(start, end, g, head, anchor)]
    tail: list = list(phases[j + 1:])
    if turned and tail:
        tail = [p.turned() for p in tail]
        lp = tail[-1]
        if estimate - cost[last] >= current:
            return None
        _route, seconds = lattice.route(lp.poses[0], phases[-1].poses[-1], lp.grasp,
                                        should_stop=should_stop)
        estimate += seconds - cost[last]
        tail[-1] = Leg(lp.poses[0], phases[-1].poses[-1], lp.grasp,
                        lp.poses[:2] if len(lp.poses) >= 4 else (), ())
    plan += tail
    return current - estimate, plan


@dataclass(frozen=True)
class Leg:
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


@dataclass(frozen=True)
class RunRound:
    """One round's choice of a run to re-plan (:func:`best_run`).

    Attributes:
        run: ``(i, j, g)``: phases ``i .. j`` of the path (:func:`phases_of`, from 0) planned
            as one at grasp ``g``; ``None`` when no run saves by the estimate.
        saving: its estimated saving (s; 0 without a run).
        routed: runs routed on the lattice to choose it.
    """

    run: tuple[int, int, int] | None
    saving: float
    routed: int


def best_run(checker: PivotChecker, lattice: TransferLattice, states: list[State], *,
             costs: CostModel, should_stop: Stop, start_grasp: int | None = None,
             grasps: tuple[int, ...] = (), exclude: frozenset[tuple[int, int, int]] = frozenset(),
             exhaustive: bool = False) -> RunRound:
    """The run of ``states``' phases :func:`~.refine.refine` would re-plan first.

    The run whose lattice re-plan saves the most by the estimate, ties to the earlier run;
    ``exclude``: runs ``(i, j, g)`` not to choose (refused by the checks). By branch and
    bound (:func:`best_candidate`), or, ``exhaustive``, by routing every run: the same run
    and saving, routing more. ``start_grasp``, ``grasps``: as :func:`~.refine.refine`'s.
    No run for an empty path or one that fails its checks.

    Raises:
        Interrupted: ``should_stop`` said stop.
    """
    pricer = Pricer(checker, costs)
    phases = phases_of(states)
    current = pricer.path(phases)
    if not phases or not math.isfinite(current):  # as refine: nothing to re-plan
        return RunRound(None, 0.0, 0)
    refused = {(i, j, g, phases[i].poses) for i, j, g in exclude if 0 <= i < len(phases)}
    if exhaustive:
        return _every_run(lattice, pricer, phases, current, refused, should_stop, start_grasp,
                          grasps)
    best, routed = best_candidate(lattice, pricer, phases, current, refused, should_stop,
                                  start_grasp, grasps)
    if best is None:
        return RunRound(None, 0.0, routed)
    return RunRound(best[:3], best[3], routed)


def _every_run(lattice: TransferLattice, pricer: Pricer, phases: list[Phase], current: float,
               refused: set, should_stop: Stop, start_grasp: int | None,
               grasps: tuple[int, ...]) -> RunRound:
    """:func:`best_run` routing every run, in the order of :func:`_candidates`."""
    cost = [pricer.phase(p) for p in phases]
    regrasp = [0.0] + [pricer.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False)]
    best: tuple[float, tuple[int, int, int]] | None = None
    routed = 0
    for i, j, g in _candidates(phases, start_grasp, grasps):
        if (i, j, g, phases[i].poses) in refused:
            continue
        if should_stop():
            raise Interrupted("route refinement")
        routed += 1
        priced = _priced(lattice, phases, cost, regrasp, current, (i, j, g), should_stop)
        if priced is not None and priced[0] > 1e-9 and (best is None or priced[0] > best[0]):
            best = (priced[0], (i, j, g))
    return RunRound(None, 0.0, routed) if best is None else RunRound(best[1], best[0], routed)

"""The one improve step of a found path: lattice re-routing, then the path optimiser.

A fresh plan (:meth:`~.regrasp_search.RegraspSearch.run`) and a repaired route
(:func:`~.repair.polish`) are improved alike by :func:`improve`: the path's phases re-planned
on the held assembly's lattice (:func:`~.routes.refine.refine`, when ``config.optimiser.routes``
and a lattice is given), then the cheapest path over its waypoints
(:func:`~.optimiser.optimise`), then its regrasps free to slide along the transfers beside
them (:func:`~.regrasp_slide.slide_regrasps`, when ``config.optimiser.slide_regrasps``),
then its detours straightened (turn, straight push, turn:
:func:`~.straighten.straighten`, when ``config.optimiser.straighten``), then each phase
along the route bound's shortest route where that is cheaper
(:func:`~.follow_route.follow_route`, when ``config.optimiser.follow_route``), each step
within its :class:`Budget` of motion checks (the last three within the optimiser's) and the
same cost model (``config.cost``). The path optimiser, the slide and the straightening are
repeated while a round changes the path (at most :data:`ROUNDS`); the followed route runs in
the first round only. The grasp the robot holds the box with at the start
(``start_grasp``) is kept by every step.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.follow_route import follow_route
from pivot_ompl.planners.optimiser import optimise
from pivot_ompl.planners.regrasp_slide import slide_regrasps
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.refine import RefineStats, refine
from pivot_ompl.planners.straighten import straighten
from pivot_ompl.se2 import Pose

__all__ = ["ROUNDS", "Budget", "ImproveStats", "improve", "time_share"]

Stop = Callable[[], bool]
State = tuple[Pose, int]

#: Most rounds of the optimiser's stages: each stage moves the poses the others start from
#: (a slid regrasp, a straightened stretch, a followed route), so a round after one that
#: changed the path may find more; the rounds stop when one leaves the path as it was. The
#: followed route runs in the first only (again in later rounds: twice the hall's solve
#: time for 3 % of its cost).
ROUNDS = 3


@dataclass(frozen=True)
class Budget:
    """Motion checks (cache hits free) one step of :func:`improve` may compute.

    ``share`` x the checks computed before the step (a fresh plan's: a share of the search's
    work) plus ``per_state`` x the states of the path the step improves (a repair's), at
    least ``minimum``. Counts, not seconds: a seeded run improves its path alike on any
    machine (the time limit still stops it).
    """

    share: float = 0.0
    per_state: int = 0
    minimum: int = 0

    def stop(self, should_stop: Stop, checker: PivotChecker, states: Sequence[State]) -> Stop:
        """``should_stop``, or the budget spent by the checks computed from now on."""
        c = checker.counters
        start = c.valid + c.invalid
        limit = max(self.minimum, self.share * start + self.per_state * len(states))
        return lambda: should_stop() or (c.valid + c.invalid - start) > limit


def time_share(should_stop: Stop, share: float, limit: float | None) -> Stop:
    """``should_stop``, or ``share`` x ``limit`` seconds spent from now (``limit`` in s).

    The improvement of a fresh plan within its share of the solve's time limit
    (``optimiser.quality_share``); ``limit=None`` (not known): ``should_stop`` alone.
    """
    if limit is None:
        return should_stop
    end = time.perf_counter() + share * limit
    return lambda: should_stop() or time.perf_counter() >= end


@dataclass
class ImproveStats:
    """What the improve steps did (summed over calls).

    Attributes:
        refine: the lattice re-routing's figures.
        routes_seconds: time in the re-routing (s).
        seconds: time in both steps (s).
    """

    refine: RefineStats = field(default_factory=RefineStats)
    routes_seconds: float = 0.0
    seconds: float = 0.0


def improve(checker: PivotChecker, states: list[State], config: RegraspConfig, *,
            should_stop: Stop, routes: Budget, optimiser: Budget, start_grasp: int | None,
            end_grasp: int | None = None, lattice: TransferLattice | None = None,
            stats: ImproveStats | None = None) -> list[State]:
    """``states`` improved: valid, same ends, never costlier (see the module docstring).

    Args:
        checker: the checks of transfers and walks.
        states: a valid path of ``(object pose, grasp)`` states.
        config: the planner's configuration (``optimiser``, ``cost``, ``grasps``).
        should_stop: the termination condition.
        routes: the budget of the lattice re-routing.
        optimiser: the budget of the optimiser.
        start_grasp: the grasp the robot holds the box with (``states`` starts with it, and
            so does the result; a walk to another is priced); ``None``: any.
        end_grasp: the grasp the result must end with (a part of a longer path); ``None``:
            any.
        lattice: the lattice of the re-routing (``None``: no re-routing).
        stats: summed into, if given.
    """
    cfg = config.optimiser
    if not cfg.enabled:
        return states
    st = stats if stats is not None else ImproveStats()
    t0 = time.perf_counter()
    if cfg.routes and lattice is not None:
        states = refine(checker, lattice, states, costs=config.cost,
                        should_stop=routes.stop(should_stop, checker, states),
                        run_spacing=cfg.run_spacing, stats=st.refine,
                        start_grasp=start_grasp, grasps=config.grasps,
                        min_saving=cfg.route_min_saving,
                        whole_min_saving=cfg.whole_min_saving)
        st.routes_seconds += time.perf_counter() - t0
    for k in range(ROUNDS):
        before = list(states)
        states = _round(checker, states, config, should_stop=should_stop, budget=optimiser,
                        start_grasp=start_grasp, end_grasp=end_grasp, follow=k == 0)
        if states == before or should_stop():
            break
    st.seconds += time.perf_counter() - t0
    return states


def _round(checker: PivotChecker, states: list[State], config: RegraspConfig, *,
           should_stop: Stop, budget: Budget, start_grasp: int | None,
           end_grasp: int | None, follow: bool) -> list[State]:
    """One round of the optimiser's stages, each within ``budget``; never costlier.

    ``follow``: the followed route's stage too.
    """
    cfg = config.optimiser
    states = optimise(checker, states, should_stop=budget.stop(should_stop, checker, states),
                      costs=config.cost, grasps=config.grasps, start_grasp=start_grasp,
                      end_grasp=end_grasp, reach=cfg.shortcut_reach)
    if cfg.slide_regrasps:
        states = slide_regrasps(checker, states, costs=config.cost, grasps=config.grasps,
                                should_stop=budget.stop(should_stop, checker, states),
                                start_grasp=start_grasp, end_grasp=end_grasp)
    if cfg.straighten:
        states = straighten(checker, states, costs=config.cost,
                            should_stop=budget.stop(should_stop, checker, states))
    if cfg.follow_route and follow:
        states = follow_route(checker, states, costs=config.cost,
                              should_stop=budget.stop(should_stop, checker, states))
    return states

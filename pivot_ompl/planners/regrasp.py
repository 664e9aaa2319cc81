"""``RegraspPlanner``: the roadmap-multiplexing regrasp planner as an ``ompl.base.Planner``."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from ompl import base as ob

from pivot_ompl.base.state import read_state
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.expectation import Listener
from pivot_ompl.planners.guarded import GuardedPlanner, states_to_path
from pivot_ompl.planners.regrasp_search import RegraspSearch

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Resume:
    """What a (re)plan starts from, passed to :class:`RegraspPlanner` when it is made.

    Attributes:
        start_grasp: the grasp the robot holds the box with at the start: every path starts
            with it (other grasps at the start are reached by walks, priced and checked as
            any regrasp); ``None``: any valid grasp.
        search: an earlier search with the same checker and goal, whose roadmaps and caches
            serve again from the new start (replanning); ``None``: a new search.
    """

    start_grasp: int | None = None
    search: RegraspSearch | None = None


class RegraspPlanner(GuardedPlanner):
    """Visibility PRM on the box, manipulation and regrasping roadmaps multiplexed, diffusion.

    A thin adapter: the algorithm is :class:`~pivot_ompl.planners.regrasp_search.RegraspSearch`.
    The start is the problem's start state (its pose; every valid grasp is a start, or
    ``start_grasp`` alone when set: the robot holds the box with it); the goal must be a
    ``GoalState``/``GoalStates`` (their pose; every valid grasp is a goal). Calling
    ``solve`` again on the same query continues with the roadmaps and caches of the previous
    calls, and so does a query with a new start and the same goal (replanning, the
    obstacles unchanged); ``clear()`` forgets them.

    Args:
        si: the space information.
        checker: the validity core behind ``si``'s validators (``problem.checker`` of
            :func:`pivot_ompl.base.problem.make_setup`): the planner validates through it.
        seed: seed of the planner's generator (runs are deterministic for a seed).
        config: the planner's configuration (:class:`~pivot_ompl.planners.config.RegraspConfig`).
        name: the planner's name in OMPL (benchmark logs tell configurations apart by it).
        resume: the held grasp and the earlier search to continue (:class:`Resume`).

    Attributes:
        start_grasp: the grasp every path starts with (:attr:`Resume.start_grasp`).
        last_search: the search of the last ``solve`` (the one to resume first).
        solve_limit: the time limit (s) of the next ``solve``, when the caller knows it
            (:func:`pivot_ompl.api.plan` sets it): improving the path found then takes at
            most ``optimiser.quality_share`` of it; ``None``: only the termination
            condition stops the improvement.
        proof: polled by the search: whether "no plan" is proven (it then stops).
        expect: told the search's expected regrasps and their places once, as soon as known
            (:mod:`.expectation`; a plan's prover).
    """

    def __init__(self, si: ob.SpaceInformation, checker: PivotChecker, *, seed: int = 0,
                 config: RegraspConfig | None = None, name: str = "RegraspPlanner",
                 resume: Resume | None = None) -> None:
        """Create the planner."""
        super().__init__(si, name)
        r = resume or Resume()
        self.config = config or RegraspConfig()
        self.checker = checker
        self.seed = seed
        self.last_search: RegraspSearch | None = r.search
        self.start_grasp: int | None = r.start_grasp
        self.stats: dict[str, Any] = {}
        self.solve_limit: float | None = None
        self.proof: Callable[[], bool] | None = None
        self.expect: Listener | None = None

    def clear(self) -> None:  # noqa: D102
        super().clear()
        self.last_search = None

    def _solve(self, ptc: Any) -> ob.PlannerStatus:
        checker = self.checker
        start, goal = self._endpoints(ptc)
        s_pose, _ = read_state(start)
        g_pose, _ = read_state(goal)
        grasps = self.config.grasps
        held = self.start_grasp
        if not any(checker.state_valid(s_pose, g) for g in grasps if held in (None, g)):
            return ob.PlannerStatus(ob.PlannerStatus.INVALID_START)
        if not any(checker.state_valid(g_pose, g) for g in grasps):
            return ob.PlannerStatus(ob.PlannerStatus.INVALID_GOAL)
        t0 = time.perf_counter()
        search = self.last_search
        if search is None or search.goal != g_pose or search.checker is not checker:
            search = RegraspSearch(checker, s_pose, g_pose, self.config,
                                   np.random.default_rng(self.seed), start_grasp=held)
            self.last_search = search
        elif search.start != s_pose or search.start_grasp != held:
            # a new start: the roadmaps grown so far serve again
            search.restart(s_pose, lambda: bool(ptc()), start_grasp=held)
        # else: solving again continues with the same roadmaps and caches (OMPL semantics)
        if self.expect is not None:  # a search resumed has told its expectation before
            search.expected.listener = self.expect
            if search.expected.told:
                self.expect(None, ())
        proof = self.proof
        searching = None if proof is None else (lambda: bool(ptc()) or proof())
        states = search.run(lambda: bool(ptc()), limit=self.solve_limit, searching=searching)
        self.stats = asdict(search.stats)
        self.stats["time"] = time.perf_counter() - t0
        if not states:
            return ob.PlannerStatus(ob.PlannerStatus.TIMEOUT)
        states_to_path(self, states)
        return ob.PlannerStatus(ob.PlannerStatus.EXACT_SOLUTION)

"""``VisibilityPRM``: the visibility roadmap on the compound (object pose x grasp) space.

The same Visibility PRM as the regrasp planner's object roadmap
(:class:`~pivot_ompl.planners.objects.visibility.VisibilityRoadmap`), on compound states:
samples are uniform states, visibility is ``si.checkMotion``, and a sample is tested only
against guards of its grasp. A grasp change is possible only at one object pose, so each new
guard is also tried at the other grasps of its pose (a regrasp link), which keeps the planner
complete on regrasp problems. It samples until start and goal are connected or the
termination condition holds.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from ompl import base as ob

from pivot_ompl.base.state import read_state, write_state
from pivot_ompl.planners.evaluation import Status
from pivot_ompl.planners.guarded import GuardedPlanner, states_to_path
from pivot_ompl.planners.objects.roadmap import Roadmap
from pivot_ompl.planners.objects.visibility import VisibilityRoadmap
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]


class StateRoadmap:
    """A :class:`Roadmap` of compound states: the poses in the roadmap, the grasps beside."""

    def __init__(self) -> None:
        """An empty roadmap."""
        self.roadmap = Roadmap()
        self.grasps: list[int] = []

    def add(self, c: State, kind: str) -> int:
        """Add a node; return its index."""
        self.grasps.append(c[1])
        return self.roadmap.add(c[0], kind)

    def connect(self, i: int, j: int) -> None:
        """Add the edge ``i - j``."""
        self.roadmap.connect(i, j)

    def component(self, i: int) -> int:
        """Representative of ``i``'s component."""
        return self.roadmap.component(i)

    def __getitem__(self, i: int) -> State:
        """The state of node ``i``."""
        return self.roadmap.poses[i], self.grasps[i]


class VisibilityPRM(GuardedPlanner):
    """Visibility PRM on the compound space (see the module docstring).

    Args:
        si: the space information.
        seed: seed of the planner's own generator.
        max_failures: consecutive discarded samples counted as a finished roadmap (it keeps
            sampling until the termination condition; the count is reported).
    """

    def __init__(self, si: ob.SpaceInformation, *, seed: int = 0,
                 max_failures: int = 200) -> None:
        """Create the planner (``setup`` is called by OMPL)."""
        super().__init__(si, "VisibilityPRM")
        self.seed = seed
        self.max_failures = max_failures
        self.stats: dict[str, Any] = {}

    def _solve(self, ptc: Any) -> ob.PlannerStatus:
        si = self.getSpaceInformation()
        start, goal_state = self._endpoints(ptc)
        rng = np.random.default_rng(self.seed)
        bounds = si.getStateSpace().getSubspace(0).getBounds()
        lo, hi = bounds.low, bounds.high
        # a and b are never freed: nanobind keeps wrappers of freed addresses, and a state
        # allocated later at the same address would come back with a stale wrapper type
        a, b = si.allocState(), si.allocState()

        def valid(c: State) -> bool:
            write_state(a, *c)
            return bool(si.isValid(a))

        def sample(should_stop: Callable[[], bool]) -> State | None:
            while True:
                c = ((rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]),
                      rng.uniform(-np.pi, np.pi)), int(rng.integers(0, 4)))
                if valid(c):
                    return c
                if should_stop():  # a scene with little free space must not run past it
                    return None

        def visible(p: State, q: State, should_stop: Callable[[], bool]) -> Status:
            write_state(a, *p)
            write_state(b, *q)  # OMPL's motion check runs to its end: never stopped
            return Status.VALID if si.checkMotion(a, b) else Status.INVALID

        store = StateRoadmap()

        def same_grasp(q: State, guards: list[int]) -> Iterator[int]:
            return (g for g in list(guards) if store.grasps[g] == q[1])

        vis = VisibilityRoadmap(store, sample=sample, visible=visible, candidates=same_grasp,
                                max_failures=self.max_failures)
        s_i = vis.add_guard(read_state(start))
        g_i = vis.add_guard(read_state(goal_state))
        stop = lambda: bool(ptc())  # noqa: E731
        t0 = time.perf_counter()
        samples = 0
        while not stop() and store.component(s_i) != store.component(g_i):
            samples += 1
            kind, i = vis.step(stop)
            if kind == "stopped":
                break
            if kind == "guard":  # regrasp links at the guard's pose
                q, g = store[i]
                for g2 in range(4):
                    if g2 != g and valid((q, g2)) \
                            and visible((q, g), (q, g2), stop) is Status.VALID:
                        store.connect(i, vis.add_guard((q, g2)))
        self.stats = {"guards": len(vis.guards), "nodes": len(store.grasps),
                      "samples": samples, "failures": vis.failures,
                      "time": time.perf_counter() - t0}
        if store.component(s_i) != store.component(g_i):
            return ob.PlannerStatus(ob.PlannerStatus.TIMEOUT)
        states_to_path(self, [store[i] for i in store.roadmap.path(s_i, g_i)])
        return ob.PlannerStatus(ob.PlannerStatus.EXACT_SOLUTION)

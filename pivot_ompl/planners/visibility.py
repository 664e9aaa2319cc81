"""Visibility PRM (Simeon, Laumond and Nissoux 2000) as used in the regrasp paper, Section III.

A sample that sees no guard becomes a guard; one that sees guards of two or more connected
components becomes a connector linked to one guard of each; other samples are discarded.
Construction stops after ``max_failures`` consecutive discarded samples or at the
termination condition. :class:`VisibilityRoadmapBuilder` is the algorithm on any
configurations (the regrasp planner runs it on the box alone); :class:`VisibilityPRM` is the
``ompl.base.Planner`` on the compound space.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from ompl import base as ob

from pivot_ompl.base.state import read_state, write_state
from pivot_ompl.graph import UnionFind
from pivot_ompl.planners.guarded import GuardedPlanner, states_to_path
from pivot_ompl.planners.roadmap import Roadmap, pose_metric
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)


@dataclass
class VisibilityRoadmapBuilder:
    """Builds a visibility roadmap of object poses.

    Args:
        sample: draws a random valid configuration.
        visible: whether the local path between two configurations is valid; may also
            return extra nodes (critical configurations) through ``on_blocked``.
        max_failures: consecutive discarded samples before stopping.
        guard_radius: guards farther than this (m, in the pose metric) are not tested.
    """

    sample: Callable[[], Pose]
    visible: Callable[[Pose, Pose], bool]
    max_failures: int = 40
    guard_radius: float = 3.0
    roadmap: Roadmap = field(default_factory=Roadmap)
    guards: list[int] = field(default_factory=list)
    failures: int = 0

    def add_guard(self, pose: Pose, kind: str = "guard") -> int:
        """Add a node that always becomes a guard (start and goal)."""
        i = self.roadmap.add(pose, kind)
        self.guards.append(i)
        return i

    def step(self) -> str:
        """One sample: returns ``"guard"``, ``"connector"`` or ``"discarded"``."""
        q = self.sample()
        rm = self.roadmap
        seen: dict[int, int] = {}  # component -> guard seen
        near = rm.nearest(q, len(self.guards), among=self.guards)
        dist: np.ndarray | list[float] = (
            pose_metric(np.array([rm.poses[g] for g in near]), q) if near else [])
        for g, d in zip(near, dist, strict=False):
            if d > self.guard_radius:
                break
            comp = rm.component(g)
            if comp in seen:
                continue
            if self.visible(rm.poses[g], q):
                seen[comp] = g
        if not seen:
            self.add_guard(q)
            self.failures = 0
            return "guard"
        if len(seen) >= 2:
            i = rm.add(q, "connector")
            for g in seen.values():
                rm.connect(g, i)
            self.failures = 0
            return "connector"
        self.failures += 1
        return "discarded"

    def build(self, until: Callable[[], bool]) -> None:
        """Sample until ``max_failures`` consecutive discards or ``until()`` is true."""
        while self.failures < self.max_failures and not until():
            self.step()


class VisibilityPRM(GuardedPlanner):
    """Visibility PRM on the compound (object pose x grasp) space.

    Samples are uniform compound states; visibility is ``si.checkMotion``. A grasp change
    is only possible at equal object poses, so each guard is also tried at the other grasps
    of its pose (a regrasp link), which keeps the planner complete on regrasp problems.

    Args:
        si: the space information.
        seed: seed of the planner's own generator.
        max_failures: consecutive discarded samples before the roadmap is considered done
            (the planner then keeps sampling until the termination condition).
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
        space = si.getStateSpace()
        rs = space.getSubspace(0)
        lo, hi = rs.getBounds().low, rs.getBounds().high
        a, b = si.allocState(), si.allocState()

        def sample() -> tuple[Pose, int] | None:
            """A valid sample, or ``None`` once the termination condition holds."""
            while True:
                q = (rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]),
                     rng.uniform(-np.pi, np.pi))
                g = int(rng.integers(0, 4))
                write_state(a, q, g)
                if si.isValid(a):
                    return q, g
                if ptc():  # a scene with little free space must not run past the limit
                    return None

        def visible(p: tuple[Pose, int], q: tuple[Pose, int]) -> bool:
            write_state(a, *p)
            write_state(b, *q)
            return si.checkMotion(a, b)

        nodes: list[tuple[Pose, int]] = []
        comp: UnionFind[int] = UnionFind()
        edges: dict[int, list[int]] = {}
        find = comp.find

        def add(node: tuple[Pose, int]) -> int:
            i = len(nodes)
            nodes.append(node)
            comp.add(i)
            edges[i] = []
            return i

        def link(i: int, j: int) -> None:
            edges[i].append(j)
            edges[j].append(i)
            comp.union(i, j)

        guards: list[int] = []
        s_i = add(read_state(start))
        g_i = add(read_state(goal_state))
        guards += [s_i, g_i]
        t0 = time.perf_counter()
        failures = 0
        n_samples = 0
        while not ptc() and find(s_i) != find(g_i):
            n_samples += 1
            q = sample()
            if q is None:
                break
            seen: dict[int, int] = {}
            for gd in guards:
                if ptc():
                    break
                c = find(gd)
                if c in seen or nodes[gd][1] != q[1]:
                    continue
                if visible(nodes[gd], q):
                    seen[c] = gd
            if not seen:
                i = add(q)
                guards.append(i)
                failures = 0
                for g2 in range(4):  # regrasp links at the guard's pose
                    if g2 == q[1]:
                        continue
                    write_state(b, q[0], g2)
                    if si.isValid(b) and visible(q, (q[0], g2)):
                        j = add((q[0], g2))
                        guards.append(j)
                        link(i, j)
            elif len(seen) >= 2:
                i = add(q)
                for gd in seen.values():
                    link(gd, i)
                failures = 0
            else:
                failures += 1
        # a and b are not freed: nanobind keeps wrappers of freed addresses, and a state
        # allocated later at the same address would come back with a stale wrapper type
        self.stats = {"guards": len(guards), "nodes": len(nodes), "samples": n_samples,
                      "time": time.perf_counter() - t0}
        if find(s_i) != find(g_i):
            return ob.PlannerStatus(ob.PlannerStatus.TIMEOUT)
        path = _bfs(edges, s_i, g_i)
        states_to_path(self, [nodes[i] for i in path])
        return ob.PlannerStatus(ob.PlannerStatus.EXACT_SOLUTION)


def _bfs(edges: dict[int, list[int]], s: int, g: int) -> list[int]:
    parent = {s: s}
    frontier = [s]
    while frontier:
        nxt = []
        for i in frontier:
            for j in edges[i]:
                if j not in parent:
                    parent[j] = i
                    nxt.append(j)
        frontier = nxt
    path = [g]
    while path[-1] != s:
        path.append(parent[path[-1]])
    return path[::-1]

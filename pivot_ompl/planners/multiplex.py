"""Roadmap multiplexing (the regrasp paper, Section IV) as a pure-Python search.

One manipulation roadmap per grasp (box and robot move together) plus the regrasping
roadmap (the robot walks alone between grasps of the resting box) are multiplexed into one
graph whose nodes are ``(object pose, grasp)``. Nodes come from the object roadmap (the
Visibility PRM on the box alone, with its critical configurations) through
``PlanWithObjectConfig``, then from a diffusion process (random sample, nearest object node,
extend by ``epsilon``). Edges are candidates until a shortest path uses them: only then are
they validated (pivot sequences and walks are the expensive part), so the search is lazy.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.graph import UnionFind, astar
from pivot_ompl.planners.optimiser import budgeted, optimise
from pivot_ompl.planners.roadmap import Roadmap, pose_metric
from pivot_ompl.planners.visibility import VisibilityRoadmapBuilder
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.pivot_checker import PivotChecker

log = logging.getLogger(__name__)

Node = tuple[int, int]  # (object roadmap index, grasp)


@dataclass(frozen=True)
class RegraspParams:
    """Parameters of the regrasp planner (typed, with units).

    Attributes:
        epsilon: diffusion extension step (m, in the pose metric).
        guard_failures: consecutive discarded samples that end the Visibility PRM.
        grasps: the grasps the robot may use.
        regrasp_cost: cost of one regrasp on top of the walking distance (m).
        neighbours: candidate edges per new manipulation node.
        connect_radius: candidate edges are not longer than this (m, pose metric).
        critical_bias: probability that a diffusion sample is drawn near a critical
            configuration.
        goal_bias: probability that a diffusion sample is the goal pose.
        optimise: run the path optimiser (shortcuts and useless-regrasp removal).
        critical_spacing: a critical configuration closer than this (m, pose metric) to a
            recorded one is not recorded again.
        max_visibility_samples: samples of the Visibility PRM phase at most, before the
            diffusion phase.
        bridge_bias: probability that a diffusion iteration is a bridge test instead.
        bridge_sigma: standard deviation (m) of the bridge test's second sample.
        bridge_rounds: rounds of (up to 100) bridge tests before the diffusion.
        search_every: the diffusion searches after this many new manipulation nodes.
        passage_steps: distances (m) of the straight extensions from a passage node.
    """

    epsilon: float = 1.0
    guard_failures: int = 25
    grasps: tuple[int, ...] = (0, 1, 2, 3)
    regrasp_cost: float = 2.0
    neighbours: int = 10
    connect_radius: float = 3.5
    critical_bias: float = 0.25
    goal_bias: float = 0.05
    optimise: bool = True
    critical_spacing: float = 0.4
    bridge_bias: float = 0.3
    bridge_rounds: int = 60
    search_every: int = 8
    bridge_sigma: float = 0.5
    passage_steps: tuple[float, ...] = (0.5, 1.0, 1.5, 2.0)
    max_visibility_samples: int = 30


@dataclass
class RegraspStats:
    """Figures of one run (roadmap sizes and counts)."""

    object_nodes: int = 0
    guards: int = 0
    connectors: int = 0
    critical: int = 0
    diffusion_nodes: int = 0
    passage_nodes: int = 0
    manipulation_nodes: dict[int, int] = field(default_factory=dict)
    regrasp_edges: int = 0
    searches: int = 0
    edges_checked: int = 0
    edges_invalid: int = 0
    time_visibility: float = 0.0
    time_search: float = 0.0
    time_optimise: float = 0.0


@dataclass
class MultiplexedSearch:
    """The regrasp planner's data and algorithm (see the module docstring).

    Args:
        checker: validity of states, pivot edges and walks.
        start, goal: object poses.
        params: planner parameters.
        rng: random generator (the only source of randomness).
    """

    checker: PivotChecker
    start: Pose
    goal: Pose
    params: RegraspParams
    rng: np.random.Generator
    stats: RegraspStats = field(default_factory=RegraspStats)

    def __post_init__(self) -> None:
        """Create the object roadmap and the multiplexed graph."""
        self.obj = Roadmap()
        self.adj: dict[Node, dict[Node, float]] = {}
        self._uf: UnionFind[Node] = UnionFind()  # over candidate edges (never split)
        self.by_grasp: dict[int, list[int]] = {g: [] for g in self.params.grasps}
        self.verified: dict[tuple[Node, Node], bool] = {}
        self.critical: list[int] = []
        b = self.checker.world.bounds
        self._lo = (b[0], b[1])
        self._hi = (b[2], b[3])
        self.start_nodes: list[Node] = []
        self.goal_nodes: set[Node] = set()

    # -- object roadmap --------------------------------------------------------------------
    def _random_pose(self) -> Pose:
        return (float(self.rng.uniform(self._lo[0], self._hi[0])),
                float(self.rng.uniform(self._lo[1], self._hi[1])),
                float(self.rng.uniform(-math.pi, math.pi)))

    def _sample_box_valid(self) -> Pose:
        for _ in range(1000):
            q = self._random_pose()
            if self.checker.box_valid(q):
                return q
        return self._random_pose()

    def _visible(self, a: Pose, b: Pose) -> bool:
        """Object-roadmap visibility: the box alone can pivot along the edge.

        Critical configurations (where the robot's bounding volume starts or stops colliding
        along the edge) are recorded.
        """
        edge = self.checker.transfer(a, b, 0, with_robot=False)
        if not edge.valid:
            return False
        self._record_critical(edge.sequence)
        return True

    def _record_critical(self, seq) -> None:
        ck, m = self.checker, self.checker.model
        poses = [m.object_from_car(r.car, 0) for r in seq.rotations]
        if len(poses) < 2:
            return
        for g in self.params.grasps:
            free = [ck.robot_valid(p, g) for p in poses]
            for i in range(1, len(poses)):
                if free[i] != free[i - 1]:
                    q = poses[i - 1] if free[i - 1] else poses[i]
                    near = self.obj.nearest(q, 1, among=self.critical)
                    if near and pose_metric(np.array([self.obj.poses[near[0]]]), q)[0] < \
                            self.params.critical_spacing:
                        continue
                    idx = self.obj.add(q, "critical")
                    self.critical.append(idx)

    # -- multiplexed graph ------------------------------------------------------------------
    def _add_node(self, node: Node) -> None:
        if node not in self.adj:
            self.adj[node] = {}
            self._uf.add(node)

    def _link(self, a: Node, b: Node, cost: float) -> None:
        if (a, b) in self.verified and not self.verified[(a, b)]:
            return
        self.adj[a][b] = cost
        self.adj[b][a] = cost
        self._uf.union(a, b)

    def _maybe_connected(self) -> bool:
        """Whether start and goal share a component of the candidate graph.

        Edges are only removed later, so this is a sound filter: no component, no path.
        """
        goals = {self._uf.find(g) for g in self.goal_nodes}
        return any(self._uf.find(s) in goals for s in self.start_nodes)

    def plan_with_object_config(self, i: int) -> int:
        """Add object node ``i`` to every manipulation roadmap where it is valid.

        Returns the number of manipulation nodes added.
        """
        q = self.obj.poses[i]
        ck, p = self.checker, self.params
        rs = ck.steering.rs
        m = ck.model
        added: list[int] = []
        for g in p.grasps:
            if not ck.state_valid(q, g):
                continue
            node = (i, g)
            self._add_node(node)
            car = m.car_pose(q, g)
            for j in self.obj.nearest(q, p.neighbours, among=self.by_grasp[g]):
                qj = self.obj.poses[j]
                carj = m.car_pose(qj, g)
                d = rs.distance(car, carj)
                if d <= p.connect_radius and self._plausible(car, carj, g):
                    self._link(node, (j, g), d)
            self.by_grasp[g].append(i)
            added.append(g)
        # regrasping roadmap: the robot walks between the valid grasps at this pose
        for a_i, a in enumerate(added):
            for b in added[a_i + 1:]:
                walk_est = m.robot_offset(a) * 0.5 * math.pi * min((b - a) % 4, (a - b) % 4)
                self._link((i, a), (i, b), p.regrasp_cost + walk_est)
                self.stats.regrasp_edges += 1
        return len(added)

    def _plausible(self, car_a: Pose, car_b: Pose, grasp: int) -> bool:
        """Cheap necessary test of a candidate edge.

        The box and robot are free at a few poses along its Reeds-Shepp path (the full pivot
        check is left to the lazy search).
        """
        ck, m = self.checker, self.checker.model
        for c in ck.steering.rs.sample(car_a, car_b, [0.25, 0.5, 0.75]):
            if not ck.state_valid(m.object_from_car(c, grasp), grasp):
                return False
        return True

    def _edge_valid(self, a: Node, b: Node) -> bool:
        key = (a, b) if a <= b else (b, a)
        v = self.verified.get(key)
        if v is not None:
            return v
        pa, pb = self.obj.poses[a[0]], self.obj.poses[b[0]]
        if a[1] == b[1]:
            v = self.checker.transfer(pa, pb, a[1]).valid
        else:
            walk = self.checker.transit(pa, a[1], b[1])
            v = walk.valid
            if v:  # the real walking cost replaces the estimate
                cost = self.params.regrasp_cost + walk.cost
                self.adj[a][b] = self.adj[b][a] = cost
        self.verified[key] = v
        self.stats.edges_checked += 1
        if not v:
            self.stats.edges_invalid += 1
        return v

    def search(self, ptc: Callable[[], bool]) -> list[Node]:
        """Lazy shortest path from a start node to a goal node; ``[]`` if none yet."""
        if not self._maybe_connected():
            return []
        t0 = time.perf_counter()
        try:
            while not ptc():
                self.stats.searches += 1
                path = self._shortest_path()
                if not path:
                    return []
                # validate every transfer edge of the path (so one search removes all its bad
                # transfers), then the walks, which cost more, only if the transfers hold
                pairs = list(zip(path, path[1:], strict=False))
                ok = True
                for walks in (False, True):
                    for a, b in pairs:
                        if (a[1] != b[1]) != walks:
                            continue
                        if ptc():
                            return []
                        if not self._edge_valid(a, b):
                            self.adj[a].pop(b, None)
                            self.adj[b].pop(a, None)
                            ok = False
                            if walks:
                                break
                    if not ok:
                        break
                if ok:
                    return path
            return []
        finally:
            self.stats.time_search += time.perf_counter() - t0

    def _shortest_path(self) -> list[Node]:
        """A* over the multiplexed graph.

        Heuristic: straight distance of the box to the goal less the largest car offset (a
        transfer edge is at least that long).
        """
        poses = self.obj.poses
        gx, gy = self.goal[0], self.goal[1]
        slack = max(self.checker.model.object_size[:2])

        def h(n: Node) -> float:
            q = poses[n[0]]
            return max(0.0, math.hypot(q[0] - gx, q[1] - gy) - slack)

        return astar(self.start_nodes, self.goal_nodes, lambda u: self.adj[u].items(), h)

    # -- the algorithm (Fig. 7 of the paper) -------------------------------------------------
    def run(self, ptc: Callable[[], bool]) -> list[tuple[Pose, int]]:
        """Plan; return the path as ``(object pose, grasp)`` states, ``[]`` on time-out."""
        p, ck = self.params, self.checker
        s_i = self.obj.add(self.start, "start")
        g_i = self.obj.add(self.goal, "goal")
        t0 = time.perf_counter()
        vis = VisibilityRoadmapBuilder(self._sample_box_valid, self._visible,
                                       max_failures=p.guard_failures, roadmap=self.obj)
        vis.guards.extend([s_i, g_i])
        for i in (s_i, g_i):
            self.plan_with_object_config(i)
        self.start_nodes = [n for n in self.adj if n[0] == s_i]
        self.goal_nodes = {n for n in self.adj if n[0] == g_i}
        m = ck.model
        for (_, g) in self.start_nodes:  # always try the direct edge first
            if (g_i, g) in self.goal_nodes:
                d = ck.steering.rs.distance(m.car_pose(self.start, g), m.car_pose(self.goal, g))
                self._link((s_i, g), (g_i, g), d)
        path = self.search(ptc)
        if not path:
            done = 2
            n = 0
            while not ptc() and vis.failures < p.guard_failures and \
                    n < p.max_visibility_samples:
                n += 1
                vis.step()
                for i in range(done, len(self.obj)):
                    self.plan_with_object_config(i)
                done = len(self.obj)
            self.stats.time_visibility = time.perf_counter() - t0
            path = self.search(ptc)
            # diffusion: grow the object roadmap towards random samples
            # passage phase: cheap bridge tests before the diffusion
            for _ in range(p.bridge_rounds):
                if path or ptc():
                    break
                path = self._bridge_step(ptc)
            since = 0
            while not path and not ptc():
                if self.rng.uniform() < p.bridge_bias:
                    path = self._bridge_step(ptc)
                    continue
                q = self._diffusion_target()
                near = self.obj.nearest(q, 1)[0]
                qn = self._extend(self.obj.poses[near], q)
                if qn == self.obj.poses[near]:
                    continue
                i = self.obj.add(qn, "diffusion")
                self.stats.diffusion_nodes += 1
                since += self.plan_with_object_config(i) > 0
                if since >= p.search_every:
                    since = 0
                    path = self.search(ptc)
        self._fill_stats()
        if not path:
            return []
        states = [(self.obj.poses[i], g) for i, g in path]
        if p.optimise:
            t1 = time.perf_counter()
            states = optimise(ck, states, grasps=p.grasps,
                              should_stop=budgeted(ptc, ck))
            self.stats.time_optimise = time.perf_counter() - t1
        return states

    def _bridge_step(self, ptc: Callable[[], bool], attempts: int = 100) -> list[Node]:
        """Bridge tests for narrow passages.

        Two box poses (same yaw) in collision whose midpoint is free give a passage node;
        straight extensions along the box's axes from it (the directions in which each grasp's
        car drives straight) give aligned approach nodes. Runs up to ``attempts`` cheap tests,
        adds the first passage found.
        """
        ck, p = self.checker, self.params
        w = ck.world
        for _ in range(attempts):
            q1 = self._random_pose()
            if not w.box_in_bounds(q1) or w.box_distance(q1) > 0:
                continue
            q2 = (q1[0] + float(self.rng.normal(0, p.bridge_sigma)),
                  q1[1] + float(self.rng.normal(0, p.bridge_sigma)), q1[2])
            if not w.box_in_bounds(q2) or w.box_distance(q2) > 0:
                continue
            mid = (0.5 * (q1[0] + q2[0]), 0.5 * (q1[1] + q2[1]), q1[2])
            if ck.box_valid(mid):
                break
        else:
            return []
        self.stats.passage_nodes += 1
        new = [self.obj.add(mid, "passage")]
        for k in range(4):
            a = mid[2] + k * 0.5 * math.pi
            for d in p.passage_steps:
                q = (mid[0] + d * math.cos(a), mid[1] + d * math.sin(a), mid[2])
                if not ck.box_valid(q):
                    break
                new.append(self.obj.add(q, "passage"))
        added = 0
        for i in new:
            added += self.plan_with_object_config(i)
        return self.search(ptc) if added else []

    def _diffusion_target(self) -> Pose:
        u = self.rng.uniform()
        if u < self.params.goal_bias:
            return self.goal
        if u < self.params.goal_bias + self.params.critical_bias and self.critical:
            c = self.obj.poses[self.critical[int(self.rng.integers(len(self.critical)))]]
            return (c[0] + float(self.rng.normal(0, 0.3)), c[1] + float(self.rng.normal(0, 0.3)),
                    c[2] + float(self.rng.normal(0, 0.5)))
        return self._random_pose()

    def _extend(self, near: Pose, target: Pose) -> Pose:
        """Move from ``near`` towards ``target`` along the object's Reeds-Shepp path.

        Moves by at most ``epsilon``, stopping at the last box-valid pose (sampled every 5 cm):
        the diffusion creeps into narrow passages instead of jumping over them.
        """
        rs = self.checker.steering.rs
        d = rs.distance(near, target)
        if d == 0.0:
            return near
        reach = min(1.0, self.params.epsilon / d)
        n = max(1, int(reach * d / 0.05))
        last = near
        for q in rs.sample(near, target, [reach * (k + 1) / n for k in range(n)]):
            if not self.checker.box_valid(q):
                break
            last = q
        return last

    def _fill_stats(self) -> None:
        s = self.stats
        kinds = self.obj.kinds
        s.object_nodes = len(self.obj)
        s.guards = kinds.count("guard") + 2
        s.connectors = kinds.count("connector")
        s.critical = kinds.count("critical")
        s.manipulation_nodes = {g: len(v) for g, v in self.by_grasp.items()}

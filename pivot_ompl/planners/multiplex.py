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

import heapq
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import UnionFind
from pivot_ompl.planners.optimiser import budgeted, optimise
from pivot_ompl.planners.passages import find_passages, passage_poses
from pivot_ompl.planners.roadmap import Roadmap, canonical, half_turn, pose_metric
from pivot_ompl.planners.single_grasp import SingleGraspConnect
from pivot_ompl.planners.visibility import VisibilityRoadmapBuilder
from pivot_ompl.se2 import Pose, wrap_angle

log = logging.getLogger(__name__)

Node = tuple[int, int]  # (object roadmap index, grasp)



def _key(a: Node, b: Node) -> tuple[Node, Node]:
    """The undirected key of edge ``a - b``."""
    return (a, b) if a <= b else (b, a)


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
        search_every: the diffusion searches after this many new manipulation nodes (a
            search is skipped at no cost while the candidate graph cannot join start and goal).
        passage_steps: distances (m) of the extensions from a passage node.
        single_grasp_checks: motion checks (transfer edges) of the single-grasp
            RRT-Connect tried before the multiplexed search
            (:mod:`pivot_ompl.planners.single_grasp`), shared by the grasps valid at both
            start and goal; ``0``: not tried.
        single_grasp_step: its longest extension (m).
        slot_seeds: seed the object roadmap with box poses along the scene's slots
            (:mod:`pivot_ompl.planners.passages`): gaps between obstacles wide enough for
            the box but narrower than the walking robot (its least width and the kept
            clearance on both sides, plus ``slot_play``), where it must let go of the box.
        slot_play: the play (m) beyond which a gap no longer counts as a slot: the walking
            robot's lattice passes a gap only with some play.
        slot_spacing: spacing (m) of the seeded poses along a slot (each is multiplexed with
            its grasps and regrasps: at 0.1 m fig10's two slots gave 40 % of the roadmap's
            nodes; 0.2 m halves them, plans as short, runs ~10 % faster).
        slot_approach: distances (m) beyond the slot's ends (and the box's length) of the
            seeded poses from which the box is pushed in or pulled out.
        search_weight: inflation of the graph search's heuristic (weighted A*: a path at
            most this factor costlier than the graph's shortest, found expanding far fewer
            nodes; the path optimiser shortens it afterwards).
        eager_filter: test a candidate edge's plausibility (box and robot free at three
            poses of its Reeds-Shepp path) when it is inserted; otherwise (the default)
            only when the lazy A* pops it (:meth:`MultiplexedSearch._shortest_path`).
        passage_mode: ``"box"``: passage nodes keep the bridge test's random yaw and are
            extended along the box's axes; ``"geometry"``: the passage's direction is taken
            across the line joining the two colliding samples, the box turned along and
            across it. Neither depends on the world's axes.
        yaw_range: sampled yaws lie in ``[-yaw_range, yaw_range)``. Whatever the range,
            neighbours are found with yaw modulo pi and linked to the grasp of the same
            physical state (yaw ``t`` with grasp ``k`` = yaw ``t + pi`` with ``k + 2``);
            ``pi/2`` also samples only one yaw of each pair (measured: more needless
            regrasps and slower on fig10 than ``pi``).
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
    search_every: int = 16
    eager_filter: bool = False
    passage_mode: str = "box"
    yaw_range: float = math.pi
    bridge_sigma: float = 0.5
    passage_steps: tuple[float, ...] = (0.5, 1.0, 1.5, 2.0)
    max_visibility_samples: int = 30
    search_weight: float = 2.0
    single_grasp_checks: int = 80
    single_grasp_step: float = 1.5
    slot_seeds: bool = True
    slot_play: float = 0.1
    slot_spacing: float = 0.2
    slot_approach: tuple[float, ...] = (0.4, 0.7, 1.2)


@dataclass
class RegraspStats:
    """Figures of one run (roadmap sizes and counts)."""

    object_nodes: int = 0
    guards: int = 0
    connectors: int = 0
    critical: int = 0
    diffusion_nodes: int = 0
    passage_nodes: int = 0
    slots: int = 0
    slot_nodes: int = 0
    manipulation_nodes: dict[int, int] = field(default_factory=dict)
    regrasp_edges: int = 0
    searches: int = 0
    edges_checked: int = 0
    plausibility_tests: int = 0
    edges_invalid: int = 0
    single_grasp_checks: int = 0
    single_grasp_solved: bool = False
    time_single_grasp: float = 0.0
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
        #: object nodes where grasp 0 or 2 (index 0), 1 or 3 (index 1) is valid
        self._parity: tuple[list[int], list[int]] = ([], [])
        #: edges found invalid (undirected; ``False``): never linked again
        self.verified: dict[tuple[Node, Node], bool] = {}
        #: checked valid, as the plan writes them: ``(state, state)`` in path order
        self._valid: set[tuple[tuple[Pose, int], tuple[Pose, int]]] = set()
        #: results of the cheap test of transfer edges (:meth:`_plausible_edge`)
        self._plausibility: dict[tuple[Node, Node], bool] = {}
        self.critical: list[int] = []
        b = self.checker.world.bounds
        self._lo = (b[0], b[1])
        self._hi = (b[2], b[3])
        self.start_nodes: list[Node] = []
        self.goal_nodes: set[Node] = set()
        #: States ``(node, frame parity)`` that may be reached from the start nodes over
        #: edges that passed the cheap test (a superset after full checks remove edges),
        #: ``None`` before the start and goal nodes exist or after the termination condition
        #: stopped its growth (then a failed search computes it again).
        self._reach: set[tuple[Node, int]] | None = None
        self._vis: VisibilityRoadmapBuilder | None = None
        self._done = 0  # object nodes already added to the manipulation roadmaps
        self._h: dict[int, float] = {}  # A* heuristic per object node
        self._since = 0

    # -- object roadmap --------------------------------------------------------------------
    def _random_pose(self) -> Pose:
        """A uniform pose; yaw in ``[-yaw_range, yaw_range)``."""
        return (float(self.rng.uniform(self._lo[0], self._hi[0])),
                float(self.rng.uniform(self._lo[1], self._hi[1])),
                float(self.rng.uniform(-self.params.yaw_range, self.params.yaw_range)))

    def _sample_box_valid(self) -> Pose:
        stop = self.checker.should_stop
        for k in range(1000):
            if stop is not None and k % 50 == 49 and stop():
                break
            q = self._random_pose()
            if self.checker.box_valid(q):
                return q
        return self._random_pose()

    def _visible(self, a: Pose, b: Pose) -> bool:
        """Object-roadmap visibility: the box alone can pivot along the edge.

        Critical configurations (where the robot's bounding volume starts or stops colliding
        along the edge) are recorded. The box's cheap test along the path runs first.
        """
        ck = self.checker
        if not ck.path_free(a, b, 0, with_robot=False):
            return False
        edge = ck.transfer(a, b, 0, with_robot=False)
        if not edge.valid:
            return False
        self._record_critical(edge.sequence)
        return True

    def _record_critical(self, seq) -> None:
        ck, m = self.checker, self.checker.model
        poses = [canonical(m.object_from_car(r.car, 0)) for r in seq.rotations]
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
        key = (a, b) if a <= b else (b, a)
        if self.verified.get(key) is False:
            return
        self.adj[a][b] = cost
        self.adj[b][a] = cost
        self._uf.union(a, b)
        r = self._reach
        if r is None:
            return
        flip = int(a[0] != b[0] and a[1] != b[1])
        for parity in (0, 1):
            sa, sb = (a, parity), (b, parity ^ flip)
            if (sa in r) == (sb in r):
                continue
            if a[0] != b[0] and not self._plausible_edge(a, b):
                return
            self._grow_reach(sb if sa in r else sa)
            if self._reach is None:
                return

    def _grow_reach(self, state: tuple[Node, int]) -> None:
        """Add ``state`` and the states joined to it by plausible edges to the reachable set.

        Each transfer edge that would add a state is tested first (the cheap test, cached):
        the set is the component of the start over the edges that survive that test.
        """
        reach = self._reach
        assert reach is not None
        stack = [state]
        reach.add(state)
        stop = self.checker.should_stop
        steps = 0
        while stack:
            steps += 1
            if stop is not None and steps % 64 == 1 and stop():
                self._reach = None  # incomplete: forgotten (computed again after a search)
                return
            n, parity = stack.pop()
            for v in list(self.adj[n]):
                transfer = v[0] != n[0]
                sv = (v, parity ^ int(transfer and v[1] != n[1]))
                if sv in reach or (transfer and not self._plausible_edge(n, v)):
                    continue
                reach.add(sv)
                stack.append(sv)

    def _compute_reach(self) -> None:
        """The states ``(node, frame parity)`` connected to a start over surviving edges."""
        self._reach = set()
        for s in self.start_nodes:
            if self._reach is None:  # stopped by the termination condition
                return
            if (s, 0) not in self._reach:
                self._grow_reach((s, 0))

    def _maybe_connected(self) -> bool:
        """Whether the goal (in the start's frame) may be reached from the start.

        Two sound filters: the union-find over every candidate edge ever added, and the set
        of states reachable from the start over the edges that passed the cheap test (kept
        up to date as edges are added; edges refused later by a full check only shrink the
        truth, so it is computed again when a search fails). A search that cannot succeed
        is skipped.
        """
        r = self._reach
        if r is not None and not any((g, 0) in r for g in self.goal_nodes):
            return False
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
            # neighbours in pose (yaw modulo pi): node j's yaw is within pi/2 of q's or its
            # half-turn is, and then the same physical state is (j, g + 2)
            for j in self.obj.nearest(q, p.neighbours, among=self._parity[g % 2]):
                qj = self.obj.poses[j]
                gj = g if abs(wrap_angle(qj[2] - q[2])) <= 0.5 * math.pi else (g + 2) % 4
                if (j, gj) not in self.adj:
                    continue
                carj = m.car_pose(qj, gj)
                d = rs.distance(car, carj)
                if d <= p.connect_radius and (not p.eager_filter
                                              or self._plausible_edge(node, (j, gj))):
                    self._link(node, (j, gj), d)
            self.by_grasp[g].append(i)
            added.append(g)
        for parity in {g % 2 for g in added}:
            self._parity[parity].append(i)
        # regrasping roadmap: the robot walks between the valid grasps at this pose
        for a_i, a in enumerate(added):
            for b in added[a_i + 1:]:
                walk_est = m.robot_offset(a) * 0.5 * math.pi * min((b - a) % 4, (a - b) % 4)
                self._link((i, a), (i, b), p.regrasp_cost + walk_est)
                self.stats.regrasp_edges += 1
        return len(added)

    def _plausible(self, car_a: Pose, car_b: Pose, grasp: int) -> bool:
        """Cheap necessary test of a candidate edge, run first when the lazy search checks it.

        The box and robot are free at a few poses along its Reeds-Shepp path.
        """
        return self.checker.cars_free(car_a, car_b, grasp, (0.25, 0.5, 0.75))

    def _plausible_edge(self, a: Node, b: Node) -> bool:
        """The cheap test of transfer edge ``a - b`` (cached); an implausible edge is dropped.

        ``(j, g + 2)`` is the same car as ``(j's half turn, g)``.
        """
        key = _key(a, b)
        v = self._plausibility.get(key)
        if v is None:
            m = self.checker.model
            pa, pb = self.obj.poses[a[0]], self.obj.poses[b[0]]
            pb = pb if a[1] == b[1] else half_turn(pb)
            v = self._plausibility[key] = self._plausible(m.car_pose(pa, a[1]),
                                                          m.car_pose(pb, a[1]), a[1])
            self.stats.plausibility_tests += 1
            if not v:
                self._drop(a, b)
        return v

    def _drop(self, a: Node, b: Node) -> None:
        """Remove edge ``a - b`` for good (never linked again)."""
        self.adj[a].pop(b, None)
        self.adj[b].pop(a, None)
        self.verified[_key(a, b)] = False

    def _edge_valid(self, a: Node, b: Node, sa: tuple[Pose, int], sb: tuple[Pose, int]) -> bool:
        """Check the edge ``a -> b`` of a path, written as the states ``sa -> sb``.

        The edge is checked exactly as the plan will hold it (the path's frame and
        direction, :meth:`_express`): a pivot sequence depends on its direction, and a pose
        and its half turn differ by round-off, which can change the Reeds-Shepp path. An
        invalid edge is refused in every frame and direction (a conservative choice).
        """
        key = (a, b) if a <= b else (b, a)
        if self.verified.get(key) is False:
            return False
        if (sa, sb) in self._valid:
            return True
        (pa, ga), (pb, gb) = sa, sb
        ck = self.checker
        if a[0] != b[0]:  # a transfer
            v = self._plausible_edge(a, b) and ck.transfer(pa, pb, ga).valid
        else:
            walk = ck.transit(pa, ga, gb)
            v = walk.valid
            if v:  # the real walking cost replaces the estimate
                cost = self.params.regrasp_cost + walk.cost
                self.adj[a][b] = self.adj[b][a] = cost
        if v:
            self._valid.add((sa, sb))
        else:
            self.verified[key] = False
        self.stats.edges_checked += 1
        if not v:
            self.stats.edges_invalid += 1
        return v

    def search(self, ptc: Callable[[], bool], *, transfers_only: bool = False) -> list[Node]:
        """Lazy shortest path from a start node to a goal node; ``[]`` if none yet.

        With ``transfers_only``, regrasp edges are not used (one grasp all the way).
        """
        if not self._maybe_connected():
            return []
        t0 = time.perf_counter()
        try:
            while not ptc():
                self.stats.searches += 1
                try:
                    path = self._shortest_path(transfers_only, ptc)
                except Interrupted:
                    return []
                if not path:
                    if not transfers_only:
                        self._compute_reach()
                    return []
                # validate every transfer edge of the path (so one search removes all its bad
                # transfers), then the walks, which cost more, only if the transfers hold
                states = self._express(path)
                pairs = list(zip(path, path[1:], states, states[1:], strict=False))
                ok = True
                for walks in (False, True):
                    for a, b, sa, sb in pairs:
                        if (a[0] == b[0]) != walks:
                            continue
                        if ptc():
                            return []
                        if not self._edge_valid(a, b, sa, sb):
                            self.adj[a].pop(b, None)
                            self.adj[b].pop(a, None)
                            ok = False
                            if walks:
                                break
                    if not ok:
                        break
                if ok:
                    bad = self._invalid_as_expressed(path, ptc)
                    if bad is None:
                        return path
                    if ptc():
                        return []
                    self.verified[bad if bad[0] <= bad[1] else (bad[1], bad[0])] = False
                    self.adj[bad[0]].pop(bad[1], None)
                    self.adj[bad[1]].pop(bad[0], None)
            return []
        finally:
            self.stats.time_search += time.perf_counter() - t0

    def _shortest_path(self, transfers_only: bool = False,
                       ptc: Callable[[], bool] | None = None) -> list[Node]:
        """Lazy A* over the multiplexed graph (candidate edges tested when they matter).

        The queue holds edges, not nodes (Lazy Weighted A*): a transfer edge's cheap
        plausibility test (:meth:`_plausible_edge`, cached) runs only when the edge is popped
        to close its end node, so one search tests about one edge per node it expands
        instead of every edge of the graph, and an implausible edge costs no further search
        (it is dropped and the search goes on). Costs do not depend on the test, so the path
        is the shortest over the plausible edges.

        Heuristic: straight distance of the box to the goal less the largest car offset (a
        transfer edge is at least that long).
        """
        poses = self.obj.poses
        gx, gy = self.goal[0], self.goal[1]
        slack = max(self.checker.model.object_size[:2])
        cache = self._h
        adj = self.adj
        plausible = self._plausible_edge
        known = self._plausibility
        weight = self.params.search_weight

        def h(i: int) -> float:
            v = cache.get(i)
            if v is None:
                q = poses[i]
                v = cache[i] = weight * max(0.0, math.hypot(q[0] - gx, q[1] - gy) - slack)
            return v

        # A transfer edge joining grasp g to grasp g + 2 turns the path's frame by a half turn
        # (see _express): the search tracks that parity, so that the plan reaches the goal
        # exactly as given (not its half turn, the same placement of the box under another
        # name, which a checker comparing poses would refuse).
        State = tuple[Node, int]
        goals = {(g, 0) for g in self.goal_nodes}
        heap: list[tuple[float, int, float, State, State | None]] = []
        tie = 0
        for st in self.start_nodes:
            heap.append((h(st[0]), tie, 0.0, (st, 0), None))
            tie += 1
        heapq.heapify(heap)
        parent: dict[State, State | None] = {}
        best: dict[State, float] = {}
        pops = 0
        while heap:
            _, _, gv, v, u = heapq.heappop(heap)
            if v in parent:
                continue
            pops += 1
            if ptc is not None and pops % 64 == 0 and ptc():
                raise Interrupted("regrasp graph search")
            if u is not None and u[0][0] != v[0][0] and not plausible(u[0], v[0]):
                continue  # the edge was dropped from the graph
            parent[v] = u
            if v in goals:
                path = [v[0]]
                w = u
                while w is not None:
                    path.append(w[0])
                    w = parent[w]
                return path[::-1]
            n, parity = v
            for m_, c in adj[n].items():
                transfer = m_[0] != n[0]
                if transfers_only and not transfer:
                    continue
                ws = (m_, parity ^ int(transfer and m_[1] != n[1]))
                if ws in parent:
                    continue
                gw = gv + c
                if gw >= best.get(ws, math.inf):
                    continue
                if not transfer or known.get(_key(n, m_)):  # a tested edge: prune by cost
                    best[ws] = gw
                tie += 1
                heapq.heappush(heap, (gw + h(m_[0]), tie, gw, ws, v))
        return []

    # -- the algorithm (Fig. 7 of the paper) -------------------------------------------------
    def _initialise(self) -> None:
        """Start and goal nodes, the direct edges, and the Visibility PRM builder."""
        p, ck = self.params, self.checker
        s_i = self.obj.add(self.start, "start")
        g_i = self.obj.add(self.goal, "goal")
        self._vis = VisibilityRoadmapBuilder(self._sample_box_valid, self._visible,
                                             max_failures=p.guard_failures, roadmap=self.obj)
        self._vis.guards.extend([s_i, g_i])
        for i in (s_i, g_i):
            self.plan_with_object_config(i)
        self._done = len(self.obj)
        if p.slot_seeds:
            self._seed_slots()
        self.start_nodes = [n for n in self.adj if n[0] == s_i]
        self.goal_nodes = {n for n in self.adj if n[0] == g_i}
        m = ck.model
        for (_, g) in self.start_nodes:  # always try the direct edge first
            if (g_i, g) in self.goal_nodes:
                d = ck.steering.rs.distance(m.car_pose(self.start, g), m.car_pose(self.goal, g))
                self._link((s_i, g), (g_i, g), d)
        self._compute_reach()

    def _seed_slots(self) -> None:
        """Add the box-valid poses along the scene's slots to the object roadmap.

        They are multiplexed with the next nodes (the search that follows sees them).
        """
        p, ck = self.params, self.checker
        m, clear = ck.model, ck.world.clearance
        ahead, behind, half_width = m.walking_extent()
        narrowest = min(ahead + behind, 2.0 * half_width) + 2.0 * clear
        slots = find_passages(ck.scene, min_width=min(m.object_size[:2]) + 2.0 * clear,
                              max_width=narrowest + p.slot_play)
        reach = max(m.object_size[:2])
        for slot in slots:
            for q in passage_poses(slot, reach=reach, spacing=p.slot_spacing,
                                   approach=p.slot_approach):
                if ck.box_valid(q):
                    self.obj.add(canonical(q), "slot")
                    self.stats.slot_nodes += 1
        self.stats.slots = len(slots)

    def run(self, ptc: Callable[[], bool]) -> list[tuple[Pose, int]]:
        """Plan; return the path as ``(object pose, grasp)`` states, ``[]`` on time-out.

        Calling it again continues with the same roadmaps and caches (OMPL's semantics:
        solving again continues), e.g. after a time-out.
        """
        p = self.params
        t0 = time.perf_counter()
        if self._vis is None:
            self._initialise()
            direct = self._single_grasp(ptc)
            if direct:
                self._fill_stats()
                return self._finish(direct, ptc)
        vis = self._vis
        assert vis is not None
        path = self.search(ptc)
        n = 0
        while not path and not ptc() and vis.failures < p.guard_failures and \
                n < p.max_visibility_samples:
            n += 1
            vis.step()
            path = self._add_new_nodes(ptc)
        self.stats.time_visibility += time.perf_counter() - t0
        # passage phase: cheap bridge tests before the diffusion
        for _ in range(p.bridge_rounds if self.stats.passage_nodes == 0 else 0):
            if path or ptc():
                break
            path = self._bridge_step(ptc)
        # diffusion: grow the object roadmap towards random samples
        while not path and not ptc():
            if self.rng.uniform() < p.bridge_bias:
                path = self._bridge_step(ptc)
                continue
            q = self._diffusion_target()
            near = self.obj.nearest(q, 1)[0]
            qn = self._extend(self.obj.poses[near], q)
            if qn == self.obj.poses[near]:
                continue
            self.obj.add(canonical(qn), "diffusion")
            self.stats.diffusion_nodes += 1
            path = self._add_new_nodes(ptc)
        self._fill_stats()
        if not path:
            return []
        return self._finish(self._express(path), ptc)

    def _single_grasp(self, ptc: Callable[[], bool]) -> list[tuple[Pose, int]]:
        """A regrasp-free path by RRT-Connect at each grasp valid at both ends, or ``[]``.

        Its own generator (spawned from the planner's, which it leaves as it was) and a
        budget of motion checks shared by the grasps.
        """
        p, ck = self.params, self.checker
        grasps = [g for g in p.grasps if ck.state_valid(self.start, g)
                  and ck.state_valid(self.goal, g)]
        if p.single_grasp_checks <= 0 or not grasps:
            return []
        t0 = time.perf_counter()
        rng = self.rng.spawn(1)[0]
        share = max(1, p.single_grasp_checks // len(grasps))
        try:
            for g in grasps:
                rrt = SingleGraspConnect(ck, self.start, self.goal, g, rng,
                                         step=p.single_grasp_step)
                poses = rrt.run(share, ptc)
                self.stats.single_grasp_checks += rrt.checks
                if poses:
                    self.stats.single_grasp_solved = True
                    return [(q, g) for q in poses]
            return []
        finally:
            self.stats.time_single_grasp += time.perf_counter() - t0

    def _express(self, path: list[Node]) -> list[tuple[Pose, int]]:
        """The path as ``(object pose, grasp)`` states in the start's frame.

        A transfer edge may join ``(i, g)`` to ``(j, g + 2)``: the same car, so node ``j`` is
        written as its half-turn with grasp ``g``. The frame carries on along the path; the
        search (:meth:`_shortest_path`) keeps the parity of these half turns even, so the path
        ends at the goal as given.
        """
        out: list[tuple[Pose, int]] = []
        flip = False
        prev: Node | None = None
        for node in path:
            if prev is not None and prev[0] != node[0] and prev[1] != node[1]:
                flip = not flip
            q = self.obj.poses[node[0]]
            out.append((half_turn(q) if flip else q, (node[1] + 2 * flip) % 4))
            prev = node
        return out

    def _invalid_as_expressed(self, path: list[Node],
                              ptc: Callable[[], bool]) -> tuple[Node, Node] | None:
        """The first transfer edge of ``path`` that fails as written by :meth:`_express`.

        After an odd number of half turns an edge is written as the half turn of both poses
        with grasp ``g + 2``: the same motion, but computed from other numbers, so a rotation
        grazing the bounds or an obstacle may pass one check and fail the other (the plan is
        written from the checks of the written poses). Only those edges cost a check; the
        others are the checks already made (cache hits).
        """
        states = self._express(path)
        for (a, b), (sa, sb) in zip(zip(path, path[1:], strict=False),
                                    zip(states, states[1:], strict=False), strict=True):
            if a[0] == b[0]:
                continue
            if ptc() or not self.checker.transfer(sa[0], sb[0], sa[1]).valid:
                return a, b  # the caller tells an interruption from a failure by ``ptc``
        return None

    def _multiplex_pending(self, ptc: Callable[[], bool]) -> tuple[int, int]:
        """Multiplex the object nodes not yet multiplexed, polling ``ptc`` between nodes.

        Returns the numbers of manipulation nodes added and of object nodes that gave some;
        nodes left when ``ptc`` stops it are multiplexed by the next call (solving again
        continues).
        """
        added = nodes = 0
        for i in range(self._done, len(self.obj)):
            if ptc():
                break
            k = self.plan_with_object_config(i)
            added += k
            nodes += k > 0
            self._done = i + 1
        return added, nodes

    def _add_new_nodes(self, ptc: Callable[[], bool]) -> list[Node]:
        """Add the object nodes not yet multiplexed; search every ``search_every`` additions."""
        self._since += self._multiplex_pending(ptc)[1]
        if self._since < self.params.search_every:
            return []
        self._since = 0
        return self.search(ptc)

    def _finish(self, states: list[tuple[Pose, int]],
                ptc: Callable[[], bool]) -> list[tuple[Pose, int]]:
        """The one call to the path optimiser at the end of the search."""
        if not self.params.optimise:
            return states
        t1 = time.perf_counter()
        states = optimise(self.checker, states, grasps=self.params.grasps,
                          should_stop=budgeted(ptc, self.checker))
        self.stats.time_optimise += time.perf_counter() - t1
        return states

    def _bridge_step(self, ptc: Callable[[], bool], attempts: int = 100) -> list[Node]:
        """Bridge tests for narrow passages, directions taken from the scene's geometry.

        Two box poses (same yaw) in collision lie on either side of a passage if the box
        fits between them: the passage runs across the line joining them. The box at their
        midpoint, its axes (the directions each grasp's car drives straight) turned along and
        across that direction, is a passage node if free, and nodes are added along the
        passage on both sides. Nothing depends on the world's axes. Runs up to
        ``attempts`` cheap tests (polling ``ptc``), adds the first passage found.
        """
        ck, p = self.checker, self.params
        w = ck.world
        for k in range(attempts):
            if k % 10 == 0 and ptc():
                return []
            q1 = self._random_pose()
            if not w.box_in_bounds(q1) or w.box_distance(q1) > 0:
                continue
            q2 = (q1[0] + float(self.rng.normal(0, p.bridge_sigma)),
                  q1[1] + float(self.rng.normal(0, p.bridge_sigma)), q1[2])
            if not w.box_in_bounds(q2) or w.box_distance(q2) > 0:
                continue
            mx, my = 0.5 * (q1[0] + q2[0]), 0.5 * (q1[1] + q2[1])
            if p.passage_mode == "box":  # the bridge's own (random) yaw and the box's axes
                along = q1[2]
                free = [(mx, my, q1[2])] if ck.box_valid((mx, my, q1[2])) else []
            else:
                across = math.atan2(q2[1] - q1[1], q2[0] - q1[0])
                along = across + 0.5 * math.pi  # the passage's direction
                free = [c for c in (canonical((mx, my, along)), canonical((mx, my, across)))
                        if ck.box_valid(c)]
            if free:
                break
        else:
            return []
        self.stats.passage_nodes += 1
        dirs = [along, along + math.pi] if p.passage_mode != "box" else \
            [along + k * 0.5 * math.pi for k in range(4)]
        for c in free:
            self.obj.add(c, "passage")
            for a in dirs:
                for d in p.passage_steps:
                    q = (mx + d * math.cos(a), my + d * math.sin(a), c[2])
                    if not ck.box_valid(q):
                        break
                    self.obj.add(q, "passage")
        return self.search(ptc) if self._multiplex_pending(ptc)[0] else []

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
        # the box is symmetric: steer to the target's half-turn nearest to ``near``'s yaw
        dyaw = wrap_angle(target[2] - near[2])
        if abs(dyaw) > 0.5 * math.pi:
            target = (target[0], target[1], wrap_angle(target[2] + math.pi))
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

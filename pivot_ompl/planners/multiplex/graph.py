"""The multiplexed graph: manipulation roadmaps per grasp joined by the regrasping roadmap.

Nodes are ``(object node, grasp)``: the box at an object-roadmap pose held with a grasp. Two
kinds of edge join them (:func:`~.edges.is_transfer`):

* a **transfer** ``(i, g) - (j, h)`` between two object nodes: box and robot pivot together
  with one grasp. The box is symmetric under a half turn, so neighbours are found with yaw
  modulo pi and the grasp ``h`` of node ``j`` is ``g`` or ``g + 2``, whichever describes the
  same car; an edge with ``h = g + 2`` turns the path's *frame* by a half turn
  (:func:`~.edges.frame_flip`);
* a **regrasp** ``(i, g) - (i, h)`` at one object node: the robot walks round the resting box.

A **turn** is a transfer too: from ``(i, g)`` to the pose the box reaches when the car spins
by pi about its own position (:class:`~pivot_ompl.pivoting.curves.CarPaths`), an object node
of its own (kind ``"turn"``) added wherever the disk the assembly sweeps is free.

Edges are candidates until a search uses them. A transfer's cheap test (box and robot free at
three poses of its Reeds-Shepp path, :meth:`MultiplexedGraph.plausible`) runs when a search or
the reachable set (:mod:`~.reach`) meets it; an edge that fails it, or a full check, is
removed for good.

Searches run over *states* ``(node, parity)``: the parity of the half turns taken so far, so
that a path reaches the goal exactly as given (not its half turn, which a checker comparing
poses would refuse). The graph owns that rule (:meth:`MultiplexedGraph.successor`) and writes
a path in the start's frame (:meth:`MultiplexedGraph.express`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.graph import UnionFind
from pivot_ompl.planners.multiplex.edges import (
    Node,
    State,
    Stop,
    frame_flip,
    is_transfer,
    successor,
    undirected,
    walk_estimate,
)
from pivot_ompl.planners.multiplex.reach import ReachableSet
from pivot_ompl.planners.objects.roadmap import PoseIndex, Roadmap, canonical_yaw, half_turn
from pivot_ompl.se2 import Pose, wrap_angle

#: Fractions of a transfer's Reeds-Shepp path where its cheap test places box and robot.
PLAUSIBILITY_FRACTIONS = (0.25, 0.5, 0.75)

__all__ = ["PLAUSIBILITY_FRACTIONS", "MultiplexedGraph", "Node", "State", "Stop", "frame_flip",
           "is_transfer", "undirected", "walk_estimate"]


class MultiplexedGraph:
    """Manipulation nodes and candidate edges over an object roadmap (module docstring).

    Args:
        checker: state validity, the cheap test of transfers, the Reeds-Shepp distances.
        roadmap: the object roadmap whose nodes are multiplexed.
        grasps: the grasps the robot may use.
        neighbours: candidate transfer edges per new manipulation node.
        connect_radius: longest candidate transfer edge (m, Reeds-Shepp length of its car).
        costs: the edges' costs (s): a transfer's estimated from its Reeds-Shepp length (the
            search keeps it, :mod:`~.search`), a regrasp's from its walk's estimated length
            (the search replaces it by the real walk's once checked).
        turns: add turn edges (:data:`SearchConfig.turns`), keeping ``turn_margin`` (m) free
            round the disk a turn sweeps.

    Attributes:
        adj: candidate edges and their costs, both ways: ``adj[a][b]``.
        by_grasp: object nodes multiplexed at each grasp.
        start_nodes, goal_nodes: the manipulation nodes at the start and goal poses.
        multiplexed: object nodes (by index, from 0) already multiplexed.
        regrasp_edges, plausibility_tests: counts.
        plausibility_passed: cheap tests of transfers that passed (of ``plausibility_tests``).
        links: candidate edges linked so far (a version of the graph: removals and cost
            changes do not count).
    """

    adj: dict[Node, dict[Node, float]]
    by_grasp: dict[int, list[int]]
    start_nodes: list[Node]
    goal_nodes: set[Node]
    multiplexed: int
    regrasp_edges: int
    plausibility_tests: int
    plausibility_passed: int
    links: int

    def __init__(self, checker: PivotChecker, roadmap: Roadmap, *, grasps: tuple[int, ...],
                 neighbours: int, connect_radius: float, costs: CostModel,
                 turns: bool = False, turn_margin: float = 0.05) -> None:
        """An empty graph over ``roadmap``."""
        self.checker = checker
        self.roadmap = roadmap
        self.grasps = grasps
        self.neighbours = neighbours
        self.connect_radius = connect_radius
        self.costs = costs
        m, alpha = checker.model, checker.scene.alpha_max
        #: seconds per metre of each grasp's car pushing straight
        self.push_rate = {g: costs.push_rate(m.edge_half_length(g), alpha) for g in range(4)}
        self.turn_margin = turn_margin
        #: turn edges to link once their turn node is multiplexed: node -> (node, cost)
        self._turns: dict[int, list[tuple[Node, int, float]]] = {}
        self.adj = {}
        self.by_grasp = {g: [] for g in grasps}
        self.start_nodes = []
        self.goal_nodes = set()
        self.multiplexed = 0
        self.turns = turns
        self.turn_edges = 0
        self.regrasp_edges = 0
        self.plausibility_tests = 0
        self.plausibility_passed = 0
        self.links = 0
        self._components: UnionFind[Node] = UnionFind()  # over candidate edges (never split)
        #: object nodes where grasp 0 or 2 (index 0), 1 or 3 (index 1) is valid
        self._parity = (PoseIndex(self.roadmap), PoseIndex(self.roadmap))
        self._removed: set[tuple[Node, Node]] = set()
        self._plausible: dict[tuple[Node, Node], bool] = {}
        #: the states a search may reach (:mod:`~.reach`), computed once the ends are set
        self._reach = ReachableSet(self.adj, self.plausible)

    # -- structure ---------------------------------------------------------------------
    def successor(self, state: State, node: Node) -> State:
        """The state reached from ``state`` along the edge to ``node`` (parity carried on)."""
        return successor(state, node)

    def successors(self, state: State) -> Iterator[tuple[State, float]]:
        """The states one candidate edge away, with the edges' costs."""
        n, parity = state
        for m, c in self.adj[n].items():
            yield (m, parity ^ frame_flip(n, m)), c

    def removed(self, a: Node, b: Node) -> bool:
        """Whether the edge ``a - b`` was removed (it is never linked again)."""
        return undirected(a, b) in self._removed

    def remove(self, a: Node, b: Node) -> None:
        """Remove the edge ``a - b`` for good."""
        self.adj[a].pop(b, None)
        self.adj[b].pop(a, None)
        self._removed.add(undirected(a, b))

    def set_cost(self, a: Node, b: Node, cost: float) -> None:
        """Replace the cost of the edge ``a - b`` (e.g. a walk's estimate by its real cost)."""
        self.adj[a][b] = self.adj[b][a] = cost

    def transfer_edges(self) -> Iterator[tuple[Node, Node]]:
        """Every candidate transfer edge at one grasp, once (for pictures)."""
        for a, nbrs in self.adj.items():
            for b in nbrs:
                if b[1] == a[1] and b[0] > a[0]:
                    yield a, b

    # -- growth ------------------------------------------------------------------------
    def multiplex_pending(self, should_stop: Stop) -> tuple[int, int]:
        """Multiplex the object nodes not yet multiplexed, polling ``should_stop`` between.

        Returns the numbers of manipulation nodes added and of object nodes that gave some;
        the nodes left when stopped are multiplexed by the next call.
        """
        added = nodes = 0
        while self.multiplexed < len(self.roadmap):  # turn nodes are added on the way
            if should_stop():
                break
            i = self.multiplexed
            k = self._multiplex(i, should_stop)
            for node, grasp, cost in self._turns.pop(i, ()):
                if (i, grasp) in self.adj:
                    self.link(node, (i, grasp), cost, should_stop)
                    self.turn_edges += 1
            added += k
            nodes += k > 0
            self.multiplexed = i + 1
        return added, nodes

    def _multiplex(self, i: int, should_stop: Stop) -> int:
        """Add object node ``i`` at every grasp valid there (``PlanWithObjectConfig``).

        Each manipulation node gets candidate transfer edges to its nearest nodes (yaw modulo
        pi: node ``j``'s yaw within pi/2 of ``i``'s, or its half turn with grasp ``g + 2``),
        and regrasp edges join the grasps valid at ``i``. Returns the manipulation nodes added.
        """
        q = self.roadmap.poses[i]
        ck, m = self.checker, self.checker.model
        rs = ck.steering.paths
        added: list[int] = []
        near: dict[int, list[int]] = {}  # per grasp parity: g and g + 2 share their neighbours
        for g in self.grasps:
            if not ck.state_valid(q, g):
                continue
            node = (i, g)
            if node not in self.adj:
                self.adj[node] = {}
                self._components.add(node)
            car = m.car_pose(q, g)
            if g % 2 not in near:
                near[g % 2] = self.roadmap.nearest(q, self.neighbours, among=self._parity[g % 2])
            for j in near[g % 2]:
                qj = self.roadmap.poses[j]
                gj = g if abs(wrap_angle(qj[2] - q[2])) <= 0.5 * math.pi else (g + 2) % 4
                if (j, gj) not in self.adj:
                    continue
                d = rs.distance(car, m.car_pose(qj, gj))
                if d <= self.connect_radius:
                    self.link(node, (j, gj), d * self.push_rate[g], should_stop)
            self.by_grasp[g].append(i)
            added.append(g)
        for parity in {g % 2 for g in added}:
            self._parity[parity].append(i)
        if self.turns and self.roadmap.kinds[i] != "turn":
            for g in added:
                self._add_turn(i, g)
        for k, a in enumerate(added):  # the regrasping roadmap at this pose
            for b in added[k + 1:]:
                walk = walk_estimate(self.checker.model, a, b)
                self.link((i, a), (i, b), self.costs.regrasp_seconds(walk), should_stop)
                self.regrasp_edges += 1
        return len(added)

    def _add_turn(self, i: int, g: int) -> None:
        """A turn node for ``(i, g)`` if the assembly has room to turn (linked later)."""
        turned = self.checker.turned(self.roadmap.poses[i], g, margin=self.turn_margin)
        if turned is None:
            return
        yaw, shift = canonical_yaw(turned[2])
        j = self.roadmap.add((turned[0], turned[1], yaw), "turn")
        cost = self.costs.spin_estimate(math.pi, self.checker.scene.alpha_max)
        self._turns.setdefault(j, []).append(((i, g), (g + shift) % 4, cost))

    def link(self, a: Node, b: Node, cost: float, should_stop: Stop) -> None:
        """Add the candidate edge ``a - b`` (unless removed before); keep the reachable set."""
        if self.removed(a, b):
            return
        self.adj[a][b] = cost
        self.adj[b][a] = cost
        self.links += 1
        self._components.union(a, b)
        self._reach.joined(a, b, should_stop)

    def set_ends(self, start: int, goal: int, should_stop: Stop, *,
                 start_grasp: int | None = None) -> None:
        """Set the start and goal object nodes (both multiplexed).

        Their manipulation nodes (at the start only ``(start, start_grasp)`` if given), the
        direct edge at each grasp valid at both (always tried first), and the reachable set.
        """
        self.start_nodes = [n for n in self.adj if n[0] == start and start_grasp in (None, n[1])]
        self.goal_nodes = {n for n in self.adj if n[0] == goal}
        m, rs = self.checker.model, self.checker.steering.paths
        qs, qg = self.roadmap.poses[start], self.roadmap.poses[goal]
        for (_, g) in self.start_nodes:
            if (goal, g) in self.goal_nodes:
                d = rs.distance(m.car_pose(qs, g), m.car_pose(qg, g))
                self.link((start, g), (goal, g), d * self.push_rate[g], should_stop)
        self.compute_reach(should_stop)

    # -- the cheap test and the reachable set ---------------------------------------------
    def plausible(self, a: Node, b: Node) -> bool:
        """The cheap test of transfer ``a - b`` (cached); an implausible edge is removed.

        ``(j, g + 2)`` is the same car as ``(j's half turn, g)``.
        """
        key = undirected(a, b)
        v = self._plausible.get(key)
        if v is None:
            m = self.checker.model
            pa, pb = self.roadmap.poses[a[0]], self.roadmap.poses[b[0]]
            pb = pb if a[1] == b[1] else half_turn(pb)
            v = self._plausible[key] = self.checker.cars_free(
                m.car_pose(pa, a[1]), m.car_pose(pb, a[1]), a[1], PLAUSIBILITY_FRACTIONS)
            self.plausibility_tests += 1
            if v:
                self.plausibility_passed += 1
            else:
                self.remove(a, b)
        return v

    def known_plausible(self, a: Node, b: Node) -> bool:
        """Whether ``a - b`` is a regrasp or a transfer that passed its cheap test already."""
        return not is_transfer(a, b) or self._plausible.get(undirected(a, b), False)

    def compute_reach(self, should_stop: Stop) -> None:
        """The states connected to a start over edges that pass the cheap test.

        Grown until it holds a goal state (:meth:`.ReachableSet.grow`).
        """
        self._reach.compute(self.start_nodes, self.goal_nodes, should_stop)

    def maybe_connected(self) -> bool:
        """Whether the goal (in the start's frame) may be reached from the start.

        Two sound filters: the components over every candidate edge ever added, and the
        reachable set (edges refused later by full checks only shrink the truth, so a failed
        search computes it again). A search that cannot succeed is skipped.
        """
        if self._reach.excludes_goal(self.goal_nodes):
            return False
        goals = {self._components.find(g) for g in self.goal_nodes}
        return any(self._components.find(s) in goals for s in self.start_nodes)

    # -- paths -------------------------------------------------------------------------
    def express(self, path: list[Node]) -> list[tuple[Pose, int]]:
        """The path as ``(object pose, grasp)`` states in the start's frame.

        After a transfer joining ``(i, g)`` to ``(j, g + 2)``, node ``j`` is written as its
        half turn with grasp ``g``, and so on along the path.
        """
        out: list[tuple[Pose, int]] = []
        flip = 0
        prev: Node | None = None
        for node in path:
            if prev is not None:
                flip ^= frame_flip(prev, node)
            q = self.roadmap.poses[node[0]]
            out.append((half_turn(q) if flip else q, (node[1] + 2 * flip) % 4))
            prev = node
        return out


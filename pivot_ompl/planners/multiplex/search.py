"""The lazy search of the multiplexed graph, and the full checks of the path it finds.

:meth:`PathSearch.cheapest` is Lazy Weighted A* (:func:`pivot_ompl.graph.astar` with
``valid``): the queue holds edges, and a transfer's cheap test runs only when the edge is
popped to close its end state, so one search tests about one edge per state it expands; an
edge that fails is removed and the same search goes on. Costs do not depend on the test, so
the path is the cheapest over the plausible edges (within the heuristic's weight).

:meth:`PathSearch.find` then checks the path's edges exactly as the plan will write them (the
start's frame and the path's direction, :meth:`MultiplexedGraph.express`): every transfer
first (so one search removes all its bad transfers), then the walks, which cost more; a walk
found replaces its estimated cost by its real one. An edge that fails is removed and the
search runs again, until a path passes or the graph has none.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.planners.multiplex.graph import MultiplexedGraph, Node, State, is_transfer
from pivot_ompl.se2 import Pose

Stop = Callable[[], bool]
#: The search polls the termination condition every this many expansions.
POLL_EVERY = 64


class PathSearch:
    """Searches the multiplexed graph and checks the paths found (see the module docstring).

    Args:
        checker: the full checks of transfers and walks.
        graph: the graph searched (edges removed as they fail).
        goal: the goal pose (the heuristic's target).
        weight: inflation of the heuristic (weighted A*).

    Attributes:
        searches, edges_checked, edges_invalid: counts.
        seconds: time spent in :meth:`find` (s).
    """

    searches: int
    edges_checked: int
    edges_invalid: int
    seconds: float

    def __init__(self, checker: PivotChecker, graph: MultiplexedGraph, goal: Pose, *,
                 weight: float) -> None:
        """A search over ``graph``."""
        self.checker = checker
        self.graph = graph
        self.goal = goal
        self.weight = weight
        self.searches = self.edges_checked = self.edges_invalid = 0
        self.seconds = 0.0
        #: heuristic per object node: the box's straight distance to the goal less the
        #: largest car offset (a transfer edge is at least that long), at the fastest
        #: grasp's seconds per metre, weighted
        self._h: dict[int, float] = {}
        self._slack = max(checker.model.object_size[:2])
        self._rate = min(graph.push_rate.values())
        #: the cheapest regrasp (s) and the fewest regrasps from each node to the goal
        #: (:meth:`MultiplexedGraph.regrasps_to_go`), as of ``graph.links == _levels_at``
        self._regrasp = graph.costs.regrasp_seconds(0.0)
        self._levels: dict[Node, int] = {}
        self._levels_at = -1
        #: edges checked valid, as the plan writes them: ``(state, state)`` in path order
        self._checked: set[tuple[tuple[Pose, int], tuple[Pose, int]]] = set()

    def heuristic(self, node: Node) -> float:
        """The weighted heuristic of ``node``: its transfers' and its regrasps' least cost.

        The box's straight distance to the goal less the largest car offset at the fastest
        grasp's seconds per metre (inflated by ``weight``), plus the fewest regrasps to the
        goal at the cheapest regrasp's cost; ``inf`` where the goal cannot be reached. At
        most ``weight`` times a lower bound: a path found costs at most ``weight`` times the
        cheapest over the plausible edges.
        """
        level = self._levels.get(node)
        if level is None:
            return math.inf
        i = node[0]
        v = self._h.get(i)
        if v is None:
            q = self.graph.roadmap.poses[i]
            v = self._h[i] = self.weight * self._rate * max(
                0.0, math.hypot(q[0] - self.goal[0], q[1] - self.goal[1]) - self._slack)
        return v + self._regrasp * level

    def cheapest(self, should_stop: Stop) -> list[Node]:
        """Lazy weighted A* from a start node to a goal node; ``[]`` if there is none.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        g = self.graph
        if self._levels_at != g.links:
            levels = g.regrasps_to_go(should_stop)
            if levels is None:
                raise Interrupted("regrasps to go")
            self._levels, self._levels_at = levels, g.links

        def valid(u: State, v: State) -> bool:
            return not is_transfer(u[0], v[0]) or g.plausible(u[0], v[0])

        states = astar([(s, 0) for s in g.start_nodes], {(n, 0) for n in g.goal_nodes},
                       g.successors, lambda s: self.heuristic(s[0]), valid=valid,
                       known=lambda u, v: g.known_plausible(u[0], v[0]),
                       should_stop=should_stop, poll_every=POLL_EVERY)
        return [s[0] for s in states]

    def find(self, should_stop: Stop) -> list[Node]:
        """A path whose every edge passes its full check; ``[]`` if none yet (or stopped)."""
        g = self.graph
        if not g.maybe_connected():
            return []
        t0 = time.perf_counter()
        try:
            while not should_stop():
                self.searches += 1
                try:
                    path = self.cheapest(should_stop)
                except Interrupted:
                    return []
                if not path:
                    g.compute_reach(should_stop)
                    return []
                if self._check(path, should_stop):
                    return path
            return []
        finally:
            self.seconds += time.perf_counter() - t0

    def _check(self, path: list[Node], should_stop: Stop) -> bool:
        """Check ``path``'s transfers, then its walks; remove the first failures."""
        states = self.graph.express(path)
        pairs = list(zip(path, path[1:], states, states[1:], strict=False))
        for walks in (False, True):
            ok = True
            for a, b, sa, sb in pairs:
                if is_transfer(a, b) == walks:
                    continue
                if should_stop():
                    return False
                if not self._edge_valid(a, b, sa, sb, should_stop):
                    if should_stop():  # interrupted: unknown, not invalid
                        return False
                    self.graph.remove(a, b)
                    ok = False
                    if walks:
                        break
            if not ok:
                return False
        return True

    def _edge_valid(self, a: Node, b: Node, sa: tuple[Pose, int], sb: tuple[Pose, int],
                    should_stop: Stop) -> bool:
        """Check the edge ``a -> b`` of a path, written as the states ``sa -> sb``.

        A pivot sequence depends on its direction, and a pose and its half turn differ by
        round-off, which can change the Reeds-Shepp path: the edge is checked as the plan
        holds it. An invalid edge is refused in every frame and direction (conservative).
        """
        g = self.graph
        if g.removed(a, b):
            return False
        if (sa, sb) in self._checked:
            return True
        (pa, ga), (pb, gb) = sa, sb
        ck = self.checker
        costs = g.costs
        if is_transfer(a, b):
            v = g.plausible(a, b)
            if v:
                edge = ck.transfer(pa, pb, ga, should_stop=should_stop)
                v = edge.valid
                if v:  # the real rotations' seconds replace the estimate
                    g.set_cost(a, b, costs.rotations(r.angle for r in edge.sequence.rotations))
        else:
            walk = ck.transit(pa, ga, gb, should_stop=should_stop)
            v = walk.valid
            if v:  # the real walk replaces the estimate
                g.set_cost(a, b, costs.regrasp_seconds(walk.length))
        if v:
            self._checked.add((sa, sb))
        self.edges_checked += 1
        self.edges_invalid += not v
        return v

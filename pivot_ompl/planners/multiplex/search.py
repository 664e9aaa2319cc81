"""The lazy search of the multiplexed graph, and the full checks of the path it finds.

:meth:`PathSearch.cheapest` is Lazy Weighted A* (:func:`pivot_ompl.graph.astar` with
``valid``): the queue holds edges, and a transfer's cheap test runs only when the edge is
popped to close its end state, so one search tests about one edge per state it expands; an
edge that fails is removed and the same search goes on. Costs do not depend on the test, so
the path is the cheapest over the plausible edges (within the heuristic's weight). The
heuristic is the exact cost to go over the plausible edges, frame parity ignored
(:func:`cost_to_go`), recomputed whenever edges have been linked: the
search expands little more than the path it returns, even on floors of many rooms.

:meth:`PathSearch.find` then checks the path's edges exactly as the plan will write them (the
start's frame and the path's direction, :meth:`MultiplexedGraph.express`): every transfer
first (so one search removes all its bad transfers), then the walks, which cost more; a walk
found replaces its estimated cost by its real one. An edge that fails is removed and the
search runs again, until a path passes or the graph has none.

A transfer keeps its estimated cost when it passes. The estimates are optimistic for every
transfer alike (a sequence of pivots costs more than the straight push the estimate prices:
real over estimate about 1.3 on the median, on floors of many rooms), so a checked transfer
priced at its real cost would lose to the unchecked ones round it, and a re-search after a
failure would leave the checked path all along the floor and check most of it anew. With
the estimates kept, a re-search is the same search over the graph less the failed edges: it
stays on the checked path but round them, and the heuristic stays exact.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar, distances
from pivot_ompl.planners.evaluation import Evaluator, Found, Status, lazy_search
from pivot_ompl.planners.multiplex.edges import Node, State, is_transfer
from pivot_ompl.planners.multiplex.graph import MultiplexedGraph
from pivot_ompl.se2 import Pose

Stop = Callable[[], bool]
#: The search polls the termination condition every this many expansions.
POLL_EVERY = 64


def cost_to_go(graph: MultiplexedGraph, should_stop: Stop) -> dict[Node, float] | None:
    """The cheapest cost (s) from each node of ``graph`` to a goal, over plausible edges.

    Dijkstra (:func:`pivot_ompl.graph.distances`) from the goal nodes over the candidate
    edges at their current costs (the graph is undirected), lazy as the search is: every way
    to a node is queued untested (only ways through regrasps and transfers already known
    plausible prune the queue), and
    a transfer is tested (cached) only when a way through it is taken from the queue to
    settle its far node: about one test per node, for the same distances as a Dijkstra
    testing every edge it relaxes. Frame parity is ignored (a relaxation). Every path of the
    graph from a node to the goal costs at least that much while no edge is linked and no
    cost lowered (edges removed later only raise it); a node without a value has no path to
    the goal. ``None`` when ``should_stop`` said stop (polled every 256 nodes).
    """
    try:
        return distances(graph.goal_nodes, lambda u: graph.adj[u].items(),
                         valid=lambda p, u: not is_transfer(p, u) or graph.plausible(p, u),
                         known=graph.known_plausible, should_stop=should_stop)
    except Interrupted:
        return None


class PathSearch:
    """Searches the multiplexed graph and checks the paths found (see the module docstring).

    Args:
        checker: the full checks of transfers and walks.
        graph: the graph searched (edges removed as they fail).
        goal: the goal pose.
        weight: inflation of the heuristic (weighted A*).

    Attributes:
        evaluate: the checks and prices of the edges (:class:`~.evaluation.Evaluator`).
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
        self.evaluate = Evaluator(checker, graph.costs)
        self.graph = graph
        self.goal = goal
        self.weight = weight
        self.searches = self.edges_checked = self.edges_invalid = 0
        self.seconds = 0.0
        #: the cheapest cost from each node to the goal over the plausible edges
        #: (:func:`cost_to_go`), as of ``graph.links == _to_go_at``
        self._to_go: dict[Node, float] = {}
        self._to_go_at = -1
        #: edges checked valid, as the plan writes them: ``(state, state)`` in path order
        self._checked: set[tuple[tuple[Pose, int], tuple[Pose, int]]] = set()

    def heuristic(self, node: Node) -> float:
        """The heuristic of ``node``: its cheapest cost to the goal over the plausible edges.

        Exact for the graph as it was when computed, with parity ignored; ``inf`` where the
        goal cannot be reached. Edges that fail their checks later only raise the true cost,
        so it stays a lower bound and the search goes almost straight to the cheapest path.
        """
        return self.weight * self._to_go.get(node, math.inf)

    def cheapest(self, should_stop: Stop) -> list[Node]:
        """Lazy weighted A* from a start node to a goal node; ``[]`` if there is none.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        g = self.graph
        if self._to_go_at != g.links:
            to_go = cost_to_go(g, should_stop)
            if to_go is None:
                raise Interrupted("cost to go")
            self._to_go, self._to_go_at = to_go, g.links

        def valid(u: State, v: State) -> bool:
            return not is_transfer(u[0], v[0]) or g.plausible(u[0], v[0])

        states = astar([(s, 0) for s in g.start_nodes], {(n, 0) for n in g.goal_nodes},
                       g.successors, lambda s: self.heuristic(s[0]), valid=valid,
                       known=lambda u, v: g.known_plausible(u[0], v[0]),
                       should_stop=should_stop, poll_every=POLL_EVERY)
        return [s[0] for s in states]

    def find(self, should_stop: Stop) -> Found[list[Node]]:
        """A path whose every edge passes its full check.

        ``VALID`` with the path; ``INVALID`` when the graph has none yet; ``STOPPED``.
        """
        g = self.graph
        if not g.maybe_connected():
            return Found(Status.INVALID)
        t0 = time.perf_counter()
        try:
            found = lazy_search(lambda: self._searched(should_stop),
                                lambda path: self._check(path, should_stop), should_stop)
            if found.status is Status.INVALID:
                g.compute_reach(should_stop)
            return found
        finally:
            self.seconds += time.perf_counter() - t0

    def _searched(self, should_stop: Stop) -> Found[list[Node]]:
        """One search (:meth:`cheapest`) as a :class:`Found`."""
        self.searches += 1
        try:
            path = self.cheapest(should_stop)
        except Interrupted:
            return Found(Status.STOPPED)
        return Found(Status.VALID, path) if path else Found(Status.INVALID)

    def _check(self, path: list[Node], should_stop: Stop) -> Status:
        """Check ``path``'s transfers, then its walks; remove the first failures."""
        states = self.graph.express(path)
        pairs = list(zip(path, path[1:], states, states[1:], strict=False))
        for walks in (False, True):
            ok = True
            for a, b, sa, sb in pairs:
                if is_transfer(a, b) == walks:
                    continue
                if should_stop():
                    return Status.STOPPED
                status = self._edge(a, b, sa, sb, should_stop)
                if status is Status.STOPPED:
                    return status
                if status is Status.INVALID:
                    self.graph.remove(a, b)
                    ok = False
                    if walks:
                        break
            if not ok:
                return Status.INVALID
        return Status.VALID

    def _edge(self, a: Node, b: Node, sa: tuple[Pose, int], sb: tuple[Pose, int],
              should_stop: Stop) -> Status:
        """Check the edge ``a -> b`` of a path, written as the states ``sa -> sb``.

        A pivot sequence depends on its direction, and a pose and its half turn differ by
        round-off, which can change the Reeds-Shepp path: the edge is checked as the plan
        holds it. An invalid edge is refused in every frame and direction (conservative).
        """
        g = self.graph
        if g.removed(a, b):
            return Status.INVALID
        if (sa, sb) in self._checked:
            return Status.VALID
        (pa, ga), (pb, gb) = sa, sb
        if is_transfer(a, b):
            status = Status.INVALID
            if g.plausible(a, b):
                status = self.evaluate.transfer(pa, pb, ga, should_stop=should_stop).status
        else:
            walk = self.evaluate.walk(pa, ga, gb, should_stop=should_stop)
            status = walk.status
            if walk.valid:  # the real walk replaces the estimate
                g.set_cost(a, b, walk.cost)
        if status is Status.STOPPED:
            return status
        if status is Status.VALID:
            self._checked.add((sa, sb))
        self.edges_checked += 1
        self.edges_invalid += status is Status.INVALID
        return status

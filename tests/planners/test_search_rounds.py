"""The lazy search's cost to go, the costs it keeps, and the paths it returns.

* :func:`cost_to_go` tests a transfer only when a way through it settles a node: the
  distances of the Dijkstra over every plausible edge (the reference tests them all), with at
  most one passed test per node settled.
* A transfer that passes its full check keeps its estimated cost: a re-search is the cheapest
  path at the estimates over the edges left (weight 1).
* :meth:`PathSearch.find` returns a path whose every edge passes its full check.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from factories import shipped

from pivot_ompl.base.problem import make_problem
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.evaluation import Status
from pivot_ompl.planners.multiplex.graph import is_transfer
from pivot_ompl.planners.multiplex.search import PathSearch, cost_to_go
from pivot_ompl.planners.regrasp_search import RegraspSearch

NEVER = lambda: False  # noqa: E731


def _grown(samples: int = 40, seed: int = 0) -> RegraspSearch:
    """fig10's search after ``samples`` visibility samples, multiplexed."""
    scene = shipped("fig10")
    ck = make_problem(scene).checker
    search = RegraspSearch(ck, scene.start, scene.goal, RegraspConfig(),
                           np.random.default_rng(seed))
    search.prepare(NEVER)
    for _ in range(samples):
        search.visibility.step(NEVER)
    search.graph.multiplex_pending(NEVER)
    return search


def _dijkstra(sources, neighbours) -> dict:
    dist = dict.fromkeys(sources, 0.0)
    heap = [(0.0, k, s) for k, s in enumerate(sources)]
    tie = len(heap)
    while heap:
        d, _, u = heapq.heappop(heap)
        if d > dist[u]:
            continue
        for v, c in neighbours(u):
            if d + c < dist.get(v, math.inf):
                dist[v] = d + c
                heapq.heappush(heap, (d + c, tie, v))
                tie += 1
    return dist


def test_lazy_cost_to_go_is_the_dijkstra_over_every_plausible_edge():
    g = _grown().graph
    before = g.plausibility_passed
    to_go = cost_to_go(g, NEVER)
    assert to_go is not None
    passed = g.plausibility_passed - before
    assert passed <= len(to_go)  # one passed test per node settled, at most

    def plausible_edges(u):
        return [(v, c) for v, c in list(g.adj[u].items())
                if not is_transfer(u, v) or g.plausible(u, v)]

    want = _dijkstra(list(g.goal_nodes), plausible_edges)
    assert to_go.keys() == want.keys()
    assert all(abs(to_go[n] - want[n]) <= 1e-9 * max(1.0, want[n]) for n in want)


def _cost(g, path) -> float:
    return sum(g.adj[a][b] for a, b in zip(path, path[1:], strict=False))


def _cheapest(g) -> float:
    """The reference: Dijkstra over (node, parity) states, every transfer tested."""

    def succ(state):
        n = state[0]
        for (m, parity), c in list(g.successors(state)):
            if not is_transfer(n, m) or g.plausible(n, m):
                yield (m, parity), c

    dist = _dijkstra([(s, 0) for s in g.start_nodes], succ)
    return min(dist.get((n, 0), math.inf) for n in g.goal_nodes)


def test_checks_keep_the_transfers_estimates_and_a_re_search_is_the_cheapest_at_them():
    search = _grown()
    g = search.graph
    estimates = {(a, b): c for a, nbrs in g.adj.items() for b, c in nbrs.items()
                 if is_transfer(a, b)}
    paths = PathSearch(search.checker, g, search.goal, weight=1.0)
    assert paths.find(NEVER).status is Status.VALID
    assert paths.edges_checked > 0
    for a, nbrs in g.adj.items():
        for b, c in nbrs.items():
            if is_transfer(a, b):
                assert c == estimates[(a, b)]  # checked or not, priced at its estimate
    again = paths.cheapest(NEVER)
    assert _cost(g, again) <= _cheapest(g) * (1 + 1e-9) + 1e-9


def test_the_path_found_passes_every_full_check():
    search = _grown()
    found = search.paths.find(NEVER)
    assert found.status is Status.VALID and found.path
    path = found.path
    ck, g = search.checker, search.graph
    states = g.express(path)
    for a, b, (pa, ga), (pb, gb) in zip(path, path[1:], states, states[1:], strict=False):
        if is_transfer(a, b):
            assert ck.transfer(pa, pb, ga).valid
        else:
            assert ck.transit(pa, ga, gb).valid
    assert search.paths.edges_checked >= len(path) - 1


def test_nodes_linked_once_the_goal_is_reachable_run_no_cheap_test():
    # the reachable set only answers whether a search may succeed: once it holds a goal
    # state, new nodes' transfers are left to the search (tested lazily when it takes them)
    search = _grown()
    g = search.graph
    assert g.maybe_connected()
    tests, links = g.plausibility_tests, g.links
    for _ in range(40):
        search.visibility.step(NEVER)
    g.multiplex_pending(NEVER)
    assert g.links > links
    assert g.plausibility_tests == tests
    found = search.paths.find(NEVER)  # and the search still finds a checked path
    assert found.status is Status.VALID

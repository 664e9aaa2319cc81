"""A* and union-find against brute force on random graphs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import csgraph, csr_matrix

from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import UnionFind, astar, distances


def random_graph(n: int, p: float, seed: int) -> dict[int, list[tuple[int, float]]]:
    rng = np.random.default_rng(seed)
    adj: dict[int, list[tuple[int, float]]] = {i: [] for i in range(n)}
    for i in range(n):
        for j in range(i + 1, n):
            if rng.random() < p:
                c = float(rng.uniform(0.1, 3.0))
                adj[i].append((j, c))
                adj[j].append((i, c))
    return adj


def dijkstra(adj, starts, goals) -> float:
    """The least cost from a start to a goal: scipy's Dijkstra, an oracle apart from ours."""
    n = len(adj)
    edges = [(u, v, c) for u in adj for v, c in adj[u]]
    rows, cols, costs = (list(x) for x in zip(*edges, strict=True)) if edges else ([], [], [])
    d = csgraph.dijkstra(csr_matrix((costs, (rows, cols)), shape=(n, n)),
                         indices=sorted(set(starts)), min_only=True)
    return min(float(d[g]) for g in goals)


def cost(adj, path) -> float:
    return sum(dict(adj[a])[b] for a, b in zip(path, path[1:], strict=False))


@given(seed=st.integers(0, 10_000), n=st.integers(2, 25), p=st.floats(0.05, 0.5))
@settings(max_examples=150, deadline=None)
def test_astar_is_optimal_with_zero_heuristic_and_multiple_ends(seed, n, p):
    adj = random_graph(n, p, seed)
    starts, goals = [0, n // 3], {n - 1, n // 2}
    path = astar(starts, goals, lambda u: adj[u], lambda u: 0.0)
    best = dijkstra(adj, starts, goals)
    if math.isinf(best):
        assert path == []
    else:
        assert path[0] in starts and path[-1] in goals
        assert cost(adj, path) == best or math.isclose(cost(adj, path), best)


def test_astar_on_a_grid_with_an_admissible_heuristic_finds_the_shortest_detour():
    free = np.ones((20, 20), dtype=bool)
    free[5, :18] = False  # a wall with a gap on the right

    def nb(c):
        x, y = c
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            q = (x + dx, y + dy)
            if 0 <= q[0] < 20 and 0 <= q[1] < 20 and free[q]:
                yield q, 1.0

    goal = (10, 0)
    path = astar([(0, 0)], {goal}, nb, lambda c: abs(c[0] - goal[0]) + abs(c[1] - goal[1]))
    assert path[0] == (0, 0) and path[-1] == goal
    assert all(free[c] for c in path)
    assert len(path) - 1 == 10 + 2 * 18  # down through the gap at column 18 and back
    free[5, 18:] = False
    assert astar([(0, 0)], {goal}, nb, lambda c: 0.0) == []


@given(seed=st.integers(0, 10_000))
@settings(max_examples=100, deadline=None)
def test_union_find_matches_naive_components(seed):
    rng = np.random.default_rng(seed)
    n = 30
    uf: UnionFind[int] = UnionFind()
    label = list(range(n))
    for i in range(n):
        uf.add(i)
    for _ in range(int(rng.integers(0, 40))):
        a, b = (int(x) for x in rng.integers(0, n, 2))
        uf.union(a, b)
        la, lb = label[a], label[b]
        label = [la if x == lb else x for x in label]
    for i in range(n):
        for j in range(n):
            assert uf.connected(i, j) == (label[i] == label[j])


def test_astar_honours_the_termination_condition():
    import pytest

    from pivot_ompl.errors import Interrupted

    def line(n):  # an endless corridor: the goal is never reached
        yield n + 1, 1.0

    with pytest.raises(Interrupted):
        astar([0], {-1}, line, lambda n: 0.0, should_stop=lambda: True)


@given(seed=st.integers(0, 10_000), n=st.integers(2, 25), p=st.floats(0.05, 0.6),
       broken=st.floats(0.0, 0.7))
@settings(max_examples=150, deadline=None)
def test_lazy_astar_finds_the_cheapest_path_over_the_edges_that_pass(seed, n, p, broken):
    adj = random_graph(n, p, seed)
    rng = np.random.default_rng(seed + 1)
    bad = {(u, v) for u in adj for v, _ in adj[u] if rng.random() < broken}
    kept = {u: [(v, c) for v, c in adj[u] if (u, v) not in bad] for u in adj}
    starts, goals = [0, n // 3], {n - 1, n // 2}
    checked: list[tuple[int, int]] = []

    def valid(u: int, v: int) -> bool:
        checked.append((u, v))
        return (u, v) not in bad

    path = astar(starts, goals, lambda u: adj[u], lambda u: 0.0, valid=valid)
    best = dijkstra(kept, starts, goals)
    if math.isinf(best):
        assert path == []
    else:
        assert path[0] in starts and path[-1] in goals
        assert all((a, b) not in bad for a, b in zip(path, path[1:], strict=False))
        assert math.isclose(cost(adj, path), best)
    assert len(checked) == len(set(checked))  # no edge is checked twice


def test_lazy_astar_checks_only_the_edges_it_takes_from_the_queue():
    def nb(c):  # an open grid: 8 neighbours each
        x, y = c
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                if (dx or dy) and 0 <= x + dx < 30 and 0 <= y + dy < 30:
                    yield (x + dx, y + dy), math.hypot(dx, dy)

    goal = (29, 29)
    checked = []

    def valid(u, v):
        checked.append(v)
        return True

    path = astar([(0, 0)], {goal}, nb, lambda c: math.hypot(goal[0] - c[0], goal[1] - c[1]),
                 valid=valid)
    assert len(path) == 30
    assert len(checked) <= 2 * len(path)  # eager: 8 per expanded node


def all_distances(adj, starts, usable) -> dict[int, float]:
    """Every node's cost from the nearest start over the edges ``usable(u, v)`` (brute force)."""
    dist = dict.fromkeys(starts, 0.0)
    for _ in range(len(adj)):  # Bellman-Ford
        for u, d in list(dist.items()):
            for v, c in adj[u]:
                if usable(u, v) and d + c < dist.get(v, math.inf):
                    dist[v] = d + c
    return dist


@given(seed=st.integers(0, 10_000), n=st.integers(2, 25), p=st.floats(0.05, 0.5),
       lazy=st.booleans())
@settings(max_examples=150, deadline=None)
def test_distances_are_every_nodes_cheapest_cost_over_the_edges_that_pass(seed, n, p, lazy):
    adj = random_graph(n, p, seed)
    bad = {(u, v) for u in adj for v, _ in adj[u] if (u * 31 + v * 17 + seed) % 5 == 0}
    checked = []

    def valid(u, v):  # noqa: ANN001, ANN202
        checked.append((u, v))
        return (u, v) not in bad

    starts = [0, n // 3]
    if lazy:
        got = distances(starts, lambda u: adj[u], valid=valid)
        want = all_distances(adj, starts, lambda u, v: (u, v) not in bad)
        assert len(checked) <= sum(len(e) for e in adj.values())
    else:
        got = distances(starts, lambda u: adj[u])
        want = all_distances(adj, starts, lambda u, v: True)
    assert got.keys() == want.keys()
    assert all(math.isclose(got[k], want[k], abs_tol=1e-12) for k in want)


def test_distances_poll_the_stop_every_so_many_nodes():
    adj = random_graph(60, 0.3, 1)
    polls = []
    with pytest.raises(Interrupted):
        distances([0], lambda u: adj[u], should_stop=lambda: polls.append(1) or len(polls) > 2,
                  poll_every=5)
    assert len(polls) == 3

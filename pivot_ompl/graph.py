"""A* shortest path on an implicit graph (used by the regrasp search and the walk planner)."""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Collection, Hashable, Iterable
from typing import TypeVar

N = TypeVar("N", bound=Hashable)


def astar(starts: Iterable[N], goals: Collection[N],
          neighbours: Callable[[N], Iterable[tuple[N, float]]],
          heuristic: Callable[[N], float]) -> list[N]:
    """Cheapest path from any start to any goal; ``[]`` if none.

    Args:
        starts: start nodes (cost 0).
        goals: goal nodes (membership tested).
        neighbours: ``n -> [(m, cost), ...]`` with non-negative costs.
        heuristic: admissible lower bound of the cost from a node to the goals.
    """
    dist: dict[N, float] = {}
    parent: dict[N, N] = {}
    heap: list[tuple[float, int, N]] = []
    tie = 0
    for s in starts:
        dist[s] = 0.0
        heap.append((heuristic(s), tie, s))
        tie += 1
    heapq.heapify(heap)
    done: set[N] = set()
    while heap:
        _, _, u = heapq.heappop(heap)
        if u in done:
            continue
        done.add(u)
        if u in goals:
            path = [u]
            while path[-1] in parent:
                path.append(parent[path[-1]])
            return path[::-1]
        du = dist[u]
        for v, c in neighbours(u):
            nd = du + c
            if nd < dist.get(v, math.inf):
                dist[v] = nd
                parent[v] = u
                tie += 1
                heapq.heappush(heap, (nd + heuristic(v), tie, v))
    return []

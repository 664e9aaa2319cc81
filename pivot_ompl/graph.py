"""Graph algorithms: A* and Dijkstra on an implicit graph, and union-find (components).

:func:`astar` and :func:`distances` share the package's one priority-queue search
(:func:`_settle`, lazy when given ``valid``); the other queue in the package orders something
else than a graph search (``wholebody.clearance``: the next sample each body is measured at).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Collection, Hashable, Iterable, Iterator
from typing import Generic, TypeVar

from pivot_ompl.errors import Interrupted

N = TypeVar("N", bound=Hashable)


def _settle(starts: Iterable[N], neighbours: Callable[[N], Iterable[tuple[N, float]]],
            heuristic: Callable[[N], float], valid: Callable[[N, N], bool] | None,
            known: Callable[[N, N], bool] | None) -> Iterator[tuple[N, float, N | None]]:
    """The nodes in the order a (lazy) best-first search closes them: ``(node, cost, parent)``.

    The one priority queue of the package, shared by :func:`astar` and :func:`distances`
    (see :func:`astar` for the arguments). A node's edges are expanded when the caller asks
    for the next node, so a caller that stops at a goal expands nothing past it.
    """
    dist: dict[N, float] = {}
    heap: list[tuple[float, int, float, N, N | None]] = []
    tie = 0
    for s in starts:
        h = heuristic(s)
        if h == math.inf:
            continue
        dist[s] = 0.0
        heap.append((h, tie, 0.0, s, None))
        tie += 1
    heapq.heapify(heap)
    done: set[N] = set()
    while heap:
        _, _, du, u, p = heapq.heappop(heap)
        if u in done or (valid is None and du > dist[u]):
            continue
        if valid is not None and p is not None and not valid(p, u):
            continue
        done.add(u)
        yield u, du, p
        for v, c in neighbours(u):
            nd = du + c
            # checked edges: only the cheapest known way to ``v`` is queued; candidate
            # edges: every way is queued (the cheapest may fail its check)
            if v in done or nd >= dist.get(v, math.inf):
                continue
            h = heuristic(v)
            if h == math.inf:
                continue
            if valid is None or (known is not None and known(u, v)):
                dist[v] = nd
            tie += 1
            heapq.heappush(heap, (nd + h, tie, nd, v, u))


def astar(starts: Iterable[N], goals: Collection[N],
          neighbours: Callable[[N], Iterable[tuple[N, float]]],
          heuristic: Callable[[N], float], *,
          valid: Callable[[N, N], bool] | None = None,
          known: Callable[[N, N], bool] | None = None,
          should_stop: Callable[[], bool] | None = None, poll_every: int = 1024) -> list[N]:
    """Cheapest path from any start to any goal; ``[]`` if none.

    Args:
        starts: start nodes (cost 0).
        goals: goal nodes (membership tested).
        neighbours: ``n -> [(m, cost), ...]`` with non-negative costs.
        heuristic: admissible lower bound of the cost from a node to the goals (``inf``:
            no goal can be reached from it, and it is never queued).
        valid: ``(n, m) -> bool``, if given: the edges ``neighbours`` gives are candidates,
            each checked only when the node it leads to is taken from the queue through it
            (lazy A*: most edges out of an expanded node never are, and are never checked).
            A node whose edge fails stays open, to be reached through another.
        known: ``(n, m) -> bool``, with ``valid``: the candidate edges already known to pass
            ``valid``; a way through one of them is queued only if it is the cheapest known
            way (as with checked edges), so the queue stays small.
        should_stop: termination condition, polled every ``poll_every`` expansions.
        poll_every: expansions between two polls of ``should_stop``.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    parent: dict[N, N] = {}
    for closed, (u, _, p) in enumerate(_settle(starts, neighbours, heuristic, valid, known),
                                       start=1):
        if p is not None:
            parent[u] = p
        if should_stop is not None and closed % poll_every == 0 and should_stop():
            raise Interrupted("A* search")
        if u in goals:
            path = [u]
            while path[-1] in parent:
                path.append(parent[path[-1]])
            return path[::-1]
    return []


def distances(starts: Iterable[N], neighbours: Callable[[N], Iterable[tuple[N, float]]], *,
              valid: Callable[[N, N], bool] | None = None,
              known: Callable[[N, N], bool] | None = None,
              should_stop: Callable[[], bool] | None = None,
              poll_every: int = 256) -> dict[N, float]:
    """Cheapest cost from the nearest start to every node it reaches (Dijkstra).

    Lazy when given ``valid``, as :func:`astar` is: :func:`astar`'s search with a zero
    heuristic and no goal, run until the queue is empty; the same arguments. A node missing
    from the result is not reachable.

    Raises:
        Interrupted: ``should_stop()`` became true (polled every ``poll_every`` nodes closed).
    """
    out: dict[N, float] = {}
    for u, du, _ in _settle(starts, neighbours, lambda _: 0.0, valid, known):
        out[u] = du
        if should_stop is not None and len(out) % poll_every == 0 and should_stop():
            raise Interrupted("Dijkstra search")
    return out


class UnionFind(Generic[N]):
    """Disjoint sets of hashable items (path halving, union by pointing at the second root)."""

    def __init__(self) -> None:
        """An empty structure."""
        self._parent: dict[N, N] = {}

    def add(self, x: N) -> None:
        """Make ``x`` a singleton set (no-op if known)."""
        self._parent.setdefault(x, x)

    def __contains__(self, x: object) -> bool:
        """Whether ``x`` was added."""
        return x in self._parent

    def find(self, x: N) -> N:
        """Representative of ``x``'s set."""
        p = self._parent
        while p[x] != x:
            p[x] = p[p[x]]
            x = p[x]
        return x

    def union(self, a: N, b: N) -> None:
        """Merge the sets of ``a`` and ``b``."""
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self._parent[ra] = rb

    def connected(self, a: N, b: N) -> bool:
        """Whether ``a`` and ``b`` are in one set."""
        return self.find(a) == self.find(b)

"""The guided refinement's counterexample: a path of fewest regrasps through the relaxation.

:func:`best_path` is what :func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound` refines
around: the relaxation's graph's path of fewest regrasps (the same count as
:meth:`~pivot_ompl.analysis.piece_graph.PieceGraph.fewest_regrasps`), with its nodes.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

from pivot_ompl.analysis.piece_graph import PieceGraph, Regrasp
from pivot_ompl.errors import Interrupted


def best_path(graph: PieceGraph, starts: list[int], goals: set[int],
              allowed: Callable[[Regrasp], bool],
              should_stop: Callable[[], bool] | None = None) -> tuple[int | None, list[int]]:
    """A path of fewest allowed regrasps from a start to a goal node, and that count.

    Level by level as :meth:`~pivot_ompl.analysis.piece_graph.PieceGraph.fewest_regrasps`
    (the same count): breadth first by transfers within a level; a regrasp out of a level is
    checked (``allowed``, the costly part) only when its far node is not reached yet, the
    largest pieces first, and the search stops at the first goal. ``(None, [])`` when no goal
    is reachable. ``should_stop`` raises :class:`~pivot_ompl.errors.Interrupted`.
    """
    parent = {s: -1 for s in starts}
    level, goal = _closure(graph, list(parent), parent, goals)
    d = 0
    while goal is None and level:
        pending = [(u, v, e) for u in level for v, e in graph.one[u] if v not in parent]
        pending.sort(key=lambda uve: -graph.areas[uve[1]])
        level = []
        for u, v, e in pending:
            if should_stop is not None and should_stop():
                raise Interrupted("the guided refinement's path")
            if v in parent or not allowed(e):
                continue
            parent[v] = u
            grown, goal = _closure(graph, [v], parent, goals)
            level += grown
            if goal is not None:
                break
        d += 1
    if goal is None:
        return None, []
    path = [goal]
    while parent[path[-1]] >= 0:
        path.append(parent[path[-1]])
    return d, path[::-1]


def _closure(graph: PieceGraph, seeds: list[int], parent: dict[int, int], goals: set[int]
             ) -> tuple[list[int], int | None]:
    """The nodes reached from ``seeds`` (already in ``parent``) by transfers, and a goal met."""
    out: list[int] = []
    queue = deque(seeds)
    while queue:
        u = queue.popleft()
        out.append(u)
        if u in goals:
            return out, u
        for v in graph.zero[u]:
            if v not in parent:
                parent[v] = u
                queue.append(v)
    return out, None

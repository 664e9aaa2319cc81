"""The guided refinement's paths: the relaxation's fewest-regrasp path, and several a round.

:func:`best_path` is the relaxation's *counterexample*: a path of fewest regrasps through its
graph. A round of :func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound` builds the mixed
graph of its window (the costly part: the whole floor's coarse pieces cut by the window,
the window's fine voxels), finds one fewest-regrasp path and refines round the narrow places
it passes. On a large floor the count often rises only once several such paths are closed
(the Willow Garage office's 2 after four rounds of 1). :func:`cheat_windows` finds more of
them on the same graph: once a path's window is chosen, the coarse pieces it refines are
taken out of the search (as if the window had closed them: a guess, often right) and the
next fewest-regrasp path, at the same count, adds its own window, up to ``paths`` paths.
Which cells are refined is a matter of cost only (every window gives a sound bound), so
the guess needs no proof; a guess that is wrong costs cells, bounded by ``max_cells``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

import numpy as np

from pivot_ompl.analysis.piece_graph import PieceGraph, Regrasp
from pivot_ompl.analysis.raster_bound import RasterGraph
from pivot_ompl.analysis.raster_cover import RasterCover
from pivot_ompl.errors import Interrupted

#: Paths whose windows one round refines at most.
PATHS = 2


def best_path(graph: PieceGraph, starts: list[int], goals: set[int],
              allowed: Callable[[Regrasp], bool],
              should_stop: Callable[[], bool] | None = None, *,
              banned: set[int] | None = None) -> tuple[int | None, list[int]]:
    """A path of fewest allowed regrasps from a start to a goal node, and that count.

    Level by level as :meth:`~pivot_ompl.analysis.piece_graph.PieceGraph.fewest_regrasps`
    (the same count): breadth first by transfers within a level; a regrasp out of a level is
    checked (``allowed``, the costly part) only when its far node is not reached yet, the
    largest pieces first, and the search stops at the first goal. ``(None, [])`` when no goal
    is reachable. ``should_stop`` raises :class:`~pivot_ompl.errors.Interrupted`. ``banned``:
    nodes the path may not pass.
    """
    parent = dict.fromkeys(banned or (), -2)
    parent.update({s: -1 for s in starts})
    level, goal = _closure(graph, starts, parent, goals)
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


def cheat_windows(joined: RasterGraph, cover: RasterCover, path: list[int], count: int,
                  window: np.ndarray, ends: set[int],
                  search: Callable[[set[int]], tuple[int | None, list[int]]],
                  window_of: Callable[[list[int], np.ndarray], np.ndarray], *,
                  paths: int = PATHS, max_cells: int | None = None) -> np.ndarray:
    """The cells to add for ``path`` and up to ``paths - 1`` more paths of ``count`` regrasps.

    ``joined``, ``cover``: the round's coarse graph (extended by its fine nodes) and coarse
    cover without the window; ``path``: its best path, of ``count`` regrasps; ``ends``: its
    start and goal nodes (never taken out); ``search(banned)``: the round's fewest-regrasp
    search with the ``banned`` nodes taken out (count and path); ``window_of(path,
    window)``: a path's cells to add to ``window``. ``max_cells``: a further path's cells
    are added only while the window and the additions hold at most this many coarse cells.
    """
    add = window_of(path, window)
    banned: set[int] = set()
    for _ in range(paths - 1):
        if not add.any():
            break
        banned |= _closed(joined, cover, path, add) - ends
        more, path = search(banned)
        if more is None or more > count:
            break
        grown = window_of(path, window | add)
        if not grown.any() or (max_cells is not None
                               and int(window.sum() + add.sum() + grown.sum()) > max_cells):
            break
        add |= grown
    return add


def _closed(joined: RasterGraph, cover: RasterCover, path: list[int],
            add: np.ndarray) -> set[int]:
    """The coarse nodes of ``path`` whose cells meet ``add``."""
    keys = sorted(joined.base.items(), key=lambda kv: kv[1])
    firsts = np.array([v for _, v in keys], dtype=np.int64)
    out = set()
    for u in path:
        if u >= joined.total:
            continue
        (b, k), first = keys[int(np.searchsorted(firsts, u, side="right")) - 1]
        lay = joined.layer(b, k)
        box = cover.extent(lay, u - first + 1)
        if (add[box] & (cover.layers[lay][0][box] == u - first + 1)).any():
            out.add(u)
    return out

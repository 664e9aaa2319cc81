"""The floor's way to a goal, ignoring headings: a heuristic that knows the rooms and passages.

The held assembly's lattice (:mod:`.lattice`) searches states ``(ix, iy, heading)`` guided by
the straight distance to the goal. Across a floor of rooms and passages that guide points
at walls: the search fills every room between start and goal, and on a large floor runs out
of expansions before it reaches the goal. :func:`grid_distances` gives the exact distance
from every free grid position to the goal's positions over the lattice's own moves with the
headings forgotten (a move joins two positions free at *some* heading; every push of the
lattice is one of these moves at the same length), one Dijkstra over the positions
(scipy). It never exceeds the pushes any lattice route needs, so it is an admissible and
consistent heuristic that follows the free space's corridors and doors: the coarse route
the lattice search then refines.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted

Stop = Callable[[], bool]


def move_graph(cell_ids: np.ndarray, nx: int, ny: int, vectors: Iterable[tuple[int, int]],
               should_stop: Stop | None = None) -> csr_matrix:
    """The free positions joined by ``vectors`` (grid units, lengths as weights), as a matrix.

    Args:
        cell_ids: ``cell_ids[ix * ny + iy]`` numbers the free positions (``-1`` elsewhere),
            as :meth:`~.lattice.TransferLattice` numbers them.
        nx: the grid's positions along x.
        ny: the grid's positions along y.
        vectors: the moves ``(dx, dy)`` (grid units; each also taken backwards).
        should_stop: polled between the moves' arrays.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    cells = np.flatnonzero(cell_ids >= 0)
    n = len(cells)
    ix, iy = np.divmod(cells, ny)
    here = np.arange(n, dtype=np.int32)
    rows, cols, lengths = [], [], []
    for vx, vy in vectors:
        if should_stop is not None and should_stop():
            raise Interrupted("grid distances")
        jx, jy = ix + vx, iy + vy
        inside = (jx >= 0) & (jx < nx) & (jy >= 0) & (jy < ny)
        there = np.full(n, -1, dtype=np.int32)
        there[inside] = cell_ids[jx[inside] * ny + jy[inside]]
        ok = there >= 0
        rows.append(here[ok])
        cols.append(there[ok])
        lengths.append(np.full(int(ok.sum()), float(np.hypot(vx, vy))))
    if not rows:
        return csr_matrix((n, n))
    return coo_matrix((np.concatenate(lengths), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n)).tocsr()


def graph_distances(graph: csr_matrix, sources: Iterable[int],
                    should_stop: Stop | None = None) -> np.ndarray:
    """Distance over ``graph`` (:func:`move_graph`) from every position to the nearest source.

    Returns:
        One float per cell id; ``inf`` where no source is reached (everywhere without one).

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    src = sorted(set(int(s) for s in sources))
    n = graph.shape[0]
    if n == 0 or not src:
        return np.full(n, np.inf)
    if should_stop is not None and should_stop():
        raise Interrupted("grid distances")
    return np.asarray(dijkstra(graph, directed=False, indices=src, min_only=True))


def grid_distances(cell_ids: np.ndarray, nx: int, ny: int,
                   vectors: Iterable[tuple[int, int]], sources: Iterable[int],
                   should_stop: Stop | None = None) -> np.ndarray:
    """Distance (grid units) from every free position to the nearest of ``sources``.

    :func:`move_graph` then :func:`graph_distances`; ``sources`` are cell ids (not
    positions). One float per cell id, ``inf`` where no source is reached.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    return graph_distances(move_graph(cell_ids, nx, ny, vectors, should_stop), sources,
                           should_stop)

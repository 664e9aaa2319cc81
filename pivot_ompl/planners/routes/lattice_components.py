"""The held assembly's lattice components, computed in chunks that poll the stop."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from pivot_ompl.errors import Interrupted
from pivot_ompl.transit.lattice import HEADING_VECTORS, N_HEADINGS

#: Free cells per ``connected_components`` call of the lattice's components (a few
#: hundredths of a second each, the stop polled between them).
CHUNK_CELLS = 16_384


def chunked_labels(cells: np.ndarray, cell_ids: np.ndarray, state: list[np.ndarray],
                    turn: list[np.ndarray], shape: tuple[int, int],
                    should_stop: Callable[[], bool] | None) -> np.ndarray:
    """A component label per lattice state (``cell_id * N_HEADINGS + h``), chunk by chunk.

    The free cells are cut into runs of :data:`CHUNK_CELLS`; each run's own moves (pushes
    and turns within it) get their components in one small ``connected_components`` call,
    with ``should_stop`` polled between the calls, so no single call outlasts the stop by
    more than a run's share; then the pushes that cross from one run to another join the
    runs' components (a graph of the few components they touch). States in one component
    share a label, others differ (the numbers are not consecutive).

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    nx, ny, nh = shape[0], shape[1], N_HEADINGS
    n = len(cells)
    labels = np.empty(n * nh, dtype=np.int64)
    cross_r, cross_c = [], []
    for a in range(0, n, CHUNK_CELLS):
        if should_stop is not None and should_stop():
            raise Interrupted("transfer lattice components")
        b = min(a + CHUNK_CELLS, n)
        ix, iy = np.divmod(cells[a:b], ny)
        here = np.arange(a, b, dtype=np.int64) * nh
        rows, cols = [], []
        for h, (vx, vy) in enumerate(HEADING_VECTORS[:nh]):
            jx, jy = ix + vx, iy + vy
            inside = (jx >= 0) & (jx < nx) & (jy >= 0) & (jy < ny)
            there = np.full(b - a, -1, dtype=np.int64)
            there[inside] = cell_ids[jx[inside] * ny + jy[inside]]
            ok = state[h][a:b] & (there >= 0)
            ok[ok] &= state[h][there[ok]]
            inner = ok & (there >= a) & (there < b)
            rows.append(here[inner] + h)
            cols.append(there[inner] * nh + h)
            out = ok & ~inner
            cross_r.append(here[out] + h)
            cross_c.append(there[out] * nh + h)
            ok = turn[h][a:b]
            rows.append(here[ok] + h)
            cols.append(here[ok] + (h + 1) % nh)
        r, c = np.concatenate(rows) - a * nh, np.concatenate(cols) - a * nh
        m = (b - a) * nh
        graph = coo_matrix((np.ones(len(r), dtype=np.int8), (r, c)), shape=(m, m)).tocsr()
        _, sub = connected_components(graph, directed=False)
        labels[a * nh:b * nh] = sub + a * nh  # runs' labels never meet: a run's states <= m
    if should_stop is not None and should_stop():
        raise Interrupted("transfer lattice components")
    r, c = np.concatenate(cross_r), np.concatenate(cross_c)
    if len(r):
        touched, pairs = np.unique(np.concatenate([labels[r], labels[c]]), return_inverse=True)
        k = len(touched)
        graph = coo_matrix((np.ones(len(r), dtype=np.int8), (pairs[:len(r)], pairs[len(r):])),
                           shape=(k, k)).tocsr()
        _, joined = connected_components(graph, directed=False)
        remap = np.arange(n * nh, dtype=np.int64)
        remap[touched] = n * nh + joined  # above every run's label: no clash
        labels = remap[labels]
    return labels.astype(np.int32)  # < 2 * MAX_CELLS * N_HEADINGS

"""The held assembly's lattice components, computed in chunks that poll the stop.

The lattice's moves (:mod:`.lattice`) are pushes along a state's heading and turns in place
to the next heading; :func:`turn_room` is the one test of where a turn is free, which the
components (:func:`lattice_labels`) and the joins of a route's ends (:mod:`.lattice_ends`)
both use.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from pivot_ompl.errors import Interrupted
from pivot_ompl.transit.lattice import HEADING_VECTORS, N_HEADINGS

__all__ = ["CHUNK_CELLS", "chunked_labels", "lattice_labels", "turn_room"]

#: Free cells per ``connected_components`` call of the lattice's components (a few
#: hundredths of a second each, the stop polled between them).
CHUNK_CELLS = 16_384


def turn_room(fits: Callable[[int], np.ndarray], h: int) -> np.ndarray:
    """Where the lattice may turn in place between heading ``h`` and the next (booleans).

    Free at both headings and at the yaw half-way between them (field yaws ``2 h``, ``2 h + 1``
    and ``2 h + 2``: ``fits(k)`` is the grid of field yaw ``k``, any shape): a turn either way.
    """
    return fits(2 * h) & fits(2 * h + 1) & fits(2 * ((h + 1) % N_HEADINGS))


def lattice_labels(fits: Callable[[int], np.ndarray], shape: tuple[int, int],
                   should_stop: Callable[[], bool] | None) -> tuple[np.ndarray, np.ndarray]:
    """The components of the lattice's states, where ``fits(k)`` is field yaw ``k``'s grid.

    ``fits(k)``: the ``(nx, ny)`` positions free at field yaw ``k`` (``shape`` is
    ``(nx, ny)``). Returned as ``(cell_ids, labels)``: ``cell_ids[ix * ny + iy]`` numbers the
    cells free at some heading (``-1`` elsewhere), and ``labels[cell_id * N_HEADINGS + h]``
    is the component of state ``(ix, iy, h)``, ``-1`` where it is not free. Every array but
    ``cell_ids`` follows the free floor, not the grid's rectangle.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    nx, ny, nh = shape[0], shape[1], N_HEADINGS
    flat = [fits(k).reshape(-1) for k in range(2 * nh)]
    any_free = np.zeros(nx * ny, dtype=bool)
    for h in range(nh):
        any_free |= flat[2 * h]
    cells = np.flatnonzero(any_free)
    cell_ids = np.full(nx * ny, -1, dtype=np.int32)  # < MAX_CELLS * 16 states
    cell_ids[cells] = np.arange(len(cells), dtype=np.int32)
    state = [flat[2 * h][cells] for h in range(nh)]  # free at heading h, per free cell
    turn = [turn_room(lambda k: flat[k][cells], h) for h in range(nh)]
    labels = chunked_labels(cells, cell_ids, state, turn, (nx, ny), should_stop)
    labels[~np.stack(state, axis=1).reshape(-1)] = -1
    return cell_ids, labels


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

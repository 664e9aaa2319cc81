"""The floor field's graph layer: the open grid's graph and its connected components.

The graph follows the open floor, not the bounds' rectangle (a turned row of rooms fills a
small part of it, and the rectangle grows with the square of its length): its nodes are the
open positions in grid order (:attr:`OpenGraph.cells`: their flat grid indices). Every node
has one slot per heading vector (16, in :data:`~pivot_ompl.transit.lattice.HEADING_VECTORS`
order): the edge to the position that vector away, of its length when that position is open
too, ``inf`` otherwise (no edge; it then points back at the node itself). Built directly in
CSR form (no sort), a block of grid rows at a time; a query only closes the resting box's
positions (in place, restored after).

A walk never leaves the connected component it starts in: the components are labelled once
per scene (:func:`open_components`) and a query's graph is restricted to the components of its
goals (:meth:`OpenGraph.component_graph`, kept per set of components), so the open floor
outside a turned building, say, costs a query nothing.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from pivot_ompl.transit.lattice import HEADING_VECTORS

#: Grid positions whose graph edges are built between two polls of the termination condition.
GRAPH_CHUNK = 20_000


def open_components(mask: np.ndarray) -> np.ndarray:
    """Connected component of every open position of ``mask``, in flat grid order.

    Two open positions are joined when one of the 16 heading vectors leads from one to the
    other: the components of the open positions joined by the 8 unit moves (image
    labelling), merged where a move two cells long (a knight move) joins two of them.

    Args:
        mask: ``(nx, ny)`` booleans, the open positions.

    Returns:
        One label per open position (``np.flatnonzero(mask.ravel())`` order); equal labels
        for positions of one component.
    """
    nx, ny = mask.shape
    image, _ = ndimage.label(mask, structure=np.ones((3, 3), dtype=bool))
    pairs = []
    for vx, vy in HEADING_VECTORS:
        if abs(vx) + abs(vy) != 3 or vx < 0:  # the knight moves, one way each
            continue
        a = image[:nx - vx, max(0, -vy):ny - max(0, vy)]  # p
        b = image[vx:, max(0, vy):ny + min(0, vy)]  # p + (vx, vy)
        join = (a > 0) & (b > 0) & (a != b)
        pairs.append(np.stack([a[join], b[join]]))
    n = int(image.max()) + 1
    ab = np.concatenate(pairs, axis=1) if pairs else np.zeros((2, 0), dtype=np.int64)
    merged = connected_components(
        csr_matrix((np.ones(ab.shape[1], dtype=np.int8), (ab[0], ab[1])), shape=(n, n)),
        directed=False)[1]
    return merged[image.ravel()[np.flatnonzero(mask.ravel())]]


class OpenGraph:
    """The open grid's graph (see the module docstring), built a block of rows at a time.

    Args:
        mask: ``(nx, ny)`` booleans, the open positions (final: the graph reads it as is).
        resolution: grid spacing (m).

    Attributes:
        cells: the open positions' flat grid indices (the nodes, in grid order).
        node: per flat grid index, its node (``-1`` where not open).
        rows_done: grid rows whose edges are built.
    """

    def __init__(self, mask: np.ndarray, resolution: float) -> None:
        """Nodes of the open positions; no edges yet (:meth:`add_rows`)."""
        self.mask, self.resolution = mask, resolution
        self.nx, self.ny = mask.shape
        nd = len(HEADING_VECTORS)
        self.cells = np.flatnonzero(mask.ravel())
        self.node = np.full(self.nx * self.ny, -1, dtype=np.int64)
        self.node[self.cells] = np.arange(len(self.cells))
        m = len(self.cells)
        self._indices = np.empty((m, nd), dtype=np.int32)
        self._weights = np.empty((m, nd))
        self._components: np.ndarray | None = None
        self._graphs: dict[tuple[int, ...], tuple[np.ndarray, csr_matrix]] = {}
        self.rows_done = 0

    def add_rows(self, i0: int, i1: int) -> None:
        """The graph's edges out of the open positions of grid rows ``i0:i1``."""
        ny = self.ny
        lo, hi = np.searchsorted(self.cells, [i0 * ny, i1 * ny])
        ix, iy = np.divmod(self.cells[lo:hi], ny)
        v = np.asarray(HEADING_VECTORS)
        tx, ty = ix[:, None] + v[None, :, 0], iy[:, None] + v[None, :, 1]
        inside = (tx >= 0) & (tx < self.nx) & (ty >= 0) & (ty < ny)
        there = np.where(inside, self.node[np.where(inside, tx * ny + ty, 0)], -1)
        both = there >= 0
        here = np.arange(lo, hi)[:, None]
        self._indices[lo:hi] = np.where(both, there, here)
        lengths = self.resolution * np.hypot(v[:, 0], v[:, 1])
        self._weights[lo:hi] = np.where(both, lengths[None, :], np.inf)
        self.rows_done = max(self.rows_done, i1)

    def csr(self) -> csr_matrix:
        """The whole graph (every open position; built rows only hold edges)."""
        nd, m = len(HEADING_VECTORS), len(self.cells)
        return csr_matrix((self._weights.reshape(-1), self._indices.reshape(-1),
                           np.arange(0, nd * m + 1, nd, dtype=np.int64)), shape=(m, m))

    def labels(self) -> np.ndarray:
        """:func:`open_components` of the open positions (computed once)."""
        if self._components is None:
            self._components = open_components(self.mask)
        return self._components

    def component_graph(self, nodes: np.ndarray) -> tuple[np.ndarray, csr_matrix]:
        """The graph restricted to the components of ``nodes`` (open-graph nodes).

        Returns the components' positions (flat grid indices, sorted) and their graph, its
        node ``k`` the position ``cells[k]`` (kept per set of components).
        """
        labels = self.labels()
        key = tuple(sorted({int(v) for v in labels[nodes]}))
        hit = self._graphs.get(key)
        if hit is None:
            nd = len(HEADING_VECTORS)
            members = np.flatnonzero(np.isin(labels, key))
            local = np.full(len(self.cells), -1, dtype=np.int64)
            local[members] = np.arange(len(members))
            idx = self._indices[members]
            sub = np.where(local[idx] >= 0, local[idx], np.arange(len(members))[:, None])
            graph = csr_matrix((self._weights[members].reshape(-1),
                                sub.reshape(-1).astype(np.int32),
                                np.arange(0, nd * len(members) + 1, nd, dtype=np.int64)),
                               shape=(len(members), len(members)))
            hit = self._graphs[key] = (self.cells[members], graph)
        return hit


def closed_entries(cells: np.ndarray, closed: np.ndarray, ny: int, nx: int) -> np.ndarray:
    """The entries of a component's graph (over ``cells``) that closing ``closed`` removes.

    The edges out of and into the open positions of ``cells`` among ``closed`` (flat grid
    indices, e.g. those the resting box closes), in a grid of ``nx`` by ``ny``.
    """
    nd = len(HEADING_VECTORS)
    local = np.searchsorted(cells, closed)
    hit = (local < len(cells)) & (cells[np.minimum(local, len(cells) - 1)] == closed)
    closed, local = closed[hit], local[hit]
    slots = [(local[:, None] * nd + np.arange(nd)[None, :]).ravel()]  # edges out
    cx, cy = np.divmod(closed, ny)
    for d, (vx, vy) in enumerate(HEADING_VECTORS):  # edges in: from the position -v away
        sx, sy = cx - vx, cy - vy
        inside = (sx >= 0) & (sx < nx) & (sy >= 0) & (sy < ny)
        src = sx[inside] * ny + sy[inside]
        k = np.searchsorted(cells, src)
        ok = (k < len(cells)) & (cells[np.minimum(k, len(cells) - 1)] == src)
        slots.append(k[ok] * nd + d)
    return np.concatenate(slots)


@contextmanager
def closing(graph: csr_matrix, cut: np.ndarray) -> Iterator[csr_matrix]:
    """``graph`` with its entries ``cut`` closed (``inf``) in place, restored on leaving.

    A query's part (the resting box's) is closed in the graph built once per scene.
    """
    saved = graph.data[cut]
    graph.data[cut] = np.inf
    try:
        yield graph
    finally:
        graph.data[cut] = saved

"""Connected components of the fine voxels, computed afresh or grown by new voxels.

The fine voxels of :mod:`~pivot_ompl.analysis.raster_refine` are keys ``f * cells + a * ny +
b`` (fine bin ``f``, fine cell ``(a, b)``, ``cells = nx * ny``). Two voxels are joined when
they are 8-adjacent cells of one fine bin or one cell of two consecutive fine bins (the last
and the first included). :func:`voxel_components` labels a set of voxels;
:func:`grown_components` labels the union of labelled voxels and new ones, joining only from
the new voxels: the joins among the old voxels are already in their labels.

**Growing.** The new voxels lie in cells the old ones do not hold (a window grows by whole
coarse cells), so a new voxel's neighbours in the other fine bins (the same cell) are new
ones, and its neighbours in its own bin are new ones or, only next to ``done`` (the coarse
cells the old voxels lie in), old ones. So the joins are: among the new voxels, each join once
(from the lower key); to the old ones, from the new voxels whose neighbour cell lies in
``done``. The graph's nodes are the old components then the new voxels (in key order), so
the labels are those a labelling of every voxel with the old ones' joins would give, numbered
alike.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse import csgraph

#: The four forward neighbours of a voxel's cell within its bin ``(da, db)``.
_FORWARD = ((1, 0), (0, 1), (1, 1), (1, -1))
#: All eight neighbours of a voxel's cell within its bin.
_AROUND = _FORWARD + tuple((-da, -db) for da, db in _FORWARD)


def voxel_components(keys: np.ndarray, nx: int, ny: int, bins: int) -> tuple[int, np.ndarray]:
    """``(count, labels)`` of the sorted voxel ``keys`` (module docstring)."""
    if not len(keys):
        return 0, np.zeros(0, dtype=np.int64)
    return _label(len(keys), _forward_joins(keys, nx, ny, bins))


@dataclass
class Grown:
    """Voxels labelled, grown from labelled ones.

    Attributes:
        count: components.
        keys: every voxel, sorted.
        labels: each voxel's component.
        new: the new voxels, sorted.
        new_labels: their components.
        merged: each earlier component's component now (the earlier ones only merge).
    """

    count: int
    keys: np.ndarray
    labels: np.ndarray
    new: np.ndarray
    new_labels: np.ndarray
    merged: np.ndarray


def grown_components(old_keys: np.ndarray, old_labels: np.ndarray, old_count: int,
                     new_keys: np.ndarray, done: np.ndarray, nx: int, ny: int, bins: int
                     ) -> Grown:
    """The old voxels (sorted, labelled ``0..old_count - 1``) and the new ones, labelled.

    ``done``: the coarse cells (boolean, half the fine shape) holding every old voxel; no
    new voxel lies in them. The labels are those :func:`voxel_components` gives the union
    up to their numbering (the same partition; module docstring).
    """
    new = np.sort(new_keys.astype(np.int64, copy=False))
    if not len(old_keys):
        count, labels = voxel_components(new, nx, ny, bins)
        return Grown(count, new, labels, new, labels, np.zeros(0, dtype=np.int64))
    # the two sorted runs merged by position (no voxel is in both: new cells)
    at_old = np.searchsorted(new, old_keys) + np.arange(len(old_keys))
    at_new = np.searchsorted(old_keys, new) + np.arange(len(new))
    keys = np.empty(len(old_keys) + len(new), dtype=np.int64)
    keys[at_old], keys[at_new] = old_keys, new

    index = _index_type(old_count + len(new))

    def joins() -> Iterator[tuple[np.ndarray, np.ndarray]]:
        for src, dst in _forward_joins(new, nx, ny, bins):  # among the new voxels
            yield src.astype(index) + index(old_count), dst.astype(index) + index(old_count)
        cells = nx * ny
        k = new % cells
        a, b = k // ny, k % ny
        del k
        # only a voxel whose coarse cell touches a done one may have an old neighbour
        touching = ndimage.binary_dilation(done, structure=np.ones((3, 3), dtype=bool))
        some = np.flatnonzero(touching[a // 2, b // 2])
        a, b = a[some], b[some]
        for da, db in _AROUND:  # to the old voxels, only next to their coarse cells
            ta, tb = a + da, b + db
            ok = (ta >= 0) & (ta < nx) & (tb >= 0) & (tb < ny)
            ok[ok] = done[ta[ok] // 2, tb[ok] // 2]
            idx = some[ok]
            if not len(idx):
                continue
            target = new[idx] + da * ny + db
            pos = np.clip(np.searchsorted(old_keys, target), 0, len(old_keys) - 1)
            hit = old_keys[pos] == target
            yield old_count + idx[hit], old_labels[pos[hit]]

    count, node = _label(old_count + len(new), joins())
    labels = np.empty(len(keys), dtype=np.int64)
    labels[at_old] = node[old_labels]
    labels[at_new] = node[old_count:]
    return Grown(count, keys, labels, new, node[old_count:], node[:old_count])


def _forward_joins(keys: np.ndarray, nx: int, ny: int, bins: int
                   ) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The joins among the sorted ``keys`` (indices), each once: from the lower voxel.

    One batch ``(src, dst)`` per neighbour direction (so that only one is held at a time).
    """
    cells = nx * ny
    k = keys % cells
    a, b = (k // ny).astype(np.int32), (k % ny).astype(np.int32)  # cell rows and columns
    del k
    index = _index_type(len(keys))

    def join(target: np.ndarray, ok: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        pos = np.searchsorted(keys, target)
        np.minimum(pos, len(keys) - 1, out=pos)
        hit = ok & (keys[pos] == target)
        return np.flatnonzero(hit).astype(index), pos[hit].astype(index)

    for da, db in _FORWARD:
        if (da, db) == (0, 1):  # the next cell of a row is the next key when it is a voxel
            src = np.flatnonzero((b[:-1] + 1 < ny) & (keys[1:] == keys[:-1] + 1))
            yield src.astype(index), (src + 1).astype(index)
            continue
        yield join(keys + da * ny + db, (a + da < nx) & (b + db >= 0) & (b + db < ny))
    last = keys // cells == bins - 1
    yield join(np.where(last, keys - (bins - 1) * cells, keys + cells),
               np.ones(len(keys), dtype=bool))


def _index_type(n: int) -> type[np.signedinteger]:
    """The narrowest of int32 and int64 indexing ``n`` items (a join costs its indices)."""
    return np.int32 if n < 2**31 else np.int64


def _label(nodes: int, joins: Iterable[tuple[np.ndarray, np.ndarray]]
           ) -> tuple[int, np.ndarray]:
    """Connected components of ``nodes`` nodes joined by the edges of ``joins``' batches.

    Numbered by their smallest node, in order (as a scan of the nodes meets them). One batch
    of ``(src, dst)`` edges at a time (the components of all edges do not depend on their
    order): the batch's edges between two components found so far are read as a sparse
    graph over those components (:func:`scipy.sparse.csgraph.connected_components`, weakly
    connected), whose components become the new ones. Only one batch's edges are held.
    """
    index = _index_type(nodes)
    comp = np.arange(nodes, dtype=index)  # each node's component so far (0..count - 1)
    count = nodes
    for src, dst in joins:
        u, v = comp[src], comp[dst]
        keep = u != v
        if not keep.any():
            continue
        u, v = u[keep], v[keep]
        graph = sparse.csr_array((np.ones(len(u), dtype=bool), (u, v)), shape=(count, count))
        del u, v
        count, found = csgraph.connected_components(graph, directed=True, connection="weak")
        del graph
        comp = found.astype(index, copy=False)[comp]
    first = np.full(count, nodes, dtype=index)  # each component's smallest node
    np.minimum.at(first, comp, np.arange(nodes, dtype=index))
    rank = np.empty(count, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(count)
    return int(count), rank[comp]

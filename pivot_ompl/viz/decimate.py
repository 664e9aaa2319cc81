"""Fewer triangles for a replay: vertex clustering of a triangle mesh.

A replay is one self-contained HTML file that carries every link mesh. Talos's visual meshes
hold 159 k triangles (about 3 MB of the file); a viewer needs far fewer. :func:`decimate`
merges the vertices falling in one cell of a regular grid into their mean and drops the
triangles that collapse (two corners in one cell) or repeat, growing the cell until at most
``max_faces`` triangles remain (never none: one of the mesh's own triangles when all
collapse). The surface moves by at most a cell's diagonal; no
triangle is invented, so the result stays inside the mesh's bounding box.
"""

from __future__ import annotations

import numpy as np

__all__ = ["decimate"]

#: Cell growth between two attempts.
_GROWTH = 1.3
#: Most attempts (the cell grows 1.3 ** 40, about 36 000 times).
_ATTEMPTS = 40


def decimate(vertices: np.ndarray, faces: np.ndarray, max_faces: int
             ) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices, faces)`` with at most ``max_faces`` triangles (see the module docstring).

    Args:
        vertices: ``(n, 3)`` positions.
        faces: ``(m, 3)`` vertex indices.
        max_faces: the budget (>= 1); a mesh within it is returned as it is.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) <= max_faces or len(v) == 0:
        return v, f
    size = float(np.ptp(v, axis=0).max())
    if size <= 0.0:
        return v[:3], f[:1] if len(f) else f
    cell = size / max(2.0, np.sqrt(max_faces))
    out_v, out_f = v, f
    for _ in range(_ATTEMPTS):
        out_v, out_f = _cluster(v, f, cell)
        if len(out_f) <= max_faces:
            break
        cell *= _GROWTH
    if len(out_f) == 0:  # everything collapsed: one of the mesh's own triangles
        return v[f[0]], np.array([[0, 1, 2]])
    return out_v, out_f


def _cluster(v: np.ndarray, f: np.ndarray, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices merged per grid cell of side ``cell``; degenerate and repeated faces dropped."""
    keys = np.floor((v - v.min(axis=0)) / cell).astype(np.int64)
    _, label, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    label = label.reshape(-1)
    sums = np.zeros((len(counts), 3))
    np.add.at(sums, label, v)
    merged = sums / counts[:, None]
    g = label[f]
    keep = (g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 0] != g[:, 2])
    g = g[keep]
    if len(g):
        # one triangle per set of corners (either winding kept once)
        _, first = np.unique(np.sort(g, axis=1), axis=0, return_index=True)
        g = g[np.sort(first)]
    used = np.unique(g)
    remap = np.full(len(merged), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return merged[used], remap[g]

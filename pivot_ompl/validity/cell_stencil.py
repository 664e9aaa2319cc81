"""Obstacle boxes on the grid's lines, and where a convex body meets them: a stencil's dilation.

A floor imported from an occupancy map is walls of merged map cells: axis-aligned boxes whose
sides lie on the lines of a grid of the map's spacing. Where a field's grid is that grid (its
points on the boxes' corners), a body placed at grid point ``(i, j)`` meets the box cells
``(i + di, j + dj)`` for the offsets ``(di, dj)`` of the cells the body meets when placed at
the origin: one *stencil* per body and yaw, whatever the point. The positions where the body
meets any box are the occupied cells dilated by the stencil (:func:`stencil_hits`): a few
array operations per column of the stencil, for every box of the floor at once, instead of
one Minkowski sum per box rasterised.

The body meets a cell when their interiors overlap by more than :data:`PENETRATION` on every
separating axis (a body that only touches a cell's side, to rounding, does not meet it): the
points strictly inside a box's Minkowski sum with the body, as the sums' rasters count them.
"""

from __future__ import annotations

import numpy as np

#: Overlap (m) along every separating axis beyond which a body meets a cell (rounding below).
PENETRATION = 1e-9
#: How far (in cells) a box's side may lie from the grid's line and still be on it.
ALIGN_TOL = 1e-6


def aligned_boxes(pieces: list[np.ndarray], origin: tuple[float, float], resolution: float,
                  shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The pieces that are axis-aligned boxes on the grid's lines, and their cells.

    Args:
        pieces: convex pieces (``k x 2`` vertex arrays).
        origin: the floor point of grid position ``(0, 0)``.
        resolution: the grid's spacing (m).
        shape: ``(nx, ny)`` grid positions; cell ``(a, b)`` spans positions ``a..a+1`` and
            ``b..b+1``.

    Returns:
        ``(aligned, cells)``: a boolean per piece, and the ``(nx - 1, ny - 1)`` booleans of
        the cells the aligned pieces cover.
    """
    nx, ny = shape
    cells = np.zeros((max(nx - 1, 0), max(ny - 1, 0)), dtype=bool)
    aligned = np.zeros(len(pieces), dtype=bool)
    quads = np.flatnonzero(np.fromiter(map(len, pieces), dtype=np.int64,
                                       count=len(pieces)) == 4)
    if not len(quads):
        return aligned, cells
    pts = np.stack([pieces[i] for i in quads])  # (n, 4, 2)
    uv = (pts - np.asarray(origin)) / resolution
    iuv = np.round(uv)
    lo, hi = iuv.min(axis=1), iuv.max(axis=1)  # (n, 2) cells' corners
    ok = np.abs(uv - iuv).max(axis=(1, 2)) <= ALIGN_TOL
    ok &= np.all(hi > lo, axis=1) & np.all(lo >= 0, axis=1)
    ok &= (hi[:, 0] <= nx - 1) & (hi[:, 1] <= ny - 1)  # else partly outside the cells: summed
    # a box: every vertex on two of its sides, and all four corners among the vertices
    on = ((iuv[..., 0] == lo[:, None, 0]) | (iuv[..., 0] == hi[:, None, 0])) \
        & ((iuv[..., 1] == lo[:, None, 1]) | (iuv[..., 1] == hi[:, None, 1]))
    code = (iuv[..., 0] == hi[:, None, 0]).astype(int) + 2 * (iuv[..., 1] == hi[:, None, 1])
    corners = np.zeros((len(quads), 4), dtype=bool)
    np.put_along_axis(corners, code, True, axis=1)
    ok &= on.all(axis=1) & corners.all(axis=1)
    aligned[quads[ok]] = True
    for a0, b0, a1, b1 in np.column_stack([lo[ok], hi[ok]]).astype(int):
        cells[a0:a1, b0:b1] = True
    return aligned, cells


def stencil(body: np.ndarray, resolution: float) -> list[tuple[int, int, int]]:
    """The cells a convex body (CCW vertices, at the origin) meets, as runs per column.

    ``(di, dj0, dj1)``: the body meets cells ``(di, dj)`` for ``dj0 <= dj <= dj1`` (cell
    ``(di, dj)`` spans ``[di, di + 1] x [dj, dj + 1]`` times ``resolution``), by the
    separating axes of the body's edges and the cell's sides.
    """
    lo = np.floor(body.min(axis=0) / resolution).astype(int) - 1
    hi = np.ceil(body.max(axis=0) / resolution).astype(int) + 1
    di, dj = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1),
                         indexing="ij")
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) * resolution
    cell = np.stack([di, dj], axis=-1)[..., None, :] * resolution + corners  # (.., 4, 2)
    edges = np.roll(body, -1, axis=0) - body
    normals = np.column_stack([edges[:, 1], -edges[:, 0]])
    normals = normals[np.hypot(normals[:, 0], normals[:, 1]) > 0]
    axes = np.vstack([[1.0, 0.0], [0.0, 1.0],
                      normals / np.hypot(normals[:, 0], normals[:, 1])[:, None]])
    bp = body @ axes.T  # (k, axes)
    cp = cell @ axes.T  # (.., 4, axes)
    overlap = np.minimum(bp.max(axis=0), cp.max(axis=-2)) \
        - np.maximum(bp.min(axis=0), cp.min(axis=-2))
    meets = np.all(overlap > PENETRATION, axis=-1)
    runs = []
    for a in range(meets.shape[0]):
        js = np.flatnonzero(meets[a])
        if not len(js):
            continue
        breaks = np.flatnonzero(np.diff(js) > 1)
        for s, e in zip(np.r_[0, breaks + 1], np.r_[breaks, len(js) - 1], strict=True):
            runs.append((int(di[a, 0]), int(dj[a, js[s]]), int(dj[a, js[e]])))
    return runs


def cell_prefix(cells: np.ndarray, margin: int) -> np.ndarray:
    """Running counts of occupied cells along ``y``, padded by ``margin`` cells each side.

    Entry ``(a + margin, t)`` counts the occupied cells ``(a, b)`` with ``b + margin < t``
    (:func:`stencil_hits` reads a run's count as a difference of two).
    """
    nx, ny = cells.shape
    pad = np.zeros((nx + 1 + 2 * margin, ny + 2 + 2 * margin), dtype=np.int32)
    pad[margin:margin + nx, margin + 1:margin + 1 + ny] = cells
    return np.cumsum(pad, axis=1, out=pad)


def stencil_hits(prefix: np.ndarray, margin: int, runs: list[tuple[int, int, int]],
                 shape: tuple[int, int]) -> np.ndarray:
    """The grid positions where a body of stencil ``runs`` meets an occupied cell.

    ``prefix``: :func:`cell_prefix` of :func:`aligned_boxes`' cells, its ``margin`` above
    every offset of ``runs`` (the caller's to choose: more than the body's reach in cells).
    Returns ``(nx, ny)`` booleans: position ``(i, j)`` is hit when some run's cells
    ``(i + di, j + dj0..dj1)`` hold an occupied one.
    """
    nx, ny = shape
    m = margin
    out = np.zeros((nx, ny), dtype=bool)
    for a, j0, j1 in runs:
        rows = prefix[a + m:a + m + nx]
        out |= rows[:, j1 + m + 1:j1 + m + 1 + ny] > rows[:, j0 + m:j0 + m + ny]
    return out

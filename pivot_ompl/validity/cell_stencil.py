"""Obstacle boxes on the grid's lines, and where a convex body meets them: a stencil's dilation.

A floor imported from an occupancy map is walls of merged map cells: axis-aligned boxes whose
sides lie on the lines of a grid of the map's spacing. Where a field's grid is that grid (its
points on the boxes' corners), a body placed at grid point ``(i, j)`` meets the box cells
``(i + di, j + dj)`` for the offsets ``(di, dj)`` of the cells the body meets when placed at
the origin: one *stencil* per body and yaw, whatever the point. The positions where the body
meets any box are the occupied cells dilated by the stencil (:func:`stencil_hits`): a few
array operations per column of the stencil, for every box of the floor at once, instead of
one Minkowski sum per box rasterised. A field whose grid is every ``k``-th line of the map's
(a map finer than the field) places point ``(i, j)`` on cell corner ``(k i, k j)``: the same
stencil, read every ``k``-th row and column (:func:`stencil_hits`' ``stride``). The map's grid
is found from the boxes (:func:`grid_cell`, :func:`map_cell`).

The body meets a cell when their interiors overlap by more than :data:`PENETRATION` on every
separating axis (a body that only touches a cell's side, to rounding, does not meet it): the
points strictly inside a box's Minkowski sum with the body, as the sums' rasters count them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: Overlap (m) along every separating axis beyond which a body meets a cell (rounding below).
PENETRATION = 1e-9
#: How far (in cells) a box's side may lie from the grid's line and still be on it.
ALIGN_TOL = 1e-6
#: Least share of a floor's axis-aligned boxes on a grid's lines for :func:`grid_cell`.
GRID_SHARE = 0.9
#: Most cells of a map's grid over the bounds met by a stencil (:func:`map_cell`: 16 MB of
#: running counts); a larger floor's boxes are summed.
STENCIL_CELLS = 1 << 22
#: Largest boxes whose lower corner :func:`grid_origin` tries as the map grid's origin.
ORIGIN_TRIES = 4


def _rectangles(pieces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The pieces that are axis-aligned rectangles: their indices and ``(n, 4)`` bounds.

    Four vertices, each on two of the bounds' sides (to :data:`ALIGN_TOL` of the piece's
    size), all four corners among them.
    """
    quads = np.flatnonzero(np.fromiter(map(len, pieces), dtype=np.int64,
                                       count=len(pieces)) == 4)
    if not len(quads):
        return quads, np.zeros((0, 4))
    pts = np.stack([pieces[i] for i in quads])  # (n, 4, 2)
    lo, hi = pts.min(axis=1), pts.max(axis=1)
    tol = ALIGN_TOL * (hi - lo).max(axis=1)[:, None, None]
    at_hi = np.abs(pts - hi[:, None, :]) <= tol
    at_lo = np.abs(pts - lo[:, None, :]) <= tol
    code = at_hi[..., 0].astype(int) + 2 * at_hi[..., 1]
    corners = np.zeros((len(quads), 4), dtype=bool)
    np.put_along_axis(corners, code, True, axis=1)
    ok = (at_hi | at_lo).all(axis=(1, 2)) & corners.all(axis=1) & np.all(hi > lo, axis=1)
    return quads[ok], np.column_stack([lo[ok], hi[ok]])


def grid_cell(pieces: list[np.ndarray], origin: tuple[float, float], *,
              least: int) -> float | None:
    """The spacing of the grid through ``origin`` whose lines carry the axis-aligned boxes.

    A floor imported from an occupancy map is boxes of merged map cells, every side on a
    line of the map's grid: the spacing is the boxes' shortest side (to 12 digits) where at least
    ``least`` boxes, and :data:`GRID_SHARE` of the axis-aligned ones, have every side on
    the lines of that spacing through ``origin`` (m); ``None`` otherwise.
    """
    _, rect = _rectangles(pieces)
    if len(rect) < max(least, 1):
        return None
    cell = float(f"{np.min(rect[:, 2:] - rect[:, :2]):.12g}")  # the map's, not its rounding
    uv = (rect - np.tile(np.asarray(origin, dtype=float), 2)) / cell
    on = int(np.count_nonzero(np.abs(uv - np.round(uv)).max(axis=1) <= ALIGN_TOL))
    return cell if on >= least and on >= GRID_SHARE * len(rect) else None


def grid_origin(pieces: list[np.ndarray], *, least: int
                ) -> tuple[tuple[float, float], float] | None:
    """A point on the lines of the map grid that carries the axis-aligned boxes, and its cell (m).

    A floor turned by a map's own angle (its boxes axis-aligned in the turned frame) has
    its grid's lines anywhere: the lower corners of its largest axis-aligned boxes are
    tried as the grid's origin (:func:`grid_cell`, at least ``least`` boxes on it); the
    first that carries the grid, with that grid's cell, else ``None``.
    """
    _, rect = _rectangles(pieces)
    if len(rect) < max(least, 1):
        return None
    area = np.prod(rect[:, 2:] - rect[:, :2], axis=1)
    for i in np.argsort(-area)[:ORIGIN_TRIES]:
        origin = (float(rect[i, 0]), float(rect[i, 1]))
        if (cell := grid_cell(pieces, origin, least=least)) is not None:
            return origin, cell
    return None


def map_cell(pieces: list[np.ndarray], bounds: tuple[float, float, float, float], *,
             least: int) -> float | None:
    """The cell of the map grid whose boxes a field over ``bounds`` meets by a stencil (m).

    :func:`grid_cell` through the bounds' corner (at least ``least`` boxes on it), its
    cells over the bounds at most :data:`STENCIL_CELLS`; ``None`` where there is none. A
    field whose spacing is a whole multiple of it may dilate the boxes' cells.
    """
    cell = grid_cell(pieces, (bounds[0], bounds[1]), least=least)
    area = (bounds[2] - bounds[0]) * (bounds[3] - bounds[1])
    if cell is None or area > STENCIL_CELLS * cell * cell:
        return None
    return cell


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
    index, rect = _rectangles(pieces)
    if not len(index):
        return aligned, cells
    uv = (rect - np.tile(np.asarray(origin, dtype=float), 2)) / resolution
    iuv = np.round(uv)
    lo, hi = iuv[:, :2], iuv[:, 2:]  # (n, 2) cells' corners
    ok = np.abs(uv - iuv).max(axis=1) <= ALIGN_TOL
    ok &= np.all(hi > lo, axis=1) & np.all(lo >= 0, axis=1)
    ok &= (hi[:, 0] <= nx - 1) & (hi[:, 1] <= ny - 1)  # else partly outside the cells: summed
    aligned[index[ok]] = True
    for a0, b0, a1, b1 in iuv[ok].astype(int):
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
    # each column's runs at once: where a run starts (+1) and past where it ends (-1)
    step = np.diff(np.pad(meets, ((0, 0), (1, 1))).astype(np.int8), axis=1)
    starts, ends = np.argwhere(step == 1), np.argwhere(step == -1)  # column-major, in order
    return [(int(di[a, 0]), int(dj[a, j0]), int(dj[a, j1 - 1]))
            for (a, j0), (_, j1) in zip(starts.tolist(), ends.tolist(), strict=True)]


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
                 shape: tuple[int, int], *, stride: int = 1,
                 at: tuple[int, int] = (0, 0)) -> np.ndarray:
    """The grid positions where a body of stencil ``runs`` meets an occupied cell.

    ``prefix``: :func:`cell_prefix` of :func:`aligned_boxes`' cells, its ``margin`` above
    every offset of ``runs`` (the caller's to choose: more than the body's reach in cells).
    ``stride``: the positions asked are every ``stride``-th of the cells' grid (a grid whose
    spacing is that many cells). ``at``: the first grid position of the block asked (a
    block of ``shape`` positions inside the grid). Returns ``shape`` booleans: position
    ``(i, j)`` of the block is hit when some run's cells
    ``(stride * (at[0] + i) + di, stride * (at[1] + j) + dj0..dj1)`` hold an occupied one.
    """
    nx, ny = shape
    k = stride
    mx, my = margin + k * at[0], margin + k * at[1]
    out = np.zeros((nx, ny), dtype=bool)
    for a, j0, j1 in runs:
        rows = prefix[a + mx:a + mx + k * (nx - 1) + 1:k]
        out |= rows[:, j1 + my + 1:j1 + my + 2 + k * (ny - 1):k] \
            > rows[:, j0 + my:j0 + my + 1 + k * (ny - 1):k]
    return out


@dataclass(frozen=True)
class CellDilation:
    """The boxes of a floor on a map's grid, met by a stencil's dilation of their cells.

    For a field whose grid (positions from the bounds' corner, ``resolution`` apart) is every
    ``stride``-th line of the map's (:func:`cell_dilation`).

    Attributes:
        aligned: per obstacle piece, whether it is one of those boxes (the others are the
            caller's to sum).
        prefix: :func:`cell_prefix` of the boxes' cells.
        margin: the prefix's padding (cells), above the bodies' reach.
        stride: the field's spacing in map cells.
        cell: the map's cell (m).
    """

    aligned: np.ndarray
    prefix: np.ndarray
    margin: int
    stride: int
    cell: float

    def stencil(self, body: np.ndarray) -> list[tuple[int, int, int]]:
        """The map cells a convex ``body`` (vertices relative to its position) meets."""
        return stencil(body, self.cell)

    def hits(self, runs: list[tuple[int, int, int]], shape: tuple[int, int], *,
             at: tuple[int, int] = (0, 0)) -> np.ndarray:
        """Where a body of stencil ``runs`` (:meth:`stencil`) meets a box.

        ``shape`` booleans over the block of grid positions from ``at``
        (:func:`stencil_hits`).
        """
        return stencil_hits(self.prefix, self.margin, runs, shape, stride=self.stride, at=at)


def cell_dilation(pieces: list[np.ndarray], bounds: tuple[float, float, float, float],
                  resolution: float, shape: tuple[int, int], *, reach: float,
                  least: Callable[[int], int]) -> CellDilation | None:
    """The boxes a field over ``bounds`` may meet by a stencil, where there are enough.

    The map's grid: :func:`map_cell` through the bounds' corner (at least ``least(1)`` boxes
    on it), the field's spacing ``resolution`` a whole multiple ``k`` of its cell, at least
    ``least(k)`` boxes on it (:func:`aligned_boxes`); ``shape``: the field's ``(nx, ny)``
    positions; ``reach``: the farthest (m) a body's point lies from its position. ``None``
    where the floor is no such grid (every piece is then summed).
    """
    cell = map_cell(pieces, bounds, least=least(1))
    if cell is None:
        return None
    k = max(1, int(round(resolution / cell)))
    if abs(resolution - k * cell) > ALIGN_TOL * cell:
        return None
    fine = resolution / k  # the grid's positions on the cells' lines exactly
    b = bounds
    cells_shape = (max((shape[0] - 1) * k, int(math.floor((b[2] - b[0]) / fine))) + 1,
                   max((shape[1] - 1) * k, int(math.floor((b[3] - b[1]) / fine))) + 1)
    aligned, occupied = aligned_boxes(pieces, (b[0], b[1]), fine, cells_shape)
    if aligned.sum() < least(k):
        return None
    margin = int(math.ceil(reach / fine)) + 3
    return CellDilation(aligned, cell_prefix(occupied, margin), margin, k, fine)

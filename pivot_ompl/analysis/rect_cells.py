"""Raster cells inside axis-aligned rectangles and near rectangles, all rectangles at once.

A map's obstacles are boxes on its pixels, and their convex pieces
(:func:`~pivot_ompl.validity.footprints.obstacle_pieces`) are axis-aligned rectangles. For
such a piece :func:`~pivot_ompl.analysis.raster_cover.obstacle_cells`' corner test separates:
an edge parallel to x gives a side value that depends on the corner's ``y`` alone (its other
term is a signed zero), one parallel to y on its ``x`` alone. So a corner is inside when its
``x`` passes the two vertical edges and its ``y`` the two horizontal ones, and the cells
whose four corners pass form one block of the piece's candidate cells: all of them but
perhaps the first or last column or row, whose outer corner lies within the candidates'
slack of the piece's side. :func:`rect_cells` evaluates the same floating-point side values
as the per-piece test at those outer corners only, for every rectangle at once, and marks
the blocks by a summed difference array: the same cells, bit for bit, without a Python loop
per piece.

:func:`near_rectangles` and :func:`near_turned_rectangles` bracket each cell centre's distance
to the nearest rectangle (axis-aligned, or of any direction: a turned map's), leaving GEOS only
the centres within round-off of the distance asked.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pivot_ompl.analysis.raster import FloorRaster

#: Slack (in cells) of the candidate cells round a piece, as the per-piece test's.
SLACK = 1e-6


def _four_cornered(pieces: list[np.ndarray],
                   test: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """``test`` of the four-cornered ``pieces``' edges (``(m, 4, 2)``), ``False`` for others."""
    out = np.zeros(len(pieces), dtype=bool)
    four = [n for n, piece in enumerate(pieces) if np.shape(piece) == (4, 2)]
    if four:
        p = np.array([pieces[n] for n in four], dtype=float)
        out[four] = test(np.roll(p, -1, axis=1) - p)
    return out


def axis_rectangles(pieces: list[np.ndarray]) -> np.ndarray:
    """Which ``pieces`` are four-cornered with every edge parallel to an axis (boolean)."""
    return _four_cornered(pieces, lambda e: np.all((e[:, :, 0] == 0.0) | (e[:, :, 1] == 0.0),
                                                   axis=1))


def rect_cells(raster: FloorRaster, rects: np.ndarray, eps: float) -> np.ndarray:
    """Cells (boolean ``raster.shape``) lying wholly inside one of ``rects``.

    ``rects``: ``(m, 4, 2)`` corners of axis-aligned rectangles (:func:`axis_rectangles`),
    in any order of turn; ``eps``: the corner test's round-off margin (m). The cells are
    those the per-piece corner test of :func:`~pivot_ompl.analysis.raster_cover.
    obstacle_cells` marks (module docstring).
    """
    (x0, y0), h = raster.origin, raster.cell
    nx, ny = raster.shape
    out = np.zeros((nx, ny), dtype=bool)
    p = np.asarray(rects, dtype=float).reshape(-1, 4, 2)
    if not len(p):
        return out
    q = np.roll(p, -1, axis=1)
    twice_area = np.sum(p[:, :, 0] * q[:, :, 1] - q[:, :, 0] * p[:, :, 1], axis=1)
    keep = np.abs(twice_area) >= 1e-12
    p, q, twice_area = p[keep], q[keep], twice_area[keep]
    i0 = np.maximum(0, np.ceil((p[:, :, 0].min(axis=1) - x0) / h - SLACK)).astype(np.int64)
    i1 = np.minimum(nx, np.floor((p[:, :, 0].max(axis=1) - x0) / h + SLACK)).astype(np.int64)
    j0 = np.maximum(0, np.ceil((p[:, :, 1].min(axis=1) - y0) / h - SLACK)).astype(np.int64)
    j1 = np.minimum(ny, np.floor((p[:, :, 1].max(axis=1) - y0) / h + SLACK)).astype(np.int64)
    ex, ey = q[:, :, 0] - p[:, :, 0], q[:, :, 1] - p[:, :, 1]
    sign = np.copysign(1.0, twice_area)[:, None]
    margin = -eps * np.hypot(ex, ey)

    def passes(xv: np.ndarray, yv: np.ndarray, edges: np.ndarray) -> np.ndarray:
        """Whether the corners ``(xv, yv)`` pass the ``edges`` (per rectangle, per edge)."""
        side = sign * (ex * (yv[:, None] - p[:, :, 1]) - ey * (xv[:, None] - p[:, :, 0]))
        return np.all((side >= margin) | ~edges, axis=1)

    vertical, horizontal = ex == 0.0, ey == 0.0  # a zero-length edge passes every corner
    xl, xr = x0 + i0 * h, x0 + i1 * h  # the candidates' outer corners, as the loop's
    yl, yr = y0 + j0 * h, y0 + j1 * h
    ia = i0 + ~passes(xl, yl, vertical & ~horizontal)
    ib = i1 - ~passes(xr, yl, vertical & ~horizontal)
    ja = j0 + ~passes(xl, yl, horizontal & ~vertical)
    jb = j1 - ~passes(xl, yr, horizontal & ~vertical)
    some = (i1 > i0) & (j1 > j0) & (ib > ia) & (jb > ja)
    if not some.any():
        return out
    ia, ib, ja, jb = ia[some], ib[some], ja[some], jb[some]
    a0, b0 = int(ia.min()), int(ja.min())  # the block the rectangles span, not the floor
    a1, b1 = int(ib.max()), int(jb.max())
    marks = np.zeros((a1 - a0 + 1, b1 - b0 + 1), dtype=np.int32)
    for di, dj, s in ((ia, ja, 1), (ib, ja, -1), (ia, jb, -1), (ib, jb, 1)):
        np.add.at(marks, (di - a0, dj - b0), s)
    np.cumsum(marks, axis=0, dtype=np.int32, out=marks)
    np.cumsum(marks, axis=1, dtype=np.int32, out=marks)
    out[a0:a1, b0:b1] = marks[:-1, :-1] > 0
    return out


#: Distance (m) within which a centre's distance to a rectangle is left to GEOS: the
#: arithmetic one below and GEOS's differ by round-off only, far less than this.
NEAR_MARGIN = 1e-9
#: Cell-rectangle pairs at most per batch of :func:`near_rectangles` (its memory).
PAIRS = 1_000_000


def near_rectangles(raster: FloorRaster, boxes: np.ndarray, cells: np.ndarray,
                    distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Which of ``cells`` have their centre within ``distance`` of one of ``boxes``.

    ``boxes``: ``(n, 4)`` axis-aligned rectangles ``x0, y0, x1, y1``; ``cells``: flat indices
    of ``raster``'s cells. ``(surely, maybe)``: boolean over ``cells``; ``surely``: some box
    lies closer than ``distance`` less :data:`NEAR_MARGIN` (the distance, computed from the
    box's sides, is then below ``distance`` however it is rounded); ``maybe``: within
    ``distance`` plus the margin. A centre in neither is farther than ``distance`` from
    every box; one in ``maybe`` alone is for an exact test to decide. Each box's cells are
    read in the block round it (no floor-sized temporary but an index of ``cells``).
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)

    def away(box: np.ndarray, cx: np.ndarray, cy: np.ndarray) -> np.ndarray:
        dx = np.maximum(np.maximum(boxes[box, 0] - cx, cx - boxes[box, 2]), 0.0)
        dy = np.maximum(np.maximum(boxes[box, 1] - cy, cy - boxes[box, 3]), 0.0)
        return np.hypot(dx, dy)

    return _near(raster, boxes, cells, distance, away)


def turned_rectangles(pieces: list[np.ndarray]) -> np.ndarray:
    """Which ``pieces`` are rectangles (four corners, right angles) of any direction."""

    def square(e: np.ndarray) -> np.ndarray:
        dot = np.abs(np.sum(e * np.roll(e, -1, axis=1), axis=2))
        size = np.hypot(e[:, :, 0], e[:, :, 1])
        return np.all(dot <= 1e-9 * size * np.roll(size, -1, axis=1), axis=1) & \
            np.all(size > 0.0, axis=1)

    return _four_cornered(pieces, square)


def near_turned_rectangles(raster: FloorRaster, corners: np.ndarray, cells: np.ndarray,
                           distance: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`near_rectangles` of rectangles of any direction (``(n, 4, 2)`` corners in turn).

    Each centre's distance is taken in the rectangle's own axes (its offset from the
    rectangle's centre projected on its two sides' directions, less their half lengths),
    its round-off far below :data:`NEAR_MARGIN`: ``(surely, maybe)`` as there.
    """
    p = np.asarray(corners, dtype=float).reshape(-1, 4, 2)
    centre = p.mean(axis=1)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 1]
    l1, l2 = np.hypot(e1[:, 0], e1[:, 1]), np.hypot(e2[:, 0], e2[:, 1])
    u, v = e1 / l1[:, None], e2 / l2[:, None]
    boxes = np.column_stack([p[:, :, 0].min(axis=1), p[:, :, 1].min(axis=1),
                             p[:, :, 0].max(axis=1), p[:, :, 1].max(axis=1)])

    def away(box: np.ndarray, cx: np.ndarray, cy: np.ndarray) -> np.ndarray:
        ox, oy = cx - centre[box, 0], cy - centre[box, 1]
        da = np.maximum(np.abs(ox * u[box, 0] + oy * u[box, 1]) - 0.5 * l1[box], 0.0)
        db = np.maximum(np.abs(ox * v[box, 0] + oy * v[box, 1]) - 0.5 * l2[box], 0.0)
        return np.hypot(da, db)

    return _near(raster, boxes, cells, distance, away)


def _near(raster: FloorRaster, boxes: np.ndarray, cells: np.ndarray, distance: float,
          away: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
          ) -> tuple[np.ndarray, np.ndarray]:
    """``(surely, maybe)`` of :func:`near_rectangles`, each piece's distance by ``away``.

    ``boxes``: the pieces' bounding boxes (``(n, 4)``), whose blocks grown by ``distance``
    hold every cell ``away`` may find near; ``away(piece indices, centres' x, y)``.
    """
    surely = np.zeros(len(cells), dtype=bool)
    maybe = np.zeros(len(cells), dtype=bool)
    if not len(boxes) or not len(cells):
        return surely, maybe
    (x0, y0), h = raster.origin, raster.cell
    nx, ny = raster.shape
    where = np.full(nx * ny, -1, dtype=np.int64)
    where[cells] = np.arange(len(cells))
    reach = distance + NEAR_MARGIN
    i0 = np.clip(np.floor((boxes[:, 0] - reach - x0) / h - 0.5).astype(np.int64) - 1, 0, nx)
    i1 = np.clip(np.ceil((boxes[:, 2] + reach - x0) / h - 0.5).astype(np.int64) + 2, 0, nx)
    j0 = np.clip(np.floor((boxes[:, 1] - reach - y0) / h - 0.5).astype(np.int64) - 1, 0, ny)
    j1 = np.clip(np.ceil((boxes[:, 3] + reach - y0) / h - 0.5).astype(np.int64) + 2, 0, ny)
    sizes = np.maximum(i1 - i0, 0) * np.maximum(j1 - j0, 0)
    gx, gy = raster.gx.ravel(), raster.gy.ravel()
    ends = np.cumsum(sizes)
    start = 0
    while start < len(boxes):
        stop = max(start + 1, int(np.searchsorted(ends, ends[start] - sizes[start] + PAIRS)))
        part = np.arange(start, min(stop, len(boxes)))
        start = int(part[-1]) + 1
        n = sizes[part]
        if not n.sum():
            continue
        box = np.repeat(part, n)
        at = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        width = (j1 - j0)[box]
        flat = (i0[box] + at // width) * ny + j0[box] + at % width
        pos = where[flat]
        keep = pos >= 0
        flat, pos, box = flat[keep], pos[keep], box[keep]
        d = away(box, gx[flat], gy[flat])
        surely[pos[d < distance - NEAR_MARGIN]] = True
        maybe[pos[d <= reach]] = True
    return surely, maybe

"""The regrasp bound's free cover on a raster: the same over-approximation, built at scale.

:mod:`~pivot_ompl.analysis.regrasp_bound` keeps, per yaw bin ``b`` and grasp ``k``, the exact
polygons ``F(b, k)`` of box positions where the held assembly's eroded bodies may be free
(its docstring: the bodies ``E`` of both parts, turned to the bin's centre and offset by the
net erosion; the bounds shrunk by their extents). Unions of thousands of Minkowski hulls per
bin make that slow on real floors. This module covers the same sets with raster cells,
*conservative by construction*: a cell is marked blocked only when every point of it lies
outside ``F(b, k)``, so every free position lies in a free cell.

**Obstacle cells.** A cell is an *obstacle cell* when it lies wholly inside one obstacle piece
(:func:`~pivot_ompl.validity.footprints.obstacle_pieces`, themselves subsets of the
obstacles): its four corners inside the convex piece (to :data:`EPS`: a map's boxes are
exact to its pixels, whose edges are cell edges when the cell is a multiple of a pixel).
Axis-aligned rectangles (a map's pieces) are tested all at once, with the same corner test at
their candidate blocks' outer corners (:mod:`~pivot_ompl.analysis.rect_cells`).

**Blocked cells.** Let ``c'`` be a cell and ``c`` an obstacle cell whose centre lies at offset
``e = centre(c) - centre(c')`` with ``e`` in the body ``E``. For every point ``p`` of ``c'``,
``p + e`` is the same point of ``c`` (cells are translates), inside an obstacle, and inside
the body placed at ``p``: so the body meets the obstacle wherever the box's centre is in
``c'``, and ``c'`` is blocked. The offsets are the lattice points of ``E`` (row by row, an
interval of columns per row: ``E`` is convex), and the blocked cells are the obstacle cells
dilated by them: per row of offsets one window test on prefix sums (no polygon is built).
A cell is kept inside the bounds when it meets the rectangle of allowed positions.

**Connectivity.** A continuous path of the box's centre crosses cells one after another,
8-adjacent, each holding a free point (so free); a path crossing from one bin to the next, or
regrasping, does so at a point free in both layers, so in a cell free in both. Connected
pieces are scipy's labelling of the free cells with 8-neighbours (``ndimage.label``: one C
pass per layer, where Python would visit every cell).

Cells are coarser than the polygons' exactness (a passage looks up to about two cells wider
on the raster): the raster's bound is never above the polygons' but may be below it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.rect_cells import axis_rectangles, rect_cells
from pivot_ompl.analysis.regrasp_bound import ROUND_OFF, Body, held_bodies, yaw_bins
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

#: Round-off margin (m) of the cell tests: a cell corner may lie this far outside its piece
#: (the bodies are eroded by a further ``ROUND_OFF``, 100 times more, so the blocked cells stay
#: blocked), lattice offsets lie this far inside the body, cells meet the bounds this loosely.
EPS = 1e-9
#: Cells at most per layer (a larger floor gets larger cells).
MAX_CELLS = 400_000

_EIGHT = np.ones((3, 3), dtype=bool)

#: A row of lattice offsets: ``(dj, lo, hi)``, the offsets ``(di, dj)`` with ``lo <= di <= hi``.
Row = tuple[int, int, int]


def obstacle_cells(raster: FloorRaster, pieces: list[np.ndarray],
                   should_stop: Callable[[], bool] | None = None) -> np.ndarray:
    """Cells (boolean ``raster.shape``) lying wholly inside one of the convex ``pieces``."""
    (x0, y0), h = raster.origin, raster.cell
    nx, ny = raster.shape
    rect = axis_rectangles(pieces)  # a map's pieces: all at once (the same cells)
    out = rect_cells(raster, np.array([pieces[n] for n in np.flatnonzero(rect)], dtype=float),
                     EPS)
    for n, piece in enumerate(pieces):
        if n % 256 == 0 and should_stop is not None and should_stop():
            raise Interrupted("the raster's obstacle cells")
        if rect[n]:
            continue
        p = np.asarray(piece, dtype=float)
        q = np.roll(p, -1, axis=0)
        twice_area = float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))
        if abs(twice_area) < 1e-12:
            continue
        # candidate cells with a little slack: the corner test below decides (a box edge on a
        # cell edge is often a hair inside it in floating point)
        i0 = max(0, math.ceil((p[:, 0].min() - x0) / h - 1e-6))
        i1 = min(nx, math.floor((p[:, 0].max() - x0) / h + 1e-6))
        j0 = max(0, math.ceil((p[:, 1].min() - y0) / h - 1e-6))
        j1 = min(ny, math.floor((p[:, 1].max() - y0) / h + 1e-6))
        if i1 <= i0 or j1 <= j0:
            continue
        xs = x0 + np.arange(i0, i1 + 1) * h
        ys = y0 + np.arange(j0, j1 + 1) * h
        ex, ey = q[:, 0] - p[:, 0], q[:, 1] - p[:, 1]
        side = math.copysign(1.0, twice_area) * (
            ex * (ys[None, :, None] - p[:, 1]) - ey * (xs[:, None, None] - p[:, 0]))
        corner = np.all(side >= -EPS * np.hypot(ex, ey), axis=2)
        out[i0:i1, j0:j1] |= corner[:-1, :-1] & corner[1:, :-1] & corner[:-1, 1:] & corner[1:, 1:]
    return out


def lattice_rows(points: np.ndarray, cell: float) -> list[Row]:
    """The lattice offsets ``(di, dj) * cell`` inside the convex polygon ``points``, by row."""
    y = points[:, 1]
    j0 = math.ceil((y.min() + EPS) / cell)
    j1 = math.floor((y.max() - EPS) / cell)
    if j1 < j0:
        return []
    rows = np.arange(j0, j1 + 1)
    yy = rows[:, None] * cell
    a, b = points, np.roll(points, -1, axis=0)
    dy = b[:, 1] - a[:, 1]
    crossing = ((yy >= np.minimum(a[:, 1], b[:, 1])) & (yy <= np.maximum(a[:, 1], b[:, 1]))
                & (dy != 0))
    t = np.divide(yy - a[:, 1], dy, out=np.zeros((len(rows), len(dy))), where=dy != 0)
    x = np.where(crossing, a[:, 0] + t * (b[:, 0] - a[:, 0]), np.nan)
    seen = crossing.any(axis=1)
    out = []
    for r, xl, xr in zip(rows[seen].tolist(), np.nanmin(x[seen], axis=1).tolist(),
                         np.nanmax(x[seen], axis=1).tolist(), strict=True):
        lo, hi = math.ceil((xl + EPS) / cell), math.floor((xr - EPS) / cell)
        if lo <= hi:
            out.append((r, lo, hi))
    return out


def merged_rows(rows: list[Row]) -> list[Row]:
    """The same offsets with overlapping or adjacent intervals of a row joined."""
    by_row: dict[int, list[tuple[int, int]]] = {}
    for r, lo, hi in rows:
        by_row.setdefault(r, []).append((lo, hi))
    out = []
    for r, spans in by_row.items():
        spans.sort()
        lo, hi = spans[0]
        for a, b in spans[1:]:
            if a <= hi + 1:
                hi = max(hi, b)
            else:
                out.append((r, lo, hi))
                lo, hi = a, b
        out.append((r, lo, hi))
    return out


class Dilation:
    """Obstacle cells dilated by lattice offsets, by windows on column prefix sums.

    Args:
        obstacles: the obstacle cells (boolean ``nx x ny``).
        reach: largest offset (cells) asked for, either way.
    """

    def __init__(self, obstacles: np.ndarray, reach: int) -> None:
        """Prefix sums along the first axis, padded by ``reach`` on both ends."""
        nx, ny = obstacles.shape
        self.shape = (nx, ny)
        self.pad = reach + 2
        sums = np.zeros((nx + 1 + 2 * self.pad, ny), dtype=np.int32)
        sums[self.pad + 1:self.pad + 1 + nx] = np.cumsum(obstacles, axis=0, dtype=np.int32)
        sums[self.pad + 1 + nx:] = sums[self.pad + nx]
        self.sums = sums

    def blocked(self, rows: list[Row]) -> np.ndarray:
        """Cells ``c'`` with an obstacle cell at ``c' + (di, dj)`` for an offset of ``rows``."""
        nx, ny = self.shape
        out = np.zeros((nx, ny), dtype=bool)
        base = self.pad
        for dj, lo, hi in rows:
            if max(-lo, hi + 1) > self.pad:
                raise ValueError(f"offset row {(dj, lo, hi)} beyond the padding {self.pad}")
            jl, jr = max(0, -dj), min(ny, ny - dj)
            if jl >= jr:
                continue
            top = self.sums[base + hi + 1:base + hi + 1 + nx, jl + dj:jr + dj]
            bottom = self.sums[base + lo:base + lo + nx, jl + dj:jr + dj]
            out[:, jl:jr] |= top > bottom
        return out


def cells_meeting(raster: FloorRaster, lo: tuple[float, float], hi: tuple[float, float]
                  ) -> np.ndarray:
    """Cells (boolean ``raster.shape``) that meet the rectangle ``[lo, hi]`` (none if empty)."""
    (x0, y0), h = raster.origin, raster.cell
    nx, ny = raster.shape
    if lo[0] > hi[0] or lo[1] > hi[1]:
        return np.zeros((nx, ny), dtype=bool)
    xs, ys = x0 + np.arange(nx) * h, y0 + np.arange(ny) * h
    in_x = (xs <= hi[0] + EPS) & (xs + h >= lo[0] - EPS)
    in_y = (ys <= hi[1] + EPS) & (ys + h >= lo[1] - EPS)
    return in_x[:, None] & in_y[None, :]


def layer_reach(cell: float, bounds: tuple[float, float, float, float], parts: list[Body],
                yaw: float, inside: list[float], clear: list[float],
                ) -> tuple[list[float], list[float], list[Row]]:
    """Where a layer's reference point keeps the bodies in the bounds, and what they meet.

    ``(lo, hi, rows)``: the corners of the rectangle of reference points that keep every
    part, eroded by its ``inside``, within ``bounds``; and the lattice rows (cells of
    ``cell`` m) of the parts offset by their ``clear`` (:func:`free_layer`'s arguments).
    """
    x0, y0, x1, y1 = bounds
    lo, hi = [x0, y0], [x1, y1]
    rows: list[Row] = []
    for part, d_in, d_clear in zip(parts, inside, clear, strict=True):
        e = part.offset_points(yaw, d_in)
        if e is not None:
            lo = [max(lo[0], x0 - e[:, 0].min()), max(lo[1], y0 - e[:, 1].min())]
            hi = [min(hi[0], x1 - e[:, 0].max()), min(hi[1], y1 - e[:, 1].max())]
        e = part.offset_points(yaw, d_clear + ROUND_OFF)
        if e is not None:
            rows += lattice_rows(e, cell)
    return lo, hi, rows


def free_layer(raster: FloorRaster, dilation: Dilation, bounds: tuple[float, float, float,
               float], parts: list[Body], yaw: float, inside: list[float],
               clear: list[float]) -> tuple[np.ndarray, int]:
    """Labelled free cells of one yaw bin and grasp (0 blocked; pieces ``1..count``).

    ``inside``: per part, the erosion (m) of the body kept inside the bounds; ``clear``: the
    net offset (m, > 0 erodes, < 0 grows) of the body kept clear of the obstacles (as
    :func:`~pivot_ompl.analysis.regrasp_bound.free_cover`).
    """
    lo, hi, rows = layer_reach(raster.cell, bounds, parts, yaw, inside, clear)
    free = cells_meeting(raster, (lo[0], lo[1]), (hi[0], hi[1]))
    if rows:
        free &= ~dilation.blocked(merged_rows(rows))
    return piece_labels(free)


def piece_labels(free: np.ndarray) -> tuple[np.ndarray, int]:
    """8-connected pieces of ``free`` labelled ``1..count`` (0 elsewhere), and ``count``.

    In the smallest integer type that holds ``count`` (``uint8`` for the usual few hundred
    pieces a layer or fewer: a floor's 152 layers then take a quarter of ``int32``'s memory).
    """
    try:
        labels, count = ndimage.label(free, structure=_EIGHT, output=np.int16)
    except RuntimeError:  # more pieces than int16 holds
        labels, count = ndimage.label(free, structure=_EIGHT, output=np.int32)
    if count <= np.iinfo(np.uint8).max:
        labels = labels.astype(np.uint8)
    return labels, int(count)


@dataclass
class RasterCover:
    """The raster over-approximation of the free states of every grasp (module docstring).

    Attributes:
        raster: the cells.
        bins: yaw bins (even); bin ``b`` holds yaws ``-pi + [b, b + 1) * 2 pi / bins``.
        layers: per ``(grasp % 2, bin)``, the labelled free cells (0 blocked) and their
            number of pieces.
        pieces: the convex obstacle pieces the obstacle cells were found in (for a finer
            cover of part of the floor, :mod:`~pivot_ompl.analysis.raster_refine`).
    """

    raster: FloorRaster
    bins: int
    layers: dict[tuple[int, int], tuple[np.ndarray, int]]
    pieces: list[np.ndarray] = field(default_factory=list)
    _extents: dict[tuple[int, int], list] = field(default_factory=dict, repr=False)

    def extent(self, layer: tuple[int, int], label: int) -> tuple[slice, slice]:
        """The block of cells holding piece ``label`` of ``layer`` (``(grasp % 2, bin)``)."""
        if layer not in self._extents:
            self._extents[layer] = ndimage.find_objects(self.layers[layer][0])
        return self._extents[layer][label - 1]

    def bin_of(self, yaw: float) -> int:
        """The bin holding ``yaw`` (any angle)."""
        return int((wrap_angle(yaw) + math.pi) // (2.0 * math.pi / self.bins)) % self.bins

    def labels(self, b: int, grasp: int) -> np.ndarray:
        """Labelled cells of bin ``b`` at ``grasp`` (grasp ``k + 2``: ``k`` a half turn on)."""
        return self.layers[(grasp % 2, (b + (self.bins // 2) * ((grasp % 4) // 2))
                            % self.bins)][0]

    def holding(self, pose: Pose, grasp: int) -> list[int]:
        """Labels of the free cells holding ``pose``'s position (all on a cell's edge)."""
        (x0, y0), h = self.raster.origin, self.raster.cell
        nx, ny = self.raster.shape
        xs = {math.floor((pose[0] - x0 + s) / h) for s in (-EPS, EPS)}
        ys = {math.floor((pose[1] - y0 + s) / h) for s in (-EPS, EPS)}
        lab = self.labels(self.bin_of(pose[2]), grasp)
        return sorted({int(lab[i, j]) for i in xs for j in ys
                       if 0 <= i < nx and 0 <= j < ny and lab[i, j]})

    def covers(self, pose: Pose, grasp: int) -> bool:
        """Whether the state may be free (``False`` proves it is in collision)."""
        return bool(self.holding(pose, grasp))


def floor_raster(bounds: tuple[float, float, float, float], cell: float) -> FloorRaster:
    """Cells of side ``cell`` over ``bounds``, or a whole multiple of it past :data:`MAX_CELLS`.

    (A map's boxes are exact to its pixels: cells a multiple of the pixel keep their edges.)
    """
    x0, y0, x1, y1 = bounds
    need = math.sqrt((x1 - x0) * (y1 - y0) / MAX_CELLS)
    side = cell * max(1, math.ceil(need / cell - 1e-9))
    return FloorRaster(bounds, min_cell=side, max_cells=MAX_CELLS)


def raster_cover(scene: Scene, *, cell: float, resolution: float | None = None,
                 tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                 should_stop: Callable[[], bool] | None = None) -> RasterCover | None:
    """The :class:`RasterCover` of ``scene``; ``None`` if ``should_stop`` said stop.

    Args:
        scene: the scene.
        cell: the cells' side (m; at least: a floor of more than :data:`MAX_CELLS` cells gets
            larger ones).
        resolution: largest erosion (m) of the rotation within a yaw bin (default: half the
            cell, the two losses alike).
        tolerance: the swept checks' tolerance (m), added to every erosion.
        clearance: distance (m) the checkers keep every body from the obstacles.
        should_stop: polled once per layer (and while the obstacle cells are found).
    """
    raster = floor_raster(scene.bounds, cell)
    n = yaw_bins(scene, 0.5 * raster.cell if resolution is None else resolution)
    try:
        pieces = obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))
        obstacles = obstacle_cells(raster, pieces, should_stop)
    except Interrupted:
        return None
    w = 2.0 * math.pi / n
    bodies = {g: held_bodies(scene, g) for g in (0, 1)}
    reach = max(p.reach for parts in bodies.values() for p in parts)
    dilation = Dilation(obstacles, math.ceil(reach / raster.cell) + 1)
    layers = {}
    for g in (0, 1):
        parts = bodies[g]
        inside = [2.0 * p.reach * math.sin(0.25 * w) + tolerance + ROUND_OFF for p in parts]
        clear = [d - clearance for d in inside]
        for b in range(n):
            if should_stop is not None and should_stop():
                return None
            layers[(g, b)] = free_layer(raster, dilation, scene.bounds, parts,
                                        -math.pi + (b + 0.5) * w, inside, clear)
    return RasterCover(raster, n, layers, pieces)

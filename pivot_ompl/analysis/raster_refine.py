"""The raster cover refined in windows round its necks: finer cells and yaw bins only there.

The coarse cover (:mod:`~pivot_ompl.analysis.raster_cover`) loses narrow doors twice: its
cells (a passage looks up to about two cells wider) and its yaw bins' rotation erosion (twice
the erosion off the assembly's width). Both losses only matter where the coarse free layers
are narrow, so :func:`refine_cover` recomputes the cover there alone, coarse to fine:

**Windows.** Per grasp parity, the union ``U`` over the yaw bins of the coarse free cells is
where the box's centre may be at all. A *neck* is a cell of ``U`` farther than :data:`THIN`
cells from every cell of ``U`` lying more than :data:`THIN` cells inside ``U`` (no disk of
that radius in ``U`` holds it: a narrow passage, not a room); the window is the necks of both
parities grown by :data:`GROW` cells. Which cells are refined is a matter of cost only: the
soundness argument below holds for any window.

**Fine voxels.** Inside the window each coarse cell is split into ``2 x 2`` cells and each
yaw bin into ``m`` bins (each of rotation erosion at most ``resolution``; fine bin ``f`` lies
in coarse bin ``f // m``). A fine cell at a fine bin is tested only where its coarse cell is
free at the coarse bin: a coarse cell blocked at a coarse bin has every point colliding at
every yaw of that bin, so every fine cell in it at every fine bin in it (sound). The test
itself is :mod:`~pivot_ompl.analysis.raster_cover`'s, on the finer cells: blocked when an
obstacle cell of the finer raster (wholly inside an obstacle piece) lies at a lattice offset
of the fine bin's eroded body, or the cell misses the rectangle of positions inside the
bounds; so a state free at a fine bin's yaw lies in a free fine voxel. Where a coarse cell is
free deeper than :data:`DEEP` cells inside its coarse layer, its fine voxels are taken as free
untested (a superset again: only the necks' edges decide).

**Components.** The free fine voxels of a parity are joined when they are 8-adjacent cells of
one fine bin (a continuous motion within the bin) or one cell of two consecutive fine bins, the
last and the first included (a yaw crossing at a point, which lies in a cell free in both
layers); :mod:`~pivot_ompl.analysis.voxel_components` labels them, and a growing window's
new voxels are joined to the earlier labels rather than labelled again.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.raster_cover import (
    EPS,
    RasterCover,
    layer_reach,
    merged_rows,
    obstacle_cells,
)
from pivot_ompl.analysis.regrasp_bound import ROUND_OFF, held_bodies, yaw_bins
from pivot_ompl.analysis.voxel_components import Grown, grown_components
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, wrap_angle

#: Largest rotation erosion (m) of a fine yaw bin.
FINE_RESOLUTION = 0.01
#: Half-width (coarse cells) below which the union of a parity's free cells is a neck.
THIN = 3
#: Coarse cells the necks are grown by to make the window.
GROW = 2
#: Coarse cells inside a coarse free layer beyond which its fine voxels are not tested.
DEEP = 3

_EIGHT = np.ones((3, 3), dtype=bool)


def neck_window(cover: RasterCover) -> np.ndarray:
    """The coarse cells to refine (boolean ``cover.raster.shape``; module docstring)."""
    window = np.zeros(cover.raster.shape, dtype=bool)
    for g in (0, 1):
        union = np.zeros(cover.raster.shape, dtype=bool)
        for b in range(cover.bins):
            union |= cover.layers[(g, b)][0] > 0
        inner = ndimage.distance_transform_edt(union) > THIN
        wide = ndimage.binary_dilation(inner, structure=_EIGHT, iterations=THIN)
        window |= union & ~wide
    if GROW and window.any():
        window = ndimage.binary_dilation(window, structure=_EIGHT, iterations=GROW)
    return window


def turn_neck_window(cover: RasterCover, *, shared: int = 20, grow: int = 1) -> np.ndarray:
    """The coarse cells where a piece of one yaw bin meets one of the next in few cells.

    A *turn neck*: two pieces of consecutive bins of a parity that share at most ``shared``
    cells (the held assembly turns from one to the other only there); their shared cells,
    grown by ``grow`` cells. Slower to refine than :func:`neck_window` (more cells) but
    closer to where the coarse bins lose the turns (docs/buildings.md).
    """
    window = np.zeros(cover.raster.shape, dtype=bool)
    n = cover.bins
    for g in (0, 1):
        for b in range(n):
            lab, nxt = cover.layers[(g, b)][0], cover.layers[(g, (b + 1) % n)][0]
            both = (lab > 0) & (nxt > 0)
            keys = lab[both].astype(np.int64) * (int(nxt.max()) + 1) + nxt[both]
            _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
            ii, jj = np.nonzero(both)
            few = counts[inverse] <= shared
            window[ii[few], jj[few]] = True
    if grow and window.any():
        window = ndimage.binary_dilation(window, structure=_EIGHT, iterations=grow)
    return window


@dataclass
class FineVoxels:
    """The free fine voxels of the window, per grasp parity, and their components.

    Attributes:
        raster: the fine cells (half the coarse side, the same origin; ``2 x`` the shape).
        split: fine bins per coarse bin.
        bins: fine yaw bins (``split`` times the coarse ones); bin ``f`` holds yaws
            ``-pi + [f, f + 1) * 2 pi / bins``.
        window: the coarse cells refined.
        keys: per parity, the sorted voxel keys ``f * cells + a * ny + b`` (fine cell
            ``(a, b)``, ``cells`` the fine raster's cell count).
        labels: per parity, each voxel's component (``0..count - 1``).
        count: per parity, the components.
        grown: per parity, how this call grew the earlier labelling (its new voxels and
            their labels, the earlier components' labels now).
        earlier: the window grown (``None``: labelled afresh).
    """

    raster: FloorRaster
    split: int
    bins: int
    window: np.ndarray
    keys: dict[int, np.ndarray]
    labels: dict[int, np.ndarray]
    count: dict[int, int]
    grown: dict[int, Grown] = field(default_factory=dict)
    earlier: np.ndarray | None = None

    @property
    def cells(self) -> int:
        """Fine cells on the floor (the key's bin stride)."""
        return self.raster.shape[0] * self.raster.shape[1]

    def holding_keys(self, pose: Pose, grasp: int) -> np.ndarray:
        """The voxel keys of ``grasp``'s layer whose closed cells hold ``pose``."""
        (x0, y0), h = self.raster.origin, self.raster.cell
        nx, ny = self.raster.shape
        cells = {(i, j) for i in {math.floor((pose[0] - x0 + s) / h) for s in (-EPS, EPS)}
                 for j in {math.floor((pose[1] - y0 + s) / h) for s in (-EPS, EPS)}
                 if 0 <= i < nx and 0 <= j < ny}
        box_bin = int((wrap_angle(pose[2]) + math.pi) // (2.0 * math.pi / self.bins)) % self.bins
        f = (box_bin + (self.bins // 2) * (grasp // 2)) % self.bins
        return np.array([f * self.cells + i * ny + j for i, j in sorted(cells)], dtype=np.int64)

    def in_window(self, pose: Pose) -> bool:
        """Whether ``pose``'s position lies in a refined coarse cell."""
        (x0, y0), h = self.raster.origin, 2.0 * self.raster.cell
        i, j = math.floor((pose[0] - x0) / h), math.floor((pose[1] - y0) / h)
        return (0 <= i < self.window.shape[0] and 0 <= j < self.window.shape[1]
                and bool(self.window[i, j]))

    def covers(self, pose: Pose, grasp: int) -> bool:
        """Whether the state may be free, for a pose in the window (``False`` proves not)."""
        return bool((self.lookup(grasp % 2, self.holding_keys(pose, grasp)) >= 0).any())

    def lookup(self, g: int, keys: np.ndarray) -> np.ndarray:
        """Components of the voxels ``keys`` of parity ``g`` (``-1`` where not free)."""
        have = self.keys[g]
        pos = np.clip(np.searchsorted(have, keys), 0, max(0, len(have) - 1))
        found = (have[pos] == keys) if len(have) else np.zeros(len(keys), dtype=bool)
        return np.where(found, self.labels[g][pos] if len(have) else -1, -1)


def fine_raster(coarse: FloorRaster) -> FloorRaster:
    """The raster of half the coarse cell over the same cells (``2 x`` the shape)."""
    (x0, y0), h = coarse.origin, coarse.cell
    nx, ny = coarse.shape
    fine = FloorRaster((x0, y0, x0 + nx * h, y0 + ny * h), min_cell=0.5 * h,
                       max_cells=4 * nx * ny + 1)
    fine.cell, fine.shape, fine.half_diag = 0.5 * h, (2 * nx, 2 * ny), 0.5 * coarse.half_diag
    xs = x0 + (np.arange(2 * nx) + 0.5) * fine.cell
    ys = y0 + (np.arange(2 * ny) + 0.5) * fine.cell
    # read-only views of one row and one column: no floor-sized arrays kept for the centres
    fine.gx = np.broadcast_to(xs[:, None], fine.shape)
    fine.gy = np.broadcast_to(ys[None, :], fine.shape)
    return fine


def refine_cover(scene: Scene, cover: RasterCover, window: np.ndarray, *,
                 resolution: float = FINE_RESOLUTION, tolerance: float, clearance: float,
                 should_stop: Callable[[], bool] | None = None,
                 memo: dict | None = None) -> FineVoxels:
    """The free fine voxels of ``window`` and their components (module docstring).

    ``should_stop`` is polled once per fine bin and raises
    :class:`~pivot_ompl.errors.Interrupted`. ``memo``: a dict kept between calls on one
    scene and cover with the same arguments, windows growing: what does not depend on the
    window is computed once (the fine bins' bounds and lattice rows, and the free voxels of
    the cells an earlier window held: a voxel's test reads only its own cell, bin and nearby
    obstacles); a window not holding the earlier one starts afresh.
    """
    memo = {} if memo is None else memo
    done = memo.get("done")
    if done is None or done.shape != window.shape or (done & ~window).any():
        memo.clear()
        done = np.zeros_like(window)
    new = window & ~done
    coarse = cover.raster
    if "raster" not in memo:
        memo["raster"] = fine_raster(coarse)
    fine = memo["raster"]
    n = cover.bins
    split = max(1, math.ceil(yaw_bins(scene, resolution) / n))
    bins = split * n
    w = 2.0 * math.pi / bins
    bodies = {g: held_bodies(scene, g) for g in (0, 1)}
    longest = max(p.reach for parts in bodies.values() for p in parts)
    pad = math.ceil(longest / fine.cell) + 2
    obstacles = obstacle_cells(fine, _near_pieces(cover, new, longest), should_stop)
    sums = _padded_sums(obstacles, pad)
    nx2, ny2 = fine.shape
    stride = sums.shape[1]
    keys: dict[int, np.ndarray] = {}
    labels: dict[int, np.ndarray] = {}
    count: dict[int, int] = {}
    grown: dict[int, Grown] = {}
    ni, nj = np.nonzero(new)  # the new cells, read in each layer (not the whole floor)
    around = _around(new.shape, ni, nj)
    for g in (0, 1):
        parts = bodies[g]
        inside = [2.0 * p.reach * math.sin(0.25 * w) + tolerance + ROUND_OFF for p in parts]
        clear = [d - clearance for d in inside]
        found = [np.zeros(0, dtype=np.int64)]
        for big in range(n):
            lab = cover.layers[(g, big)][0]
            hit = lab[ni, nj] > 0
            if not hit.any():
                continue
            ci, cj = ni[hit], nj[hit]
            deep = _deep(lab, (around[0][hit], around[1][hit]))
            a = (2 * ci[:, None] + np.array([0, 0, 1, 1])).ravel()
            b = (2 * cj[:, None] + np.array([0, 1, 0, 1])).ravel()
            test = ~np.repeat(deep, 4)
            flat = (a + pad) * stride + b + pad  # prefix-sum row before cell (a, b)
            for f in range(big * split, (big + 1) * split):
                if should_stop is not None and should_stop():
                    raise Interrupted("the refined raster cover")
                if (g, f) not in memo:
                    lo, hi, rows = layer_reach(fine.cell, scene.bounds, parts,
                                               -math.pi + (f + 0.5) * w, inside, clear)
                    memo[(g, f)] = lo, hi, merged_rows(rows) if rows else []
                free = _free_voxels(fine, sums, pad, flat, a, b, test, *memo[(g, f)])
                found.append(f * (nx2 * ny2) + a[free] * ny2 + b[free])
        grown[g] = grown_components(
            memo.get(("keys", g), np.zeros(0, dtype=np.int64)),
            memo.get(("labels", g), np.zeros(0, dtype=np.int64)), int(memo.get(("count", g), 0)),
            np.concatenate(found), done, nx2, ny2, bins)
        count[g], keys[g], labels[g] = grown[g].count, grown[g].keys, grown[g].labels
    for g in (0, 1):  # kept only once both parities are done (a stop leaves the memo whole)
        memo[("keys", g)], memo[("labels", g)], memo[("count", g)] = keys[g], labels[g], count[g]
    memo["done"] = window.copy()
    return FineVoxels(fine, split, bins, window, keys, labels, count, grown,
                      done if done.any() else None)


def _near_pieces(cover: RasterCover, window: np.ndarray, reach: float) -> list[np.ndarray]:
    """The obstacle pieces whose box comes within ``reach`` of the window's cells.

    Tested all at once: each piece's block of cells against the window grown by ``reach``
    (its cells counted by prefix sums).
    """
    if not cover.pieces or not window.any():
        return []
    (x0, y0), h = cover.raster.origin, cover.raster.cell
    nx, ny = window.shape
    ii, jj = np.nonzero(window)
    lo = np.array([x0 + ii.min() * h - reach, y0 + jj.min() * h - reach])
    hi = np.array([x0 + (ii.max() + 1) * h + reach, y0 + (jj.max() + 1) * h + reach])
    grown = ndimage.binary_dilation(window, structure=_EIGHT,
                                    iterations=math.ceil(reach / h) + 1)
    sums = np.zeros((nx + 1, ny + 1), dtype=np.int64)
    sums[1:, 1:] = grown.cumsum(axis=0).cumsum(axis=1)
    pmin = np.array([p.min(axis=0) for p in cover.pieces])
    pmax = np.array([p.max(axis=0) for p in cover.pieces])
    near = ~(np.any(pmax < lo, axis=1) | np.any(pmin > hi, axis=1))
    i0 = np.clip(np.maximum(0, np.floor_divide(pmin[:, 0] - x0, h)), 0, nx).astype(np.int64)
    j0 = np.clip(np.maximum(0, np.floor_divide(pmin[:, 1] - y0, h)), 0, ny).astype(np.int64)
    i1 = np.clip(np.floor_divide(pmax[:, 0] - x0, h) + 1, 0, nx).astype(np.int64)
    j1 = np.clip(np.floor_divide(pmax[:, 1] - y0, h) + 1, 0, ny).astype(np.int64)
    i1, j1 = np.maximum(i0, i1), np.maximum(j0, j1)
    near &= sums[i1, j1] - sums[i0, j1] - sums[i1, j0] + sums[i0, j0] > 0
    return [cover.pieces[n] for n in np.flatnonzero(near)]


def _deep(lab: np.ndarray, around: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Whether every cell within :data:`DEEP` (chessboard) of each cell is free.

    ``lab``: a layer's labels (free: above 0); ``around``: per cell, the flat indices of the
    cells within :data:`DEEP` and whether each lies on the floor (:func:`_around`).
    """
    idx, inside = around
    if DEEP < 0:
        return np.zeros(len(idx), dtype=bool)
    return (inside & (lab.ravel()[idx] > 0)).all(axis=1)


def _around(shape: tuple[int, int], ci: np.ndarray, cj: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """The cells within :data:`DEEP` (chessboard) of each cell ``(ci, cj)``.

    ``(idx, inside)``: per cell, their flat indices (clipped to the floor) and whether each
    lies on it.
    """
    nx, ny = shape
    d = np.arange(-DEEP, DEEP + 1)
    ii = (ci[:, None] + d[None, :])[:, :, None]
    jj = (cj[:, None] + d[None, :])[:, None, :]
    inside = ((ii >= 0) & (ii < nx) & (jj >= 0) & (jj < ny)).reshape(len(ci), -1)
    idx = (np.clip(ii, 0, nx - 1) * ny + np.clip(jj, 0, ny - 1)).reshape(len(ci), -1)
    return idx, inside


def _padded_sums(obstacles: np.ndarray, pad: int) -> np.ndarray:
    """Prefix sums along x of the obstacle cells, padded by ``pad`` empty cells all round."""
    nx, ny = obstacles.shape
    sums = np.zeros((nx + 1 + 2 * pad, ny + 2 * pad), dtype=np.int32)
    sums[pad + 1:pad + 1 + nx, pad:pad + ny] = np.cumsum(obstacles, axis=0, dtype=np.int32)
    sums[pad + 1 + nx:] = sums[pad + nx]
    return sums


def _free_voxels(fine: FloorRaster, sums: np.ndarray, pad: int, flat: np.ndarray,
                 a: np.ndarray, b: np.ndarray, test: np.ndarray, lo: list[float],
                 hi: list[float], merged: list) -> np.ndarray:
    """Which fine cells ``(a, b)`` are free in a fine bin (untested ones, ``~test``, are).

    ``lo``, ``hi``, ``merged``: the bin's rectangle of positions inside the bounds and its
    merged lattice rows (:func:`~pivot_ompl.analysis.raster_cover.layer_reach`).
    """
    (fx, fy), h = fine.origin, fine.cell
    xs, ys = fx + a * h, fy + b * h
    free = ((xs <= hi[0] + EPS) & (xs + h >= lo[0] - EPS)
            & (ys <= hi[1] + EPS) & (ys + h >= lo[1] - EPS))
    idx = np.flatnonzero(free & test)
    if merged and len(idx):
        stride = sums.shape[1]
        top = np.array([(hi_ + 1) * stride + dj for dj, _, hi_ in merged], dtype=np.int64)
        bottom = np.array([lo_ * stride + dj for dj, lo_, _ in merged], dtype=np.int64)
        if max(max(-r[1], r[2] + 1) for r in merged) > pad or \
                max(abs(r[0]) for r in merged) > pad:
            raise ValueError("offset rows beyond the padding")
        flat_sums = sums.ravel()
        at = flat[idx]
        hit = (flat_sums[at[None, :] + top[:, None]] > flat_sums[at[None, :] + bottom[:, None]])
        free[idx[hit.any(axis=0)]] = False
    return free

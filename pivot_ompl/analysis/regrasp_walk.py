"""Where a regrasp may happen at all: the walk round the resting box, relaxed soundly.

A regrasp from grasp ``k`` to ``j`` with the box resting at ``q`` is a walk of the robot from
its grasp-``k`` pose to its grasp-``j`` pose, the walking body clear of the obstacles (by the
checkers' clearance), inside the bounds and clear of the box (the swept checks' tolerance
aside). :class:`WalkRelaxation` keeps of the walking body only a disk inside it at any
heading (below) and of the box only a *core* that lies inside the box wherever the box may be, and
asks whether the disk's centre can get from one pose to the other. Every real walk is a walk
of the relaxation, so "no" proves that no regrasp from ``k`` to ``j`` happens there.

**The disk.** The walking body is a rectangle
(:meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`: ``ahead``, ``behind``, ``side``
from the robot pose); the largest disk round its own centre (``(ahead - behind) / 2`` ahead
of the robot pose) has radius ``min(side, (ahead + behind) / 2)`` and lies inside the body
at any heading.

**The tolerance.** A walk is accepted by certified swept checks
(:func:`~pivot_ompl.validity.certify.certify`): its samples keep the full ``clearance``, and
between two samples either the clearance test proves every pose clear, or no point of the
body moves more than twice the tolerance, so every pose lies within the tolerance (of
motion of any body point, the disk's centre included) of a sample that keeps the full
clearance. The disk centre's free set is therefore taken with the full clearance and
grown by the tolerance: a narrow passage the body passes only by coming within the
tolerance all along it (longer than twice the tolerance) is closed, where the clearance
less the tolerance would leave it open.

The question is asked of a *region* of box positions in one yaw bin (where the bound's free
pieces of the two grasps meet). The region is covered by disks of radius ``rho`` round
sample points; for each sample ``p``:

* the box core is the box at ``(p, t_b)`` eroded by ``rho`` and by the bin's rotation
  displacement ``D`` (it lies inside the box at any position of the disk and any yaw of the
  bin, see :mod:`~pivot_ompl.analysis.regrasp_bound`);
* the robot's grasp poses lie within ``rho`` plus their own rotation displacement of those at
  ``(p, t_b)``;
* the disk centre's free space is rasterised: a cell is free when it meets the free set
  (:class:`~pivot_ompl.analysis.raster.FloorRaster`), so a continuous walk crosses only free
  cells, one after another 8-adjacent; connectivity is then exact on the raster (scipy's
  labelling).

The region may hold a regrasp only if some sample joins some start cell to some end cell.
At most :data:`MAX_SAMPLES` samples are tried; when more would be needed the answer is "may"
(sound, only weaker).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable

import numpy as np
import shapely
from scipy import ndimage
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.footprints import disk_clear
from pivot_ompl.validity.merge import merge_boxes

#: Raster cell of the disk centre's free space (m).
CELL = 0.1
#: Spacing of the sample points that cover a region of box positions (m).
SAMPLE = 0.1
#: Samples tried per region at most.
MAX_SAMPLES = 64
#: Raster cells at most (a larger floor gets larger cells).
MAX_CELLS = 600_000
#: Cells a walk's window is widened by, in turn, before the whole raster is labelled (any
#: widths give the same answers; one label of a wide window costs less than several narrow).
MARGINS = (32, 96)
#: Added to every erosion (m): keeps the relaxation on the safe side of round-off.
ROUND_OFF = 1e-7
#: Side (cells) of the blocks :func:`centres_within` decides at once where it can.
BLOCK = 8

_EIGHT = np.ones((3, 3), dtype=bool)


class WalkRelaxation:
    """Whether the walking robot may regrasp with the box resting in a region (see module).

    Args:
        scene: the scene.
        width: the yaw bins' width (rad).
        tolerance: the swept checks' tolerance (m).
        clearance: what the checkers keep the walking body from the obstacles (m).
    """

    def __init__(self, scene: Scene, *, width: float, tolerance: float,
                 clearance: float) -> None:
        """Rasterise the disk centre's free space (obstacles and bounds only)."""
        m = self.model = scene.model
        ahead, behind, side = m.walking_extent()
        self.radius = min(side, 0.5 * (ahead + behind))
        self.centre = 0.5 * (ahead - behind)  # the body's centre, ahead of the robot pose
        self.turn = 2.0 * math.sin(0.25 * width)  # displacement per metre from the centre
        box_reach = 0.5 * math.hypot(*m.object_size[:2])
        self.box_erosion = box_reach * self.turn + tolerance + ROUND_OFF
        self.box_gap = self.radius - tolerance - ROUND_OFF
        self.raster = FloorRaster(scene.bounds, min_cell=CELL, max_cells=MAX_CELLS)
        free = disk_clear(scene.bounds, merge_boxes(scene.obstacles), radius=self.radius,
                          clearance=clearance - ROUND_OFF)
        # cells within the tolerance of the full-clearance set (module docstring)
        shapely.prepare(free)
        self.free = centres_within(self.raster, free, self.raster.half_diag + tolerance
                                   + ROUND_OFF)
        self.labels, _ = ndimage.label(self.free, structure=_EIGHT)
        self.queries = 0
        self._answers: dict[tuple[bytes, float, int, int], bool] = {}
        self._by_cells: dict[tuple[Hashable, float, int, int], bool] = {}

    # -- raster helpers ------------------------------------------------------------------
    def _cells(self, x: float, y: float, r: float) -> tuple[np.ndarray, np.ndarray]:
        """Free raster cells meeting the disk of radius ``r`` round ``(x, y)``.

        Read in the block round the disk's box (one cell of margin: every centre within
        ``r`` plus half a diagonal lies in it), no polygon built.
        """
        rr = r + self.raster.half_diag
        wi, wj = self.raster.window_box(x - rr, y - rr, x + rr, y + rr)
        inside = (np.hypot(self.raster.gx[wi, wj] - x, self.raster.gy[wi, wj] - y)
                  <= rr) & self.free[wi, wj]
        ii, jj = np.nonzero(inside)
        return ii + wi.start, jj + wj.start

    # -- the question --------------------------------------------------------------------
    def may_regrasp(self, region: BaseGeometry, yaw: float, k: int, j: int) -> bool:
        """Whether a regrasp from ``k`` to ``j`` may happen with the box in ``region``.

        ``region``: box positions (a polygon); ``yaw``: the bin's centre yaw. ``False``
        proves that it cannot.
        """
        self.queries += 1
        if region.is_empty:
            return False
        key = (shapely.to_wkb(region), yaw, k, j)  # the same question, the same answer
        if key not in self._answers:
            self._answers[key] = self._may_regrasp(region, yaw, k, j)
        return self._answers[key]

    def may_regrasp_cells(self, cells: Hashable, region: Callable[[], BaseGeometry],
                          yaw: float, k: int, j: int) -> bool:
        """:meth:`may_regrasp` of ``region()``, built only the first time ``cells`` is asked.

        ``cells``: a key that fixes the region (the same key, the same region: e.g. the
        raster and its cells' indices), so that a question asked again costs a lookup.
        """
        key = (cells, yaw, k, j)
        if key not in self._by_cells:
            self._by_cells[key] = self.may_regrasp(region(), yaw, k, j)
        else:
            self.queries += 1
        return self._by_cells[key]

    def _may_regrasp(self, region: BaseGeometry, yaw: float, k: int, j: int) -> bool:
        samples, rho = self._samples(region)
        if len(samples) > MAX_SAMPLES:
            return True
        reach = {g: math.hypot(*self._body_centre((0.0, 0.0, 0.0), g)) for g in (k, j)}
        blocks: list[BaseGeometry | None] = []
        for n, (x, y) in enumerate(samples):
            q = (x, y, yaw)
            rk, rj = self._body_centre(q, k), self._body_centre(q, j)
            a = self._cells(rk[0], rk[1], rho + reach[k] * self.turn)
            b = self._cells(rj[0], rj[1], rho + reach[j] * self.turn)
            if not len(a[0]) or not len(b[0]):
                continue
            common = set(self.labels[a].tolist()) & set(self.labels[b].tolist())
            if not common:
                continue  # not even round the obstacles alone
            if not blocks:  # the rest of the samples' blocked boxes, in one call
                blocks = [None] * n + self._blocked(samples[n:], yaw, rho)
            blocked = blocks[n]
            if blocked is None:
                return True  # nothing of the box is certain: it may not block
            if blocked.is_empty or self._joined(blocked, a, b):
                return True
        return False

    def _blocked(self, samples: list[tuple[float, float]], yaw: float, rho: float
                 ) -> list[BaseGeometry | None]:
        """Per sample, the box core grown by the walking disk's gap (``None``: no core).

        The core: the box at the sample, eroded by ``rho`` and the bin's rotation
        displacement (module docstring); grown by the disk's radius less the tolerance and
        half a raster cell (its centres' cells then are the cells the disk cannot reach).
        """
        m = self.model
        d = self.box_erosion + rho
        hx, hy = 0.5 * m.object_size[0] - d, 0.5 * m.object_size[1] - d
        if hx <= 0 or hy <= 0:
            return [None] * len(samples)
        corners = np.array([rectangle_corners((x, y, yaw), 2 * hx, 2 * hy)
                            for x, y in samples], dtype=float)
        return list(shapely.buffer(shapely.polygons(corners),
                                   self.box_gap - self.raster.half_diag, quad_segs=4))

    def _body_centre(self, q: tuple[float, float, float], grasp: int) -> tuple[float, float]:
        """The walking body's centre (the disk's) when the robot holds the box at ``q``."""
        x, y, heading = self.model.robot_pose(q, grasp)
        return x + self.centre * math.cos(heading), y + self.centre * math.sin(heading)

    def _joined(self, blocked: BaseGeometry, a: tuple[np.ndarray, np.ndarray],
                b: tuple[np.ndarray, np.ndarray]) -> bool:
        """Whether cells ``a`` and ``b`` are joined by free cells not in ``blocked``.

        Labelled first in a window round ``blocked``, ``a`` and ``b`` only: joined there,
        they are joined. Two of the window's pieces that reach its edge may be joined outside
        it only if they meet the same piece of the whole free raster there; if none such
        joins them, they are not joined; if one may, the window is widened
        (:data:`MARGINS`, cells) and asked again, and at last the whole raster is labelled
        (a way round outside the window might cross ``blocked`` again).
        """
        r = self.raster
        wi, wj = r.window(blocked)
        nx, ny = r.shape
        cut = ~shapely.contains_xy(blocked, r.gx[wi, wj], r.gy[wi, wj])
        lo_i = min(wi.start, int(a[0].min()), int(b[0].min())) - 1
        hi_i = max(wi.stop, int(a[0].max()) + 1, int(b[0].max()) + 1) + 1
        lo_j = min(wj.start, int(a[1].min()), int(b[1].min())) - 1
        hi_j = max(wj.stop, int(a[1].max()) + 1, int(b[1].max()) + 1) + 1
        for margin in MARGINS:
            i0, i1 = max(0, lo_i - margin), min(nx, hi_i + margin)
            j0, j1 = max(0, lo_j - margin), min(ny, hi_j + margin)
            mask = self.free[i0:i1, j0:j1].copy()
            mask[wi.start - i0:wi.stop - i0, wj.start - j0:wj.stop - j0] &= cut
            labels, _ = ndimage.label(mask, structure=_EIGHT)
            la = {v for v in labels[a[0] - i0, a[1] - j0].tolist() if v}
            lb = {v for v in labels[b[0] - i0, b[1] - j0].tolist() if v}
            if la & lb:
                return True
            if (i0, j0, i1, j1) == (0, 0, nx, ny):
                return False  # the whole raster: nothing outside it
            if not self._may_join_outside(labels, (i0, i1, j0, j1), la, lb):
                return False
        whole = self.free.copy()
        whole[wi, wj] &= cut
        labels, _ = ndimage.label(whole, structure=_EIGHT)
        return bool((set(labels[a].tolist()) - {0}) & (set(labels[b].tolist()) - {0}))

    def _may_join_outside(self, labels: np.ndarray, block: tuple[int, int, int, int],
                          la: set[int], lb: set[int]) -> bool:
        """Whether pieces ``la`` and ``lb`` of a window's ``labels`` may join outside it.

        Only if they reach the window's edge in cells of one piece of the whole free
        raster (joined through such pieces, one after another).
        """
        i0, i1, j0, j1 = block
        edge = np.zeros(labels.shape, dtype=bool)
        edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
        edge &= labels > 0
        outside = self.labels[i0:i1, j0:j1][edge]
        parent: dict[int, int] = {}

        def find(v: int) -> int:
            while parent.get(v, v) != v:
                v = parent[v]
            return v

        for inner, whole in set(zip(labels[edge].tolist(), outside.tolist(), strict=True)):
            ri, ro = find(inner), find(-whole)  # outer pieces keyed negative
            if ri != ro:
                parent[ri] = ro
        return bool({find(v) for v in la} & {find(v) for v in lb})

    def _samples(self, region: BaseGeometry) -> tuple[list[tuple[float, float]], float]:
        """Points whose ``rho``-disks cover ``region``, and ``rho``."""
        x0, y0, x1, y1 = region.bounds
        if max(x1 - x0, y1 - y0) <= SAMPLE:
            return [(0.5 * (x0 + x1), 0.5 * (y0 + y1))], 0.5 * math.hypot(x1 - x0, y1 - y0)
        rho = SAMPLE * math.sqrt(0.5)
        xs = np.arange(x0 + 0.5 * SAMPLE, x1 + 0.5 * SAMPLE, SAMPLE)
        ys = np.arange(y0 + 0.5 * SAMPLE, y1 + 0.5 * SAMPLE, SAMPLE)
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        near = shapely.contains_xy(region.buffer(rho, quad_segs=2), gx, gy)
        return list(zip(gx[near].tolist(), gy[near].tolist(), strict=True)), rho


def centres_within(raster: FloorRaster, region: BaseGeometry, distance: float, *,
                   block: int = BLOCK) -> np.ndarray:
    """Whether each cell's centre lies within ``distance`` (m) of ``region`` (prepared).

    Decided by blocks of ``block x block`` cells first: the box round a block's centres
    (widened by :data:`ROUND_OFF`) farther than ``distance`` from the region has none of
    them within it, and one inside the region has all; the other blocks' centres are asked
    each (in one call).
    """
    nx, ny = raster.shape
    i0, j0 = np.arange(0, nx, block), np.arange(0, ny, block)
    i1, j1 = np.minimum(i0 + block, nx) - 1, np.minimum(j0 + block, ny) - 1
    gx, gy = raster.gx[:, 0], raster.gy[0, :]
    xl, yl = np.meshgrid(gx[i0] - ROUND_OFF, gy[j0] - ROUND_OFF, indexing="ij")
    xh, yh = np.meshgrid(gx[i1] + ROUND_OFF, gy[j1] + ROUND_OFF, indexing="ij")
    boxes = shapely.box(xl, yl, xh, yh)
    near = shapely.dwithin(region, boxes, distance)
    inside = near & shapely.contains(region, boxes)

    def cells_of(blocks: np.ndarray) -> np.ndarray:
        return np.repeat(np.repeat(blocks, block, axis=0), block, axis=1)[:nx, :ny]

    out = np.ascontiguousarray(cells_of(inside))
    ask = cells_of(near & ~inside)
    out[ask] = shapely.dwithin(region, shapely.points(raster.gx[ask], raster.gy[ask]),
                               distance)
    return out

"""The held poses' regrasps: may the robot walk round the resting box? Exact near the box.

The held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`) joins two grasps' free
parts of one yaw bin where they meet: a regrasp with the box resting there. A regrasp is also
a walk of the robot from one grasp's stance to the other's, the walking body clear of the
obstacles (by the checkers' clearance), inside the bounds, and clear of the box (the swept
checks' tolerance aside). :class:`RegraspWalks` relaxes that walk soundly, as
:class:`~pivot_ompl.analysis.regrasp_walk.WalkRelaxation` does (of the walking body its
inscribed disk, of the box a *core* inside it at every pose asked), but decides it in exact
polygons near the box, where a passage beside it may be a few centimetres too narrow:

* **The core.** In the box's frame at the bin's middle yaw the box is an axis-aligned
  rectangle; the positions ``P`` asked are turned into that frame, and the rectangle common
  to the box at every one of them is the box's rectangle shrunk by ``P``'s extent along each
  axis (exact: a rectangle's translates meet in the one spanned by the extremes), eroded by
  the bin's rotation displacement and the tolerance.
* **The stances.** A grasp's stance at a position of ``P`` and a yaw of the bin lies within
  its own rotation displacement of ``P`` moved by the grasp's offset at the middle yaw.
* **The walk near the box.** In a window of raster cells round the box at every pose of the
  region and both grasps' stances, the disk centre's free polygon
  (:func:`~pivot_ompl.validity.footprints.disk_clear`, a superset) less the core grown by the
  disk's radius (a polygon of chords: inside the true offset) falls into parts; a part
  meeting both stances may hold the walk.
* **Far from the box.** A walk may leave the window and come back: the free raster cells
  outside the window (cells meeting the free polygon,
  :class:`~pivot_ompl.analysis.raster.FloorRaster`) are labelled, and two parts are joined
  when they touch cells outside the window of one label (a way round outside crosses only
  such cells, 8-adjacent, one after another).

A region whose core is empty, or whose parts join the stances, is halved across its longer
side (a smaller region has a larger core and smaller stances) until its pieces are
:data:`TILE` across; every piece is asked in turn, depth first, and the region may hold the
regrasp if a piece that cannot be halved may. At most :data:`MAX_TESTS` pieces are asked
(then the answer is "may": sound, only weaker). ``False`` proves that no regrasp between the
two grasps happens with the box in the region at any yaw of the bin.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy import ndimage
from shapely import affinity
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.scene import Scene
from pivot_ompl.validity.footprints import disk_clear
from pivot_ompl.validity.merge import merge_boxes

#: Raster cell (m) of the disk centre's free space far from the box.
CELL = 0.1
#: Raster cells at most (a larger floor gets larger cells).
MAX_CELLS = 600_000
#: A region's pieces are halved down to this size (m) across their longer side.
TILE = 0.02
#: Pieces of one region asked at most.
MAX_TESTS = 256
#: Added to every erosion (m): keeps the relaxation on the safe side of round-off.
ROUND_OFF = 1e-7
#: Parts of the window closer than this (m) are one part (they may touch at a point).
TOUCH = 1e-7
#: Segments of a quarter circle in the grown core (chords: inside the round offset).
QUAD_SEGS = 8

_EIGHT = np.ones((3, 3), dtype=bool)


class _Floor:
    """The disk centre's free polygon and its raster (built on the first walk asked)."""

    def __init__(self, scene: Scene, radius: float, clearance: float) -> None:
        self.free = disk_clear(scene.bounds, merge_boxes(scene.obstacles), radius=radius,
                               clearance=clearance)
        shapely.prepare(self.free)
        self.raster = FloorRaster(scene.bounds, min_cell=CELL, max_cells=MAX_CELLS)
        self.cells = self.raster.meeting(self.free)
        self.labels, _ = ndimage.label(self.cells, structure=_EIGHT)


class RegraspWalks:
    """Whether the walking robot may regrasp with the box resting in a region (see module).

    Args:
        scene: the scene.
        tolerance: the swept checks' tolerance (m).
        clearance: what the checkers keep the walking body from the obstacles (m).
    """

    def __init__(self, scene: Scene, *, tolerance: float, clearance: float) -> None:
        """Keep the model's sizes; the floor is rasterised when first needed."""
        self.scene = scene
        m = scene.model
        self.radius = m.robot_inradius()
        self.tolerance = tolerance
        self.clearance = clearance - tolerance - ROUND_OFF
        self.gap = self.radius - tolerance - ROUND_OFF  # the disk centre from the core
        self.half = (0.5 * m.object_size[0], 0.5 * m.object_size[1])
        self.box_reach = math.hypot(*self.half)
        self.tests = 0  # pieces asked so far (a measure of the work)
        self._floor: _Floor | None = None

    @property
    def floor(self) -> _Floor:
        """The disk centre's free polygon and raster."""
        if self._floor is None:
            self._floor = _Floor(self.scene, self.radius, self.clearance)
        return self._floor

    def may_regrasp(self, region: BaseGeometry, a: float, b: float, g: int, h: int) -> bool:
        """Whether a regrasp between grasps ``g`` and ``h`` may happen in ``region``.

        ``region``: box positions (m); ``[a, b]``: the yaw bin (rad). ``False`` proves that
        none happens there, at any yaw of the bin.
        """
        if region.is_empty:
            return False
        yaw, turn = 0.5 * (a + b), 2.0 * math.sin(0.25 * (b - a))
        erosion = self.box_reach * turn + self.tolerance + ROUND_OFF
        hx, hy = self.half[0] - erosion, self.half[1] - erosion
        if hx <= 0.0 or hy <= 0.0:
            return True
        m = self.scene.model
        stances = []
        for grasp in (g, h):  # the grasp's offset in the box's frame, and its turn
            x, y, _ = m.robot_pose((0.0, 0.0, 0.0), grasp)
            stances.append((x, y, math.hypot(x, y) * turn + ROUND_OFF))
        local = affinity.rotate(region, -yaw, origin=(0.0, 0.0), use_radians=True)
        todo: list[tuple[BaseGeometry, _Window | None]] = [(local, None)]
        asked = 0
        while todo:
            piece, window = todo.pop()
            if piece.is_empty:
                continue
            asked += 1
            if asked > MAX_TESTS:
                break
            x0, y0, x1, y1 = piece.bounds
            if x1 - x0 < 2.0 * hx and y1 - y0 < 2.0 * hy:  # a core: the walk asked round it
                if window is None:
                    window = _Window(self, piece, yaw, (hx, hy), stances)
                if not window.joined(piece.bounds):
                    continue  # no walk with the box anywhere in this piece
            if max(x1 - x0, y1 - y0) <= TILE:
                break
            if x1 - x0 >= y1 - y0:
                xm = 0.5 * (x0 + x1)
                halves = ((x0, y0, xm, y1), (xm, y0, x1, y1))
            else:
                ym = 0.5 * (y0 + y1)
                halves = ((x0, y0, x1, ym), (x0, ym, x1, y1))
            todo.extend((shapely.intersection(piece, shapely.box(*r)), window) for r in halves)
        else:
            self.tests += asked
            return False
        self.tests += asked
        return True


class _Window:
    """One region's window of raster cells: its free polygon and the labels outside it."""

    def __init__(self, walks: RegraspWalks, local: BaseGeometry, yaw: float,
                 core: tuple[float, float], stances: list[tuple[float, float, float]]) -> None:
        """The window round every piece of ``local`` (positions in the box's frame)."""
        self.walks, self.yaw, self.core, self.stances = walks, yaw, core, stances
        floor = walks.floor
        r = floor.raster
        # every piece's blocked core and stances lie this far from the region's bounding box
        reach = max(math.hypot(*walks.half) + walks.gap,
                    *(math.hypot(sx, sy) + sr * math.sqrt(2.0) for sx, sy, sr in stances))
        x0, y0, x1, y1 = self._world(shapely.box(*local.bounds)).bounds
        wi, wj = r.window(shapely.box(x0 - reach, y0 - reach, x1 + reach, y1 + reach))
        self.block = (wi.start, wi.stop, wj.start, wj.stop)
        (ox, oy), c = r.origin, r.cell
        self.rect = (ox + wi.start * c, oy + wj.start * c, ox + wi.stop * c, oy + wj.stop * c)
        self.free = shapely.intersection(floor.free, shapely.box(*self.rect))
        outside = floor.cells.copy()
        outside[wi, wj] = False
        labels, _ = ndimage.label(outside, structure=_EIGHT)
        i0, i1, j0, j1 = self.block
        ring = [(i, j) for i in range(i0 - 1, i1 + 1) for j in (j0 - 1, j1)]
        ring += [(i, j) for i in (i0 - 1, i1) for j in range(j0, j1)]
        nx, ny = r.shape
        ring = [(i, j) for i, j in ring if 0 <= i < nx and 0 <= j < ny and labels[i, j]]
        self.ring_labels = np.array([labels[i, j] for i, j in ring], dtype=np.int64)
        self.ring = np.array([shapely.box(ox + i * c, oy + j * c, ox + (i + 1) * c,
                                          oy + (j + 1) * c).buffer(TOUCH, join_style="mitre")
                              for i, j in ring], dtype=object)

    def _world(self, geom: BaseGeometry) -> BaseGeometry:
        return affinity.rotate(geom, self.yaw, origin=(0.0, 0.0), use_radians=True)

    def joined(self, bounds: tuple[float, float, float, float]) -> bool:
        """Whether the stances of the box at ``bounds`` (its frame) may be joined round it."""
        x0, y0, x1, y1 = bounds
        hx, hy = self.core
        core = self._world(shapely.box(x1 - hx, y1 - hy, x0 + hx, y0 + hy))
        blocked = core.buffer(self.walks.gap, quad_segs=QUAD_SEGS)
        ends = [self._world(shapely.box(x0 + sx, y0 + sy, x1 + sx, y1 + sy).buffer(
            sr, quad_segs=QUAD_SEGS, join_style="mitre")) for sx, sy, sr in self.stances]
        # the stances' boxes grown by mitre joins hold their round offsets
        left = self.free.difference(blocked)
        parts = [p for p in getattr(left, "geoms", [left]) if not p.is_empty]
        if not parts:
            return False
        arr = np.array(parts, dtype=object)
        at = [set(np.nonzero(shapely.intersects(arr, e))[0].tolist()) for e in ends]
        if not at[0] or not at[1]:
            return False
        if at[0] & at[1]:
            return True
        return self._outside(arr, at[0], at[1])

    def _outside(self, parts: np.ndarray, a: set[int], b: set[int]) -> bool:
        """Whether parts ``a`` and ``b`` are joined through each other and the outside."""
        n = len(parts)
        parent = list(range(n + int(self.ring_labels.max(initial=0)) + 1))

        def find(v: int) -> int:
            while parent[v] != v:
                parent[v] = parent[parent[v]]
                v = parent[v]
            return v

        def union(u: int, v: int) -> None:
            parent[find(u)] = find(v)

        if len(self.ring):
            hits = shapely.intersects(parts[:, None], self.ring[None, :])
            for p, k in zip(*np.nonzero(hits), strict=True):
                union(int(p), n + int(self.ring_labels[k]))
        near = shapely.dwithin(parts[:, None], parts[None, :], TOUCH)
        for p, q in zip(*np.nonzero(near), strict=True):
            union(int(p), int(q))
        return bool({find(u) for u in a} & {find(v) for v in b})

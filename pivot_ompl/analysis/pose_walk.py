"""The held poses' regrasps: may the robot walk round the resting box? Exact near the box.

The held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`, and the regrasp count
:mod:`~pivot_ompl.analysis.pose_regrasps`) joins two grasps' free parts of one yaw bin where
they meet: a regrasp with the box resting there. A regrasp is also a walk of the robot from
one grasp's stance to the other's, the walking body clear of the obstacles (by the checkers'
clearance), inside the bounds, and clear of the box (the swept checks' tolerance aside).
:class:`RegraspWalks` relaxes that walk soundly and decides it in exact polygons near the
box, where a passage beside it may be a few centimetres too narrow:

* **The walking body.** The walking body (a rectangle,
  :meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`) is relaxed to the largest disk
  inside it round the rectangle's own centre (inside the body at any heading; the robot
  pose's own inscribed disk is smaller when the body reaches further ahead than behind), so
  a walk is a path of the disk's centre through
  :func:`~pivot_ompl.validity.footprints.disk_clear`'s free set (a superset of the true one)
  that keeps out of the box.
* **The box.** Asked of a *piece* ``H`` of box positions (convex) at the yaws of one bin
  ``[a, b]``: the box's rotation core over the bin
  (:func:`~pivot_ompl.analysis.pose_cells.rotation_core`, inside the box at every yaw of the
  bin) placed at every vertex of ``H`` and intersected (the core and ``H`` convex: inside the
  core placed at every point of ``H``). Disk centres nearer to it than the disk's radius less
  the tolerance are closed (the offset's chords: inside the true offset).
* **The stances.** Where the disk's centre may be at grasp ``g``: ``H`` moved by the grasp's
  offset turned to the bin's middle, grown by how far a half bin's turn moves that offset (a
  polygon round the disk of that radius).
* **Near the box.** In a window of raster cells round the region (every piece's closed
  disk centres and stances inside it), the free set less the closed disk centres falls into
  parts; a part meeting both stances may hold the walk. A free set of at most :data:`WHOLE`
  vertices is taken whole: the window is the floor, all exact polygons.
* **Far from the box.** A walk may leave the window and come back: the free raster cells
  outside the window (cells meeting the free set, and a few more,
  :class:`~pivot_ompl.analysis.raster.FloorRaster`, :data:`CELL` across, at most
  :data:`MAX_CELLS`: memory does not grow with the floor) are labelled, and two parts are
  joined when they touch cells outside the window of one label (a way round outside crosses
  only such cells, 8-adjacent, one after another).

A piece that may hold the regrasp is cut in four (its bounding box's quarters) and each asked
again, until the pieces are :data:`SPLIT` small or :data:`MOST_PIECES` have been asked (then
"may": sound, only weaker). ``False`` proves that no regrasp between the two grasps happens
with the box in the region at any yaw of the bin.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
import shapely.affinity
from scipy import ndimage
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_cells import held_bodies, rotation_core
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.scene import Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import disk_clear
from pivot_ompl.validity.merge import merge_boxes

#: Pieces of box positions this small (m, the larger side of their bounding box) are not cut.
SPLIT = 0.01
#: Pieces asked per regrasp at most.
MOST_PIECES = 256
#: Free sets of at most this many vertices are one window, the whole floor (no raster): the
#: corridor rows' have 160-1400, the 1506-box lab's 1314.
WHOLE = 5000
#: Raster cell (m) of the disk centre's free set outside the window.
CELL = 0.1
#: Raster cells at most (a larger floor gets larger cells).
MAX_CELLS = 600_000
#: Added to every erosion and growth (m): keeps the relaxation on the safe side of round-off.
ROUND_OFF = 1e-7
#: Parts of the window closer than this (m) are one part (they may touch at a point).
TOUCH = 1e-7
#: Segments per quarter circle of the polygons round disks.
QUAD_SEGS = 4

_EIGHT = np.ones((3, 3), dtype=bool)


def _turned(points: np.ndarray, yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return points @ np.array([[c, s], [-s, c]])


class _Floor:
    """The disk centre's free set and, past ``whole`` vertices, its raster (built when asked)."""

    def __init__(self, scene: Scene, radius: float, clearance: float, whole: int) -> None:
        self.free = disk_clear(scene.bounds, merge_boxes(scene.obstacles), radius=radius,
                               clearance=clearance)
        shapely.prepare(self.free)
        self.raster: FloorRaster | None = None
        self.cells = np.zeros((0, 0), dtype=bool)
        if shapely.get_num_coordinates(self.free) <= whole:
            return  # the window is the whole floor
        self.raster = r = FloorRaster(scene.bounds, min_cell=CELL, max_cells=MAX_CELLS)
        # every cell meeting the free set (and a few more): its centre within the free set
        # grown by half a cell's diagonal (chords round the round offset: outside it)
        grown = self.free.buffer(r.half_diag / math.cos(math.pi / (4 * QUAD_SEGS)),
                                 quad_segs=QUAD_SEGS)
        shapely.prepare(grown)
        self.cells = shapely.intersects_xy(grown, r.gx.ravel(), r.gy.ravel()).reshape(r.shape)


class RegraspWalks:
    """Whether the walking robot may regrasp with the box resting in a region (see module).

    Args:
        scene: the scene.
        tolerance: the swept checks' tolerance (m).
        clearance: what the checkers keep the walking body from the obstacles (m).
        whole: the free set's vertices at most for the window to be the whole floor (no
            raster; :data:`WHOLE`).
    """

    def __init__(self, scene: Scene, *, tolerance: float = SWEEP_TOLERANCE,
                 clearance: float = KEEP_CLEARANCE, whole: int = WHOLE) -> None:
        """Keep the model's sizes; the floor is built when first needed."""
        self.scene = scene
        m = self.model = scene.model
        ahead, behind, side = m.walking_extent()
        self.radius = min(side, 0.5 * (ahead + behind))
        self.centre = 0.5 * (ahead - behind)  # the body's centre, ahead of the robot pose
        self.clearance = clearance - tolerance - ROUND_OFF
        self.gap = self.radius - tolerance - ROUND_OFF  # the disk centre from the core
        self.box = held_bodies(m)[0][0]  # the box's footprint, counter-clockwise
        #: pieces asked so far (all questions: a measure of the work)
        self.pieces = 0
        self.whole = whole
        self._floor: _Floor | None = None

    @property
    def floor(self) -> _Floor:
        """The disk centre's free set and raster."""
        if self._floor is None:
            self._floor = _Floor(self.scene, self.radius, self.clearance, self.whole)
        return self._floor

    def may_regrasp(self, region: BaseGeometry, a: float, b: float, g: int, h: int) -> bool:
        """Whether a regrasp between grasps ``g`` and ``h`` may happen with the box in ``region``.

        ``region``: box positions (m); ``[a, b]``: the bin's yaws (rad, ``b - a`` below pi).
        ``False`` proves that none happens there, at any yaw of the bin.
        """
        if region.is_empty:
            return False
        half, mid = 0.5 * (b - a), 0.5 * (a + b)
        core = rotation_core(self.box, half)
        if core is None:
            return True
        core = _turned(core, mid)
        stands = []
        for grasp in (g, h):
            x, y, heading = self.model.robot_pose((0.0, 0.0, mid), grasp)
            offset = np.array([x + self.centre * math.cos(heading),
                               y + self.centre * math.sin(heading)])
            sway = 2.0 * math.hypot(*offset) * math.sin(0.5 * half) + ROUND_OFF
            stands.append((offset, sway / math.cos(math.pi / (4 * QUAD_SEGS))))
        hull = region.convex_hull
        reach = max(float(np.hypot(*core.T).max()) + self.gap,
                    *(math.hypot(*o) + s for o, s in stands)) + 2.0 * ROUND_OFF
        window: _Window | None = None
        todo, asked = [hull], 0
        while todo:
            piece = todo.pop()
            asked += 1
            self.pieces += 1
            closed = self._closed(piece, core)
            if closed is not None:
                if window is None:
                    window = _Window(self.floor, hull, reach)
                ends = [shapely.affinity.translate(piece, *offset).buffer(
                    sway, quad_segs=QUAD_SEGS) for offset, sway in stands]
                if not window.joined(closed, ends):
                    continue  # no walk with the box anywhere in this piece
            x0, y0, x1, y1 = piece.bounds
            if max(x1 - x0, y1 - y0) <= SPLIT or asked + len(todo) >= MOST_PIECES:
                return True
            xm, ym = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            for box in (shapely.box(x0, y0, xm, ym), shapely.box(xm, y0, x1, ym),
                        shapely.box(x0, ym, xm, y1), shapely.box(xm, ym, x1, y1)):
                part = region.intersection(box)
                if not part.is_empty and part.area > 0.0:
                    todo.append(part.convex_hull)
                elif not part.is_empty:  # a sliver or a point: kept whole, not lost
                    todo.append(part.buffer(ROUND_OFF).convex_hull)
        return False

    def _closed(self, piece: BaseGeometry, core: np.ndarray) -> BaseGeometry | None:
        """The disk centres the box closes wherever in ``piece`` it rests (``None``: none)."""
        corners = np.asarray(piece.exterior.coords)[:-1] if piece.geom_type == "Polygon" \
            else np.asarray(piece.envelope.buffer(ROUND_OFF).exterior.coords)[:-1]
        sure = shapely.Polygon(core + corners[0])
        for c in corners[1:]:
            sure = sure.intersection(shapely.Polygon(core + c))
            if sure.is_empty:
                return None  # nothing of the box is certain: it may not block
        return sure.buffer(self.gap, quad_segs=QUAD_SEGS)


class _Window:
    """One region's window of raster cells: its free set and the labels outside it."""

    def __init__(self, floor: _Floor, hull: BaseGeometry, reach: float) -> None:
        """The window round ``hull`` grown by ``reach`` (m: every closed set and stance)."""
        r = floor.raster
        if r is None:  # the whole floor
            self.free, self.ring = floor.free, np.zeros(0, dtype=object)
            self.ring_labels = np.zeros(0, dtype=np.int64)
            return
        x0, y0, x1, y1 = hull.bounds
        wi, wj = r.window(shapely.box(x0 - reach, y0 - reach, x1 + reach, y1 + reach))
        (ox, oy), c = r.origin, r.cell
        rect = (ox + wi.start * c, oy + wj.start * c, ox + wi.stop * c, oy + wj.stop * c)
        self.free = shapely.intersection(floor.free, shapely.box(*rect))
        outside = floor.cells.copy()
        outside[wi, wj] = False
        labels, _ = ndimage.label(outside, structure=_EIGHT)
        i0, i1, j0, j1 = wi.start, wi.stop, wj.start, wj.stop
        ring = [(i, j) for i in range(i0 - 1, i1 + 1) for j in (j0 - 1, j1)]
        ring += [(i, j) for i in (i0 - 1, i1) for j in range(j0, j1)]
        nx, ny = r.shape
        ii, jj = np.array([(i, j) for i, j in ring if 0 <= i < nx and 0 <= j < ny
                           and labels[i, j]], dtype=np.int64).reshape(-1, 2).T
        self.ring_labels = labels[ii, jj].astype(np.int64)
        # the cells grown by TOUCH (a box's mitred offset is a box)
        self.ring = shapely.box(ox + ii * c - TOUCH, oy + jj * c - TOUCH,
                                ox + (ii + 1) * c + TOUCH, oy + (jj + 1) * c + TOUCH)

    def joined(self, closed: BaseGeometry, ends: list[BaseGeometry]) -> bool:
        """Whether a part of the free set less ``closed`` joins the two ``ends``."""
        left = self.free.difference(closed)
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

        if len(self.ring):
            hits = shapely.intersects(parts[:, None], self.ring[None, :])
            for p, k in zip(*np.nonzero(hits), strict=True):
                parent[find(int(p))] = find(n + int(self.ring_labels[k]))
        near = shapely.dwithin(parts[:, None], parts[None, :], TOUCH)
        for p, q in zip(*np.nonzero(near), strict=True):
            parent[find(int(p))] = find(int(q))
        return bool({find(u) for u in a} & {find(v) for v in b})

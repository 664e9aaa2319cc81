"""Whether a regrasp of the held poses' graph may be walked: exact polygons, split where tight.

A regrasp from grasp ``k`` to ``j`` leaves the box resting at one pose and walks the robot
from its grasp-``k`` pose to its grasp-``j`` pose, the walking body clear of the obstacles
(by the checkers' clearance), inside the bounds and clear of the box (the swept checks'
tolerance aside). The walking body (a rectangle,
:meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`) is relaxed to the largest disk inside
it, round the rectangle's own centre (inside the body at any heading; the robot pose's own
inscribed disk is smaller when the body reaches further ahead than behind), so a walk is a
path of the disk's centre through :func:`~pivot_ompl.validity.footprints.disk_clear`'s free
set (a superset of the true one) that keeps out of the box.

The question is asked of a *piece* of box positions ``H`` (convex) at the yaws of one bin
``[a, b]``, and answered on exact polygons, with no raster:

* where the box certainly is, whichever pose of the piece it rests at: the box's rotation
  core over the bin (:func:`~pivot_ompl.analysis.pose_cells.rotation_core`, inside the box
  at every yaw of the bin) placed at every vertex of ``H`` and intersected (the core and
  ``H`` convex: inside the core placed at every point of ``H``). Disk centres nearer to it
  than the disk's radius less the tolerance are closed (the offset's chords: inside the
  true offset);
* where the robot may stand at grasp ``g``: ``H`` moved by the grasp's offset turned to the
  bin's middle, grown by how far a half bin's turn moves that offset (a polygon round the
  disk of that radius);
* the walk may exist only if one connected part of the free set less the closed disk
  centres meets both stands.

A piece that may hold the regrasp is cut in four (its bounding box's quarters) and each
asked again, until the pieces are :data:`SPLIT` small or :data:`MOST_PIECES` have been asked
(then "may": sound, only weaker). The regrasp is refused only when every piece refuses it.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_cells import held_bodies, rotation_core
from pivot_ompl.scene import Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import disk_clear
from pivot_ompl.validity.merge import merge_boxes

#: Pieces of box positions this small (m, the larger side of their bounding box) are not cut.
SPLIT = 0.01
#: Pieces asked per regrasp at most.
MOST_PIECES = 256
#: Added to every erosion and growth (m): keeps the relaxation on the safe side of round-off.
ROUND_OFF = 1e-7
#: Segments per quarter circle of the polygons round disks.
QUAD_SEGS = 4


def _turned(points: np.ndarray, yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return points @ np.array([[c, s], [-s, c]])


class PoseWalks:
    """Whether the walking robot may regrasp with the box resting in a piece of a bin.

    Args:
        scene: the scene.
        tolerance: the swept checks' tolerance (m).
        clearance: what the checkers keep the walking body from the obstacles (m).
    """

    def __init__(self, scene: Scene, *, tolerance: float = SWEEP_TOLERANCE,
                 clearance: float = KEEP_CLEARANCE) -> None:
        """The disk centre's free set, cut into its connected parts (obstacles and bounds)."""
        m = self.model = scene.model
        ahead, behind, side = m.walking_extent()
        self.radius = min(side, 0.5 * (ahead + behind))
        self.centre = 0.5 * (ahead - behind)  # the body's centre, ahead of the robot pose
        free = disk_clear(scene.bounds, merge_boxes(scene.obstacles), radius=self.radius,
                          clearance=clearance - tolerance - ROUND_OFF)
        self.free = [g for g in getattr(free, "geoms", [free]) if not g.is_empty]
        self.tree = shapely.STRtree(self.free)
        self.gap = self.radius - tolerance - ROUND_OFF
        self.box = held_bodies(m)[0][0]  # the box's footprint, counter-clockwise
        #: pieces asked so far (all questions)
        self.pieces = 0

    def may_regrasp(self, region: BaseGeometry, a: float, b: float, k: int, j: int) -> bool:
        """Whether a regrasp from ``k`` to ``j`` may happen with the box in ``region``.

        ``region``: box positions; ``[a, b]``: the bin's yaws (rad, ``b - a`` below pi).
        ``False`` proves that it cannot (module docstring).
        """
        if region.is_empty:
            return False
        half, mid = 0.5 * (b - a), 0.5 * (a + b)
        core = rotation_core(self.box, half)
        if core is None:
            return True
        core = _turned(core, mid)
        stands = []
        for g in (k, j):
            x, y, h = self.model.robot_pose((0.0, 0.0, mid), g)
            offset = np.array([x + self.centre * math.cos(h), y + self.centre * math.sin(h)])
            sway = 2.0 * math.hypot(*offset) * math.sin(0.5 * half) + ROUND_OFF
            stands.append((offset, sway / math.cos(math.pi / (4 * QUAD_SEGS))))
        todo, asked = [region.convex_hull], 0
        while todo:
            piece = todo.pop()
            asked += 1
            self.pieces += 1
            if not self._may(piece, core, stands):
                continue
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

    def _may(self, piece: BaseGeometry, core: np.ndarray,
             stands: list[tuple[np.ndarray, float]]) -> bool:
        """Whether a walk may join the two stands with the box anywhere in ``piece``."""
        corners = np.asarray(piece.exterior.coords)[:-1] if piece.geom_type == "Polygon" \
            else np.asarray(piece.envelope.buffer(ROUND_OFF).exterior.coords)[:-1]
        sure = shapely.Polygon(core + corners[0])
        for c in corners[1:]:
            sure = sure.intersection(shapely.Polygon(core + c))
            if sure.is_empty:
                return True  # nothing of the box is certain: it may not block
        closed = sure.buffer(self.gap, quad_segs=QUAD_SEGS)
        ends = [shapely.affinity.translate(piece, *offset).buffer(sway, quad_segs=QUAD_SEGS)
                for offset, sway in stands]
        near = set(self.tree.query(ends[0], predicate="intersects").tolist()) & set(
            self.tree.query(ends[1], predicate="intersects").tolist())
        for i in sorted(near):
            rest = self.free[i].difference(closed)
            if any(p.intersects(ends[0]) and p.intersects(ends[1])
                   for p in getattr(rest, "geoms", [rest])):
                return True
        return False

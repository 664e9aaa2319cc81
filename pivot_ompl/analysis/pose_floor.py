"""What the held poses' relaxations of one scene share: its pieces, bodies, room and walks.

The held poses' proof (:func:`~pivot_ompl.analysis.pose_proof.prove_no_plan`) and its gate
(:func:`~pivot_ompl.analysis.pose_inner.joined_at_every_yaw`) read the same floor: the
obstacles merged into convex pieces, the held assembly's bodies, the box centre's room and
the regrasp walks' floor. :class:`HeldFloor` builds each once; the pieces grown by a
clearance, those near the room and those near its narrow passages, are built when first
asked and kept per clearance.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_cells import (
    ROUND_OFF,
    bound_slabs,
    by_size,
    centre_room,
    grown_pieces,
    held_bodies,
    near,
)
from pivot_ompl.analysis.pose_coarse import coarse_pieces
from pivot_ompl.analysis.pose_passages import diameter, passage_pieces
from pivot_ompl.analysis.pose_walk import RegraspWalks
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes


class HeldFloor:
    """A scene's floor for the held poses' relaxations, built once.

    Args:
        scene: the scene.
        clearance: kept from the obstacles (m) by the box centre's room (:attr:`room`).
        should_stop: polled while the obstacles are merged and before the room is found
            (:class:`~pivot_ompl.errors.Interrupted` when true).

    Attributes:
        bodies: per grasp, the held assembly's convex bodies
            (:func:`~pivot_ompl.analysis.pose_cells.held_bodies`).
        reach: the bodies' farthest point from the box centre (m).
        radius: the disk inside the box at every yaw (m, about its centre) whose free
            positions are the room.
        room: where the box centre may go at all (``None``: not even the start is in it).
        area: :attr:`room`, or an empty polygon.
        walks: the regrasp walks' questions (:class:`~pivot_ompl.analysis.pose_walk.RegraspWalks`).
    """

    def __init__(self, scene: Scene, clearance: float,
                 should_stop: Callable[[], bool] | None) -> None:
        """Merge the pieces and find the room (the walks' floor is built when first asked)."""
        self.scene, self.clearance = scene, clearance
        self.pieces = obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))
        self.bodies = held_bodies(scene.model)
        self.reach = max(float(np.abs(b).max()) for bodies in self.bodies for b in bodies)
        self.slabs = bound_slabs(scene.bounds, 2.0 * self.reach + 1.0)
        self._grown: dict[float, dict[int, np.ndarray]] = {}
        self._near: dict[float, dict[int, np.ndarray]] = {}
        self._coarse: dict[float, dict[int, np.ndarray]] = {}
        self._passages: dict[float, dict[int, np.ndarray]] = {}
        self.radius = 0.5 * min(scene.model.object_size[:2]) - ROUND_OFF
        self._coarse_pieces: list[np.ndarray] | None = None
        grown = self.grown(clearance)
        if should_stop is not None and should_stop():
            raise Interrupted("the held poses' relaxation")
        self.room: BaseGeometry | None = centre_room(
            grown, self.radius, shapely.box(*scene.bounds), scene.start[:2])
        self.area = self.room if self.room is not None else shapely.Polygon()
        self.walks = RegraspWalks(scene, tolerance=SWEEP_TOLERANCE, clearance=KEEP_CLEARANCE)

    def grown(self, clearance: float) -> dict[int, np.ndarray]:
        """The pieces grown by ``clearance`` (m) and the bounds' slabs, stacked by size (kept)."""
        if clearance not in self._grown:
            self._grown[clearance] = self._stacked(self.pieces, clearance)
        return self._grown[clearance]

    def near_room(self, clearance: float) -> dict[int, np.ndarray]:
        """:meth:`grown` less the pieces no body in the room can meet (kept)."""
        if clearance not in self._near:
            self._near[clearance] = self._near_room(self.grown(clearance))
        return self._near[clearance]

    def passages_near_room(self, clearance: float) -> dict[int, np.ndarray]:
        """:meth:`near_room`'s pieces near the room's narrow passages between start and goal.

        :func:`~pivot_ompl.analysis.pose_passages.passage_pieces`: a passage is narrow where
        the room is narrower than the held assembly's diameter (less the room's own disk), so
        the yaw and grasp decide whether the assembly passes; the pieces within the bodies'
        reach of one (kept). Fewer pieces than :meth:`near_room`'s: for over-approximations
        of the free set only.
        """
        if clearance not in self._passages:
            scene = self.scene
            self._passages[clearance] = passage_pieces(
                self.near_room(clearance), self.area,
                half_width=0.5 * diameter(self.bodies) - self.radius, reach=self.reach,
                ends=[(scene.start[0], scene.start[1]), (scene.goal[0], scene.goal[1])])
        return self._passages[clearance]

    def coarse_near_room(self, clearance: float,
                         should_stop: Callable[[], bool] | None = None) -> dict[int, np.ndarray]:
        """:meth:`near_room` of :func:`~pivot_ompl.analysis.pose_coarse.coarse_pieces` (kept).

        Fewer pieces, each holding some of :meth:`near_room`'s: for under-approximations of
        the free set only. ``should_stop`` is polled while the pieces are merged
        (:class:`~pivot_ompl.errors.Interrupted` when true).
        """
        if clearance not in self._coarse:
            if self._coarse_pieces is None:
                self._coarse_pieces = coarse_pieces(self.pieces, should_stop=should_stop)
            self._coarse[clearance] = self._near_room(
                self._stacked(self._coarse_pieces, clearance))
        return self._coarse[clearance]

    def _stacked(self, pieces: list[np.ndarray], clearance: float) -> dict[int, np.ndarray]:
        """``pieces`` grown by ``clearance`` (m) and the bounds' slabs, stacked by size."""
        return by_size(grown_pieces(pieces, clearance) + self.slabs)

    def _near_room(self, grown: dict[int, np.ndarray]) -> dict[int, np.ndarray]:
        """``grown`` less the pieces no body in the room can meet."""
        return near(grown, self.area, self.reach + 1e-3)

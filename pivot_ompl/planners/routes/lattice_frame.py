"""The transfer lattice's frame: the floor turned so that its headings run along its walls.

The lattice's headings are fixed directions of its grid (0, atan(1/2), pi/4, ...:
:data:`~pivot_ompl.transit.lattice.HEADING_YAWS`). A floor whose walls run at another angle (a
turned or reflected building, a map read at a yaw) has its corridors between two headings:
a route along a wall zigzags, and its ends, poses along the walls, join the lattice by turns
that graze them. So the lattice is laid in the walls' frame
(:func:`~pivot_ompl.analysis.wall_frame.wall_frame`: the scene turned by its walls' direction
about its bounds' centre and cut to its free floor, the grid's lines through the free
floor's corner, where a floor drawn in its walls' frame has its bounds' corner and so its own
grid's): a turned copy of a scene gets the lattice of the original. The direction is that of
the wall faces that look onto the free floor (``facing=True``): the old floor a turned or
reflected copy keeps as walls round it counts by its inner faces only, so on a floor whose
walls run at several angles the copy's direction is still the original's. Turning is a
rigid motion, so a route of the turned floor is one of the floor; poses go in and out by
:meth:`LatticeFrame.car_in` and :meth:`LatticeFrame.car_out`, and the route's ends stay the
exact poses asked for (the lattice's routes join them as it joins any end). A floor whose walls
run along the axes (or with too many pieces for the walls' frame) keeps its own frame: the
lattice over it is the one it always was.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely.affinity
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.wall_frame import wall_frame
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene.shared import scene_shared
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.validity.collision import CollisionWorld

__all__ = ["LatticeFrame", "lattice_frame"]


@dataclass(frozen=True)
class LatticeFrame:
    """Where the lattice lies: the scene turned by ``-yaw`` about ``centre``.

    Attributes:
        yaw: the walls' direction in the scene (rad); 0: the scene's own frame.
        centre: the point turned about (m).
        world: the turned floor's obstacles and bounds (``None``: the scene's own world).
    """

    yaw: float = 0.0
    centre: tuple[float, float] = (0.0, 0.0)
    world: CollisionWorld | None = None

    def car_in(self, car: Pose) -> Pose:
        """A pose of the scene, in the lattice's frame."""
        if self.yaw == 0.0:
            return car
        x, y, yaw = rotate_about(car, self.centre, -self.yaw)
        return (x, y, wrap_angle(yaw))

    def car_out(self, car: Pose) -> Pose:
        """A pose of the lattice's frame, in the scene (:meth:`car_in`'s inverse)."""
        if self.yaw == 0.0:
            return car
        x, y, yaw = rotate_about(car, self.centre, self.yaw)
        return (x, y, wrap_angle(yaw))

    def poses_out(self, poses: np.ndarray) -> np.ndarray:
        """Poses ``(n, 3)`` of the lattice's frame, in the scene (a new array)."""
        if self.yaw == 0.0:
            return poses
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        dx, dy = poses[:, 0] - self.centre[0], poses[:, 1] - self.centre[1]
        yaw = np.mod(poses[:, 2] + self.yaw + math.pi, 2.0 * math.pi) - math.pi
        return np.column_stack([self.centre[0] + c * dx - s * dy,
                                self.centre[1] + s * dx + c * dy, yaw])

    def region_in(self, region: BaseGeometry) -> BaseGeometry:
        """A region of the scene's floor, in the lattice's frame."""
        if self.yaw == 0.0:
            return region
        return shapely.affinity.rotate(region, -self.yaw, origin=self.centre, use_radians=True)


def lattice_frame(checker: PivotChecker, *, resolution: float) -> LatticeFrame:
    """The frame of a lattice over ``checker``'s scene at ``resolution`` (m), shared by scene.

    The walls' frame (module docstring), whatever its bounds' area, its grid's lines at
    ``resolution`` through the free floor's corner; the scene's own frame where there is none.
    """
    clearance = checker.world.clearance

    def made() -> LatticeFrame:
        f = wall_frame(checker.scene, clearance=clearance, worth=math.inf,
                       floor_grid=resolution, facing=True)
        if f is None:
            return LatticeFrame()
        return LatticeFrame(f.yaw, f.centre,
                            CollisionWorld.from_scene(f.scene, clearance=clearance))

    frame = scene_shared(checker.scene, ("lattice frame", float(clearance), float(resolution)),
                         made)
    assert frame is not None
    return frame

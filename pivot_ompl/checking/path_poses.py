"""Poses along a car's path tested free, the clearance carried from pose to pose as a bound.

The cheap test before a transfer's full check
(:meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.cars_free`) asks whether the box (and
the holding robot) are inside the bounds and collision-free at poses along the car's path.
Between two poses of the path no point of a body moves farther than the path's length between
them times ``1 + s / R`` (the car's reference moves at unit speed and turns at most ``1 / R``
per metre; ``s`` the body's farthest point from the car, ``R`` the turning radius), or, on a
spin, than ``s`` times the angle turned. A body whose clearance at one pose exceeds that
displacement (by :data:`SKIP_MARGIN`) is free at the next with no query; its clearance there
is at least the difference, carried on. The answer is the one every pose measured gives.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.curves import CarPaths
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.validity.collision import CollisionWorld

__all__ = ["POLL_POSES", "SKIP_MARGIN", "PathPoses"]

#: Poses tested between two polls of ``should_stop`` (a pose costs up to a few ms against a
#: 10 000-point polygon: a 100 m path is 400 poses).
POLL_POSES = 8

#: Least clearance bound (m) that answers "free" without a query: far above the distance
#: queries' round-off (coal's GJK answers within about a micrometre), so that a bound never
#: answers where a query would say otherwise.
SKIP_MARGIN = 1e-5


class PathPoses:
    """Tests of poses along car paths of one scene (see the module docstring).

    Args:
        model: box and robot geometry.
        world: obstacles and bounds.
        paths: the car's reference paths (Reeds-Shepp curves and spins).
        spread: per grasp, the box's and the holding robot's farthest corners (m) from the
            car (:attr:`~pivot_ompl.checking.rotation_sweeps.RotationSweeps.spread`).
    """

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, paths: CarPaths,
                 spread: Mapping[int, tuple[float, float]]) -> None:
        """Poses tested with these parts and the bodies' spreads round the car."""
        self.model, self.world, self.paths = model, world, paths
        self._spread = spread

    def free(self, car_a: Pose, car_b: Pose, grasp: int, ts: Sequence[float], *,
             with_robot: bool, should_stop: Callable[[], bool] | None) -> bool:
        """The box (and robot) inside the bounds and free at fractions ``ts`` of the path.

        Raises:
            Interrupted: ``should_stop()`` became true (polled every :data:`POLL_POSES`
                poses) before the answer was known.
        """
        m, w = self.model, self.world
        ts = list(ts)
        cars = self.paths.sample(car_a, car_b, ts)
        s_box, s_rob = self._spread[grasp]
        if self.paths.is_spin(car_a, car_b):  # the car turns in place
            turn = abs(wrap_angle(car_b[2] - car_a[2]))
            rate_box, rate_rob = turn * s_box, turn * s_rob
        else:
            length = self.paths.distance(car_a, car_b)
            radius = self.paths.rs.turning_radius
            rate_box, rate_rob = length * (1.0 + s_box / radius), length * (1.0 + s_rob / radius)
        obstacles = w.has_obstacles
        lb_box = lb_rob = -math.inf  # clearance bounds at the last pose tested
        last = None
        for k, (t, c) in enumerate(zip(ts, cars, strict=True)):
            if should_stop is not None and k % POLL_POSES == 0 and k and should_stop():
                raise Interrupted("testing poses along a path")
            if last is not None:
                dt = abs(t - last)
                lb_box -= dt * rate_box
                lb_rob -= dt * rate_rob
            last = t
            obj = m.object_from_car(c, grasp)
            if not w.box_in_bounds(obj):
                return False
            if obstacles and lb_box <= SKIP_MARGIN:
                lb_box = w.box_distance(obj)
                if lb_box <= 0.0:
                    return False
            if not with_robot:
                continue
            r = m.robot_pose(obj, grasp)
            if not w.held_in_bounds(r, grasp):
                return False
            if obstacles and lb_rob <= SKIP_MARGIN:
                lb_rob = w.held_distance(r, grasp)
                if lb_rob <= 0.0:
                    return False
        return True

"""A walk's result: its key poses, length and cost."""

from __future__ import annotations

import math
from dataclasses import dataclass

from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.lattice import motion_cost


@dataclass(frozen=True)
class WalkResult:
    """A transit walk.

    Attributes:
        valid: a collision-free walk was found.
        robot_path: key poses (straight segments, yaw interpolated linearly between them).
        length: walking distance of the robot's centre (m).
        cost: walking cost (m of forward walking: sideways, backward and turning weighted by
            the scene's ``robot.walk`` costs).
    """

    valid: bool
    robot_path: tuple[Pose, ...]
    length: float
    cost: float


INVALID_WALK = WalkResult(False, (), math.inf, math.inf)


def walk_result(poses: list[Pose], walk: WalkParameters) -> WalkResult:
    """The walk through ``poses``: yaws unwrapped pose to pose, the last pose kept as given."""
    keys = [poses[0]]
    for p in poses[1:]:
        last = keys[-1]
        q = (p[0], p[1], last[2] + wrap_angle(p[2] - last[2]))
        if abs(q[0] - last[0]) + abs(q[1] - last[1]) + abs(q[2] - last[2]) > 1e-12:
            keys.append(q)
    keys[-1] = poses[-1]
    length = sum(math.hypot(b[0] - a[0], b[1] - a[1])
                 for a, b in zip(keys, keys[1:], strict=False))
    cost = sum(motion_cost(a, b, walk) for a, b in zip(keys, keys[1:], strict=False))
    return WalkResult(True, tuple(keys), length, cost)

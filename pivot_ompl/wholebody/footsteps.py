"""Footstep planning (pure geometry): where each foot lands along a robot path or a pivot arc.

A robot pose (x, y, heading) stands its two sole frames :func:`feet_frames` apart by
:attr:`WalkSettings.feet_spacing` across the heading, their midpoint
:attr:`WalkSettings.foot_offset` ahead of the pose. A step lands the flying foot at its nominal
place beside some robot pose; :func:`reachable` says which landings the support foot allows
(:attr:`WalkSettings.max_dx_forward`, ``max_dx_backward``, ``foot_dy_out``, ``foot_dy_in``,
``foot_dtheta``, ``sole_gap``). A footstep list starts with the two current feet (flying foot
first), as PlaCo's ``make_supports`` expects, and the feet alternate after them.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.wholebody.box import rot_z, transform
from pivot_ompl.wholebody.settings import WalkSettings

log = logging.getLogger(__name__)

def _sole_corners(sole: tuple[float, float]) -> np.ndarray:
    """The sole's corners in its own frame (homogeneous columns)."""
    return _corners(float(sole[0]), float(sole[1]))


@functools.lru_cache(maxsize=8)
def _corners(length: float, width: float) -> np.ndarray:
    out = np.array([[x, y, 0.0, 1.0] for x in (0.5 * length, -0.5 * length)
                    for y in (0.5 * width, -0.5 * width)]).T
    out.flags.writeable = False
    return out


#: Most steps :func:`pivot_footsteps` tries before it gives up.
MAX_PIVOT_STEPS = 8


@dataclass(frozen=True)
class Footstep:
    """One foot placed on the floor.

    Attributes:
        left: the left foot (else the right one).
        frame: its sole frame (4 x 4, world).
    """

    left: bool
    frame: np.ndarray

    @property
    def side(self) -> str:
        """``"left"`` or ``"right"``."""
        return "left" if self.left else "right"


def pose_matrix(x: float, y: float, yaw: float, z: float = 0.0) -> np.ndarray:
    """4x4 transform of a planar pose."""
    return transform(rot_z(yaw), (x, y, z))


def planar(T: np.ndarray) -> Pose:
    """Planar pose (x, y, yaw) of a 4x4 transform."""
    return (float(T[0, 3]), float(T[1, 3]), math.atan2(T[1, 0], T[0, 0]))


def relative(a: Pose, b: Pose) -> tuple[float, float, float]:
    """Pose ``b`` in the frame of pose ``a`` (dx, dy, dyaw)."""
    c, sn = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + sn * dy, -sn * dx + c * dy, wrap_angle(b[2] - a[2]))


def densify(path: list[Pose], resolution: float) -> list[Pose]:
    """Poses along ``path`` (straight lines, yaw linear the shorter way).

    Consecutive poses are at most ``resolution`` m (or ``2 * resolution`` rad) apart.
    """
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:], strict=True):
        dth = wrap_angle(b[2] - a[2])
        n = max(1, math.ceil(max(math.hypot(b[0] - a[0], b[1] - a[1]),
                                 0.5 * abs(dth)) / resolution))
        for k in range(1, n + 1):
            u = k / n
            out.append((a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]), a[2] + u * dth))
    return out


def feet_frames(pose: Pose, settings: WalkSettings) -> tuple[np.ndarray, np.ndarray]:
    """Sole frames (left, right) on the floor for the robot pose ``pose``."""
    c, sn = math.cos(pose[2]), math.sin(pose[2])
    mx, my = pose[0] + settings.foot_offset * c, pose[1] + settings.foot_offset * sn
    half = 0.5 * settings.feet_spacing
    return (pose_matrix(mx - half * sn, my + half * c, pose[2]),
            pose_matrix(mx + half * sn, my - half * c, pose[2]))


def stance_pose(T_left: np.ndarray, T_right: np.ndarray, settings: WalkSettings) -> Pose:
    """The robot pose of two sole frames: their midpoint, the mean of their yaws."""
    mid = 0.5 * (T_left + T_right)
    yaw = planar(T_left)[2]
    yaw = yaw + 0.5 * wrap_angle(planar(T_right)[2] - yaw)
    off = settings.foot_offset
    return (mid[0, 3] - off * math.cos(yaw), mid[1, 3] - off * math.sin(yaw), yaw)


def reachable(T_fly: np.ndarray, T_support: np.ndarray, *, left: bool,
              settings: WalkSettings, ellipsoid: bool = False) -> bool:
    """Whether a foot can land at ``T_fly`` beside the support foot ``T_support``.

    Relative to the foot's nominal place beside the support foot: along within
    ``max_dx_forward`` / ``max_dx_backward``, outside within ``foot_dy_out``, yaw within
    ``foot_dtheta`` (each alone, or together in their ellipsoid with ``ellipsoid``);
    inside at most ``foot_dy_in``; the soles at least ``sole_gap`` apart.
    """
    s = settings
    sign = 1.0 if left else -1.0
    rel = np.linalg.inv(T_support) @ T_fly
    dx = float(rel[0, 3])
    dy = sign * (float(rel[1, 3]) - sign * s.feet_spacing)  # > 0: outside
    dth = abs(math.atan2(rel[1, 0], rel[0, 0]))
    if not (-s.max_dx_backward <= dx <= s.max_dx_forward):
        return False
    if not (-s.foot_dy_in <= dy <= s.foot_dy_out) or dth > s.foot_dtheta:
        return False
    if ellipsoid:
        dx_max = s.max_dx_forward if dx >= 0 else s.max_dx_backward
        if ((dx / dx_max) ** 2 + (max(dy, 0.0) / s.foot_dy_out) ** 2
                + (dth / s.foot_dtheta) ** 2) > 1.0:
            return False
    # soles apart: the flying sole's corners beyond the support sole's inner side
    # and the support sole's corners beyond the flying sole's, by the gap
    sole = s.profile.sole_size
    hy = 0.5 * sole[1]
    corners = _sole_corners(sole)
    a = sign * (rel @ corners)[1]
    b = -sign * (np.linalg.inv(rel) @ corners)[1]
    return bool(a.min() >= hy + s.sole_gap and b.min() >= hy + s.sole_gap)


def left_flies_first(T_left: np.ndarray, T_right: np.ndarray, target: Pose) -> bool:
    """Whether a walk from the feet towards robot pose ``target`` starts with the left foot.

    The left foot when the target is to the left of the feet's midpoint (more than 1 mm),
    or straight ahead or behind and turned left (or not at all).
    """
    yaw = planar(T_left)[2]
    cur = np.linalg.inv(pose_matrix(*planar(0.5 * (T_left + T_right))[:2], yaw))
    local = cur @ np.array([target[0], target[1], 0.0, 1.0])
    dyaw = wrap_angle(target[2] - yaw)
    return bool(local[1] > 1e-3 or (abs(local[1]) <= 1e-3 and dyaw >= 0))


def _first_flying_foot(dense: list[Pose]) -> bool:
    """Whether the left foot flies first: the side the path leaves towards (or turns to)."""
    cur = dense[0]
    for pose in dense[1:]:
        dx, dy, dth = relative(cur, pose)
        if abs(dy) > 0.02 or abs(dth) > 0.05:
            return dy > 0 if abs(dy) > 0.02 else dth > 0
        if abs(dx) > 0.05:
            break
    return True


def path_footsteps(path: list[Pose], *, feet: tuple[np.ndarray, np.ndarray],
                   settings: WalkSettings, resolution: float = 0.01,
                   path_tol: float = 0.015) -> list[Footstep]:
    """Footsteps from the sole frames ``feet`` (left, right) that follow ``path``.

    The path runs from the feet's robot pose (:func:`stance_pose`) through the robot poses
    ``path``, joined by straight lines with linear yaw. Each step lands the flying foot at
    its nominal place beside the furthest pose along the path that it reaches from the
    support foot (:func:`reachable`, in the ellipsoid of the limits), the sole midpoint of
    the double support that follows within ``path_tol`` (m) of the path (corners are not
    cut). A last step brings the feet together at the path's end. Empty when no step is
    needed.
    """
    T_l, T_r = feet
    dense = densify([stance_pose(T_l, T_r, settings), *path], resolution)
    fly_left = _first_flying_foot(dense)
    steps = [Footstep(fly_left, T_l if fly_left else T_r),
             Footstep(not fly_left, T_r if fly_left else T_l)]
    placed = {True: np.array(T_l), False: np.array(T_r)}
    beside = {True: 0, False: 0}  # index of the dense pose each foot stands beside
    cur, i = dense[0], 0
    while i < len(dense) - 1:
        j = i
        while j + 1 < len(dense):
            cand = feet_frames(dense[j + 1], settings)[0 if fly_left else 1]
            support = placed[not fly_left]
            if not reachable(cand, support, left=fly_left, settings=settings, ellipsoid=True):
                break
            # the sole midpoint of the double support that follows stays on the path
            mid = 0.5 * (cand[:2, 3] + support[:2, 3])
            near = dense[beside[not fly_left]:j + 2]
            if min(math.hypot(mid[0] - q[0], mid[1] - q[1]) for q in near) > path_tol:
                break
            j += 1
        if j == i:  # resolution too coarse for the limits: force progress
            j = i + 1
        cur, i = dense[j], j
        placed[fly_left] = feet_frames(cur, settings)[0 if fly_left else 1]
        beside[fly_left] = j
        steps.append(Footstep(fly_left, placed[fly_left]))
        fly_left = not fly_left
    if len(steps) == 2:
        return []
    last = feet_frames(cur, settings)[0 if fly_left else 1]
    if not np.allclose(placed[fly_left], last, atol=1e-4):
        steps.append(Footstep(fly_left, last))
    return steps


def pivot_footsteps(path: list[Pose], *, feet: tuple[np.ndarray, np.ndarray],
                    settings: WalkSettings, fly_left: bool | None = None,
                    resolution: float = 0.005) -> list[Footstep]:
    """Fewest footsteps from the sole frames ``feet`` (left, right) to ``path[-1]``.

    Each foot lands at its nominal place beside a pose along ``path``, which runs from the
    robot's pose to its pose after a pivot rotation (the arc its attached pose describes
    about the pivot): the furthest pose along the path that the support foot can reach
    (:func:`reachable`, each limit alone). Unlike :func:`path_footsteps` the robot need not
    stand at each intermediate pose, only both feet at the end's, so a pivot takes two or
    three steps. ``fly_left`` forces the first flying foot (a walk alternates its feet).

    Empty when no step is needed or when no sequence of at most :data:`MAX_PIVOT_STEPS`
    steps reaches the end (the caller then walks with :func:`path_footsteps`).
    """
    dense = densify(list(path), resolution)
    nominal = [feet_frames(q, settings) for q in dense]
    goal_l, goal_r = nominal[-1]
    T = {True: np.array(feet[0]), False: np.array(feet[1])}

    def arrived() -> bool:
        return bool(np.allclose(T[True], goal_l, atol=1e-4)
                    and np.allclose(T[False], goal_r, atol=1e-4))

    if arrived():
        return []
    if fly_left is None:
        dx, dy, dth = relative(dense[0], dense[-1])
        fly_left = dy > 0 if abs(dy) > 0.02 else dth >= 0
    steps = [Footstep(fly_left, T[fly_left]), Footstep(not fly_left, T[not fly_left])]
    side = fly_left
    for _ in range(MAX_PIVOT_STEPS):
        landing = next((nominal[k][0 if side else 1] for k in range(len(dense) - 1, -1, -1)
                        if reachable(nominal[k][0 if side else 1], T[not side], left=side,
                                     settings=settings)), None)
        if landing is None:
            return []
        T[side] = landing
        steps.append(Footstep(side, landing))
        side = not side
        if arrived():
            return steps
    return []


def chunks(footsteps: list, max_steps: int) -> list[list]:
    """Split footsteps (led by the two current feet) into walks of at most ``max_steps`` steps.

    Each walk is led by its two current feet and starts and ends at rest.
    """
    moves = len(footsteps) - 2
    return [footsteps[a:min(moves, a + max_steps) + 2] for a in range(0, moves, max_steps)]

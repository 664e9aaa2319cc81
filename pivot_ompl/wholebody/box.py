"""Box and grip-point kinematics for whole-body pivoting (frames as 4x4 homogeneous matrices).

Frames
    ``T_world_G`` -- the *grasp frame* of grasp ``k``: origin at the centre of the supporting
    edge (the footprint edge nearest the robot, under the held face) on the floor, x along the
    robot's facing direction ``h = yaw + k*pi/2``, z up. The held face is the plane ``x = 0``
    of G. While the box is held, G is *tilted*: rotated by ``-tilt`` about its own y axis (the
    supporting edge), so the box leans towards the robot and rests on that edge only.
    ``T_world_box`` -- the box centre, axes along the box's size (x along ``size[0]``).

Inclination
    :data:`DEFAULT_TILT` = 5 deg. The supporting edge, hence both pivot corners, stays on the
    floor while tilting; a pivot step then turns the tilted box about the vertical through one
    end corner of that edge.

Grip points (both hands on the held face)
    In G: ``(-offset, +/-spacing, height)`` = ``(-0.055, +/-0.25, 0.95)`` m by default
    (left hand at +y). ``height`` is clipped to ``box height - 0.10`` and the spacing to
    ``edge half-length - 0.05`` for small boxes. The grip point (0.15 m from the wrist, between
    the fingers) sits 5.5 cm in front of the face, so the hand's end (0.205 m from the wrist)
    touches it: a palm-and-fingertips push, the box being held between the two hands, the
    floor and its inclination.
    Hand orientation: approach axis (hand -z) along +x of G (into the face), fingers' closing
    axis (hand x) along +z of G (up the face): ``R_G_hand = R_y(-pi/2)``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl.grasp import (
    GRIP_EDGE,
    GRIP_HEIGHT,
    GRIP_OFFSET,
    GRIP_SPACING,
    GRIP_TOP,
    HOLD_TILT,
)
from pivot_ompl.se2 import Pose

#: The hold conventions live in :mod:`pivot_ompl.grasp` (the planner's bodies use them too).
DEFAULT_TILT = HOLD_TILT


def rot_z(a: float) -> np.ndarray:
    """3x3 rotation about z by ``a`` (rad)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(a: float) -> np.ndarray:
    """3x3 rotation about y by ``a`` (rad)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def transform(R: np.ndarray, p) -> np.ndarray:  # noqa: ANN001
    """4x4 homogeneous transform from rotation ``R`` and translation ``p``."""
    T = np.zeros((4, 4))  # not np.eye: this runs several times a solver tick
    T[:3, :3] = R
    T[:3, 3] = p
    T[3, 3] = 1.0
    return T


def rotation_about_vertical(pivot: tuple[float, float], angle: float) -> np.ndarray:
    """4x4 world rotation by ``angle`` (rad, CCW) about the vertical through ``pivot``."""
    c, s = math.cos(angle), math.sin(angle)
    x, y = pivot
    return np.array([[c, -s, 0.0, x - c * x + s * y], [s, c, 0.0, y - s * x - c * y],
                     [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def quat_xyzw(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (x, y, z, w) of a rotation matrix, w >= 0."""
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(R, dtype=float)).coeffs()  # x, y, z, w
    q = np.asarray(q, dtype=float)
    return -q if q[3] < 0 else q


def quats_xyzw(R: np.ndarray) -> np.ndarray:
    """:func:`quat_xyzw` of each rotation matrix of ``R`` (N x 3 x 3): N x 4, w >= 0.

    Shepperd's method: from the largest of ``4 w², 4 x², 4 y², 4 z²`` (no square root of a
    small number), vectorised.
    """
    R = np.asarray(R, dtype=float).reshape(-1, 3, 3)
    r00, r11, r22 = R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]
    a, b = R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0]
    c = R[:, 1, 0] - R[:, 0, 1]
    d, e = R[:, 1, 0] + R[:, 0, 1], R[:, 0, 2] + R[:, 2, 0]
    f = R[:, 2, 1] + R[:, 1, 2]
    big = np.stack((1 + r00 + r11 + r22, 1 + r00 - r11 - r22, 1 - r00 + r11 - r22,
                    1 - r00 - r11 + r22), axis=1)  # 4 w², 4 x², 4 y², 4 z²
    k = np.argmax(big, axis=1)
    s = np.sqrt(np.maximum(big[np.arange(len(R)), k], 1e-300))
    cands = np.stack((np.stack((a, b, c, s * s), axis=1),  # x y z w, times s
                      np.stack((s * s, d, e, a), axis=1),
                      np.stack((d, s * s, f, b), axis=1),
                      np.stack((e, f, s * s, c), axis=1)), axis=1)
    q = cands[np.arange(len(R)), k] / s[:, None]
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 3] < 0] *= -1.0
    return q


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (x, y, z, w)."""
    import pinocchio as pin

    return np.asarray(pin.Quaternion(float(q[3]), float(q[0]), float(q[1]), float(q[2]))
                      .normalized().toRotationMatrix())


@dataclass(frozen=True)
class BoxHold:
    """Geometry of holding a box of ``size`` at its grasps (see the module docstring).

    Attributes:
        size: box size ``(w, d, h)`` in m.
        tilt: inclination about the supporting edge while held (rad).
        grip_height: grip height above the floor in the untilted grasp frame (m).
        grip_spacing: half distance between the two grip points (m).
        grip_offset: grip point distance in front of the held face (m).
    """

    size: tuple[float, float, float]
    tilt: float = DEFAULT_TILT
    grip_height: float = GRIP_HEIGHT
    grip_spacing: float = GRIP_SPACING
    grip_offset: float = GRIP_OFFSET

    def half_extent(self, grasp: int) -> float:
        """Half of the box's extent along the robot's facing direction (m)."""
        return 0.5 * self.size[grasp % 2]

    def edge_half_length(self, grasp: int) -> float:
        """Half-length of the supporting edge (m)."""
        return 0.5 * self.size[(grasp + 1) % 2]

    def T_world_G(self, obj: Pose, grasp: int) -> np.ndarray:
        """Untilted grasp frame for object pose ``obj`` at ``grasp``."""
        h = obj[2] + grasp * 0.5 * math.pi
        r = self.half_extent(grasp)
        return transform(rot_z(h), (obj[0] - r * math.cos(h), obj[1] - r * math.sin(h), 0.0))

    def T_G_box(self, grasp: int, tilt: float) -> np.ndarray:
        """Box centre in the grasp frame for an inclination ``tilt`` (rad; read-only, cached)."""
        return _T_G_box(self, grasp, tilt)

    def _T_G_box(self, grasp: int, tilt: float) -> np.ndarray:
        inner = transform(rot_z(-grasp * 0.5 * math.pi),
                          (self.half_extent(grasp), 0.0, 0.5 * self.size[2]))
        return transform(rot_y(-tilt), (0.0, 0.0, 0.0)) @ inner

    def T_world_box(self, T_world_G: np.ndarray, grasp: int, tilt: float) -> np.ndarray:
        """Box centre pose from an (untilted) grasp frame and inclination."""
        return T_world_G @ self.T_G_box(grasp, tilt)

    def T_G_hands(self, grasp: int) -> tuple[np.ndarray, np.ndarray]:
        """Grip frames ``(left, right)`` in the tilted grasp frame (read-only, cached)."""
        return _T_G_hands(self, grasp)

    def T_world_hands(self, T_world_G: np.ndarray, grasp: int, tilt: float
                      ) -> tuple[np.ndarray, np.ndarray]:
        """Grip frames ``(left, right)`` in the world: grasp frame ``T_world_G``, tilt (rad)."""
        left, right = _T_tilted_hands(self, grasp, tilt)
        return T_world_G @ left, T_world_G @ right

    def _T_G_hands(self, grasp: int) -> tuple[np.ndarray, np.ndarray]:
        zg = min(self.grip_height, self.size[2] - GRIP_TOP)
        yg = min(self.grip_spacing, self.edge_half_length(grasp) - GRIP_EDGE)
        R = rot_y(-0.5 * math.pi)
        return (transform(R, (-self.grip_offset, yg, zg)),
                transform(R, (-self.grip_offset, -yg, zg)))

    def T_box_hands(self, grasp: int) -> tuple[np.ndarray, np.ndarray]:
        """Grip frames ``(left, right)`` in the box frame (constant while held)."""
        inv = np.linalg.inv(self.T_G_box(grasp, 0.0))
        # hands ride in the tilted G, the box too: the relative transform ignores the tilt
        left, right = self.T_G_hands(grasp)
        return inv @ left, inv @ right

    def pivot_corners(self, obj: Pose, grasp: int) -> tuple[np.ndarray, np.ndarray]:
        """World positions (3-D, on the floor) of the supporting edge's ends (left, right)."""
        T = self.T_world_G(obj, grasp)
        ell = self.edge_half_length(grasp)
        return (T[:3, :3] @ np.array([0.0, ell, 0.0]) + T[:3, 3],
                T[:3, :3] @ np.array([0.0, -ell, 0.0]) + T[:3, 3])

    def box_corners(self, T_world_box: np.ndarray) -> np.ndarray:
        """The 8 corners (8 x 3) of the box at pose ``T_world_box``."""
        h = 0.5 * np.asarray(self.size)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        return (T_world_box[:3, :3] @ (signs * h).T).T + T_world_box[:3, 3]


def _read_only(T: np.ndarray) -> np.ndarray:
    T.flags.writeable = False
    return T


@functools.lru_cache(maxsize=512)
def _T_G_box(hold: BoxHold, grasp: int, tilt: float) -> np.ndarray:
    """:meth:`BoxHold.T_G_box`, computed once per (hold, grasp, tilt): it runs every tick."""
    return _read_only(hold._T_G_box(grasp, tilt))


@functools.lru_cache(maxsize=512)
def _T_tilted_hands(hold: BoxHold, grasp: int, tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """The grip frames in the untilted grasp frame at ``tilt``, once per (hold, grasp, tilt)."""
    Tt = transform(rot_y(-tilt), (0.0, 0.0, 0.0))
    left, right = hold.T_G_hands(grasp)
    return _read_only(Tt @ left), _read_only(Tt @ right)


@functools.lru_cache(maxsize=64)
def _T_G_hands(hold: BoxHold, grasp: int) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`BoxHold.T_G_hands`, computed once per (hold, grasp)."""
    left, right = hold._T_G_hands(grasp)
    return _read_only(left), _read_only(right)

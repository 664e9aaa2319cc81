"""Geometry helpers for the viewer: homogeneous transforms and prism meshes (no meshcat calls).

Frames: every transform here is ``T_world_<thing>`` as a 4x4 numpy array, z up, metres.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose, triangulate


def planar(pose: Pose, z: float = 0.0) -> np.ndarray:
    """``T_world_frame`` of a planar pose ``(x, y, yaw)`` lifted to height ``z`` (m)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    t = np.eye(4)
    t[:2, :2] = [[c, -s], [s, c]]
    t[:3, 3] = (pose[0], pose[1], z)
    return t


def translation(x: float, y: float, z: float) -> np.ndarray:
    """A pure translation (m)."""
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def axis_angle(axis: Sequence[float] | np.ndarray, angle: float) -> np.ndarray:
    """Rotation of ``angle`` (rad) about the unit ``axis`` through the origin, as a 4x4."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    return t


def quat_xyzw_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` from quaternions ``(..., 4)`` stored x, y, z, w."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    r = np.empty(q.shape[:-1] + (3, 3))
    r[..., 0, 0] = 1 - 2 * (y * y + z * z)
    r[..., 0, 1] = 2 * (x * y - z * w)
    r[..., 0, 2] = 2 * (x * z + y * w)
    r[..., 1, 0] = 2 * (x * y + z * w)
    r[..., 1, 1] = 1 - 2 * (x * x + z * z)
    r[..., 1, 2] = 2 * (y * z - x * w)
    r[..., 2, 0] = 2 * (x * z - y * w)
    r[..., 2, 1] = 2 * (y * z + x * w)
    r[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return r


def box_transform(model: BoxGraspModel, obj: Pose, *, grasp: int | None = None,
                  tilt: float = 0.0) -> np.ndarray:
    """``T_world_box`` of the box's centre for object pose ``obj``.

    With ``grasp`` given and ``tilt`` > 0 (rad), the box is inclined towards the robot of that
    grasp about its supporting edge (the footprint edge nearest the robot), as while pivoting.
    """
    t = planar(obj, 0.5 * model.object_size[2])
    if grasp is None or tilt == 0.0:
        return t
    a = grasp * 0.5 * math.pi
    u = np.array([math.cos(a), math.sin(a), 0.0])  # local direction the robot faces
    half = model.half_extent(grasp)
    edge = -half * u + np.array([0.0, 0.0, -0.5 * model.object_size[2]])  # in the box frame
    axis = np.cross(u, [0.0, 0.0, 1.0])  # top moves towards -u (the robot) for tilt > 0
    return t @ translation(*edge) @ axis_angle(axis, tilt) @ translation(*(-edge))


def prism_mesh(points: Sequence[tuple[float, float]],
               height: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ``(2n, 3)`` and faces of a vertical prism over a simple polygon.

    The prism stands on the floor (z = 0) up to ``height`` (m).
    """
    p = np.asarray(points, dtype=float)
    n = len(p)
    verts = np.vstack([np.c_[p, np.zeros(n)], np.c_[p, np.full(n, height)]])
    tris = triangulate([tuple(q) for q in p])
    faces = [(c, b, a) for a, b, c in tris] + [(a + n, b + n, c + n) for a, b, c in tris]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    return verts, np.asarray(faces, dtype=np.uint32)

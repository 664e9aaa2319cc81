"""Planar rigid-body helpers: poses are ``(x, y, yaw)`` tuples in metres and radians."""

from __future__ import annotations

import math

Pose = tuple[float, float, float]

TWO_PI = 2.0 * math.pi


def wrap_angle(angle: float) -> float:
    """Return ``angle`` wrapped to ``[-pi, pi)`` (radians)."""
    return (angle + math.pi) % TWO_PI - math.pi


def compose(a: Pose, b: Pose) -> Pose:
    """Return ``a * b``: pose ``b`` given in frame ``a``, expressed in the frame of ``a``'s parent."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def rotate_about(pose: Pose, pivot: tuple[float, float], angle: float) -> Pose:
    """Rotate a rigidly attached ``pose`` by ``angle`` (rad, CCW) about the vertical through ``pivot``."""
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = pose[0] - pivot[0], pose[1] - pivot[1]
    return (pivot[0] + c * dx - s * dy, pivot[1] + s * dx + c * dy, pose[2] + angle)


def pose_distance(a: Pose, b: Pose) -> tuple[float, float]:
    """Return (translation distance in m, absolute wrapped yaw difference in rad)."""
    return math.hypot(a[0] - b[0], a[1] - b[1]), abs(wrap_angle(a[2] - b[2]))


def rectangle_corners(pose: Pose, length: float, width: float) -> list[tuple[float, float]]:
    """Corners (CCW) of a ``length`` (along local x) by ``width`` rectangle centred at ``pose``."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    hx, hy = 0.5 * length, 0.5 * width
    out = []
    for lx, ly in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)):
        out.append((pose[0] + c * lx - s * ly, pose[1] + s * lx + c * ly))
    return out

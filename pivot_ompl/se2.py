"""Planar rigid-body helpers: poses are ``(x, y, yaw)`` tuples in metres and radians."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

Pose = tuple[float, float, float]

TWO_PI = 2.0 * math.pi


def wrap_angle(angle: float) -> float:
    """Return ``angle`` wrapped to ``[-pi, pi)`` (radians)."""
    return (angle + math.pi) % TWO_PI - math.pi


def compose(a: Pose, b: Pose) -> Pose:
    """Return ``a * b``: pose ``b`` given in frame ``a``, expressed in ``a``'s parent frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def rotate_about(pose: Pose, pivot: tuple[float, float], angle: float) -> Pose:
    """Rotate a rigidly attached ``pose`` by ``angle`` (rad, CCW).

    The rotation is about the vertical through ``pivot``.
    """
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = pose[0] - pivot[0], pose[1] - pivot[1]
    return (pivot[0] + c * dx - s * dy, pivot[1] + s * dx + c * dy, pose[2] + angle)


def pose_distance(a: Pose, b: Pose) -> tuple[float, float]:
    """Return (translation distance in m, absolute wrapped yaw difference in rad)."""
    return math.hypot(a[0] - b[0], a[1] - b[1]), abs(wrap_angle(a[2] - b[2]))


def place_points(pose: Pose, points: Iterable[tuple[float, float]]
                 ) -> list[tuple[float, float]]:
    """World coordinates of ``points`` given in the frame of ``pose`` (x forward, y left)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return [(pose[0] + c * x - s * y, pose[1] + s * x + c * y) for x, y in points]


def rectangle_corners(pose: Pose, length: float, width: float) -> list[tuple[float, float]]:
    """Corners (CCW) of a ``length`` (along local x) by ``width`` rectangle centred at ``pose``."""
    hx, hy = 0.5 * length, 0.5 * width
    return place_points(pose, ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)))


#: Doubled area (m^2) below which three points are collinear for :func:`triangulate`.
DEGENERATE_AREA2 = 1e-12


def triangulate(points: Sequence[tuple[float, float]]) -> list[tuple[int, int, int]]:
    """Ear-clipping triangulation of a simple polygon (either orientation); CCW vertex indices.

    A degenerate remainder (collinear points, no area) is dropped: ears whose doubled area
    is below :data:`DEGENERATE_AREA2` (m^2, round-off of a rotated collinear triple) are not
    triangles (a flat prism crashes coal's convex hull).
    """
    pts = [(float(p[0]), float(p[1])) for p in points]
    n = len(pts)
    area2 = sum(pts[i][0] * pts[(i + 1) % n][1] - pts[(i + 1) % n][0] * pts[i][1]
                for i in range(n))
    idx = list(range(n)) if area2 > 0 else list(range(n - 1, -1, -1))

    def cross(o: int, a: int, b: int) -> float:
        return ((pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1])
                - (pts[a][1] - pts[o][1]) * (pts[b][0] - pts[o][0]))

    def inside(p: int, a: int, b: int, c: int) -> bool:
        return cross(a, b, p) >= 0 and cross(b, c, p) >= 0 and cross(c, a, p) >= 0

    tris: list[tuple[int, int, int]] = []
    guard = 0
    while len(idx) > 3 and guard < 10 * n * n:
        guard += 1
        for k in range(len(idx)):
            a, b, c = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            if cross(a, b, c) <= DEGENERATE_AREA2:
                continue
            if any(inside(p, a, b, c) for p in idx if p not in (a, b, c)):
                continue
            tris.append((a, b, c))
            idx.pop(k)
            break
        else:
            break  # degenerate remainder (collinear points): drop it
    if len(idx) == 3 and cross(idx[0], idx[1], idx[2]) > DEGENERATE_AREA2:
        tris.append((idx[0], idx[1], idx[2]))
    return tris


#: The 16 headings of the floor lattices: the directions of these integer grid vectors,
#: counter-clockwise from +x (0, 26.6, 45, 63.4, 90 deg, ...), so a step along a heading, or
#: square to it, or against it, ends exactly on a grid position.
GRID_HEADINGS: tuple[tuple[int, int], ...] = (
    (1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1),
    (-1, 0), (-2, -1), (-1, -1), (-1, -2), (0, -1), (1, -2), (1, -1), (2, -1))
#: Yaw of each of :data:`GRID_HEADINGS` (rad).
GRID_HEADING_YAWS: tuple[float, ...] = tuple(math.atan2(v[1], v[0]) for v in GRID_HEADINGS)

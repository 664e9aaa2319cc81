"""Planar rigid-body helpers: poses are ``(x, y, yaw)`` tuples in metres and radians."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence

import numpy as np
import shapely

from pivot_ompl.errors import Interrupted

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


#: Doubled area (m^2) at or below which a triangle of :func:`triangulate` is flat (round-off
#: of a rotated collinear triple): it has no area, but it may be all that is left of a spike
#: of the polygon that is thinner than round-off.
DEGENERATE_AREA2 = 1e-12


def triangulate(points: Sequence[tuple[float, float]], *, flat: bool = False,
                should_stop: Callable[[], bool] | None = None) -> list[tuple[int, int, int]]:
    """Triangles (vertex indices into ``points``) that cover a simple polygon exactly.

    Either orientation; repeated consecutive vertices, collinear runs and very thin parts
    are fine. GEOS's constrained Delaunay triangulation (``shapely``) of the polygon, which
    adds no vertex, so every triangle's corners are points of the polygon (a repeated point is
    named by its first index). Triangles with area are counter-clockwise; flat ones (doubled
    area at most :data:`DEGENERATE_AREA2`) are left out unless ``flat``: without them the
    triangles' union is the polygon up to parts thinner than round-off (their area sums to the
    polygon's), with them every point of the polygon, spikes included, is in a triangle (what
    a collision check needs: a spike 1e-13 m wide still stops the box).
    The triangles of the last :data:`TRIANGULATIONS_KEPT` polygons are kept (collision and
    floor geometry both ask). Linear in practice: 0.15 s for 10 000 points.

    Raises:
        Interrupted: ``should_stop()`` became true (polled between GEOS's validity check,
            its triangulation and the numbering of the corners, each at most 0.06 s at
            10 000 points).
    """
    key = tuple((float(p[0]), float(p[1])) for p in points)
    if key not in _TRIANGULATIONS:
        _TRIANGULATIONS[key] = _triangulated(np.asarray(key, dtype=float), should_stop)
        if len(_TRIANGULATIONS) > TRIANGULATIONS_KEPT:
            del _TRIANGULATIONS[next(iter(_TRIANGULATIONS))]
    tris, flats = _TRIANGULATIONS[key]
    return [*tris, *flats] if flat else list(tris)


#: Polygons whose triangles :func:`triangulate` keeps.
TRIANGULATIONS_KEPT = 64
_TRIANGULATIONS: dict[tuple[tuple[float, float], ...],
                      tuple[list[tuple[int, int, int]], list[tuple[int, int, int]]]] = {}


def _triangulated(pts: np.ndarray, should_stop: Callable[[], bool] | None
                  ) -> tuple[list[tuple[int, int, int]], list[tuple[int, int, int]]]:
    """(Triangles with area, counter-clockwise; flat triangles) of :func:`triangulate`."""
    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("triangulating a polygon")

    poly = shapely.Polygon(pts)
    if not poly.is_valid:
        poly = shapely.make_valid(poly)
    poll()
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(poly))
    poll()
    if len(tris) == 0:
        return [], []
    corners = shapely.get_coordinates(shapely.get_exterior_ring(tris)).reshape(-1, 4, 2)[:, :3]
    ids = _first_indices(pts, corners.reshape(-1, 2)).reshape(-1, 3)
    a, b, c = (pts[ids[:, k]] for k in range(3))
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    is_flat = np.abs(area2) <= DEGENERATE_AREA2
    ccw = np.where((area2 < 0)[:, None], ids[:, [0, 2, 1]], ids)
    return ([tuple(map(int, t)) for t in ccw[~is_flat]],  # type: ignore[misc]
            [tuple(map(int, t)) for t in ids[is_flat]])  # type: ignore[misc]


def _first_indices(pts: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """For each row of ``xy``, the first index of that point in ``pts``.

    The nearest point when none is equal (a corner moved by ``make_valid``).
    """
    keys = np.ascontiguousarray(pts).view([("x", float), ("y", float)]).ravel()
    unique, first = np.unique(keys, return_index=True)
    wanted = np.ascontiguousarray(xy, dtype=float).view(keys.dtype).ravel()
    at = np.minimum(np.searchsorted(unique, wanted), len(unique) - 1)
    out = first[at]
    for j in np.flatnonzero(unique[at] != wanted):
        out[j] = int(np.argmin(np.hypot(*(pts - xy[j]).T)))
    return out


#: The 16 headings of the floor lattices: the directions of these integer grid vectors,
#: counter-clockwise from +x (0, 26.6, 45, 63.4, 90 deg, ...), so a step along a heading, or
#: square to it, or against it, ends exactly on a grid position.
GRID_HEADINGS: tuple[tuple[int, int], ...] = (
    (1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1),
    (-1, 0), (-2, -1), (-1, -1), (-1, -2), (0, -1), (1, -2), (1, -1), (2, -1))
#: Yaw of each of :data:`GRID_HEADINGS` (rad).
GRID_HEADING_YAWS: tuple[float, ...] = tuple(math.atan2(v[1], v[0]) for v in GRID_HEADINGS)

"""Obstacle footprints on the floor as shapely geometry, and where a body meets them.

Two uses, both relaxations that must never forbid what the exact (coal) checks allow:
the lower bound on regrasps (:mod:`pivot_ompl.validity.regrasp_bound`) and the walking floor
field (:mod:`pivot_ompl.validity.walk_field`). So the pieces are *subsets* of the obstacles
(a cylinder by its inscribed polygon), and a body's forbidden positions are computed exactly
for those pieces (Minkowski sums of convex polygons: convex hulls of vertex differences).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, PolygonObstacle
from pivot_ompl.se2 import rectangle_corners, triangulate

#: Sides of the polygon inscribed in a cylinder obstacle (a subset of it).
CIRCLE_SIDES = 24


def _inscribed_polygon(cylinder: CylinderObstacle, sides: int) -> np.ndarray:
    """Vertices (sides x 2) of the regular polygon inscribed in a cylinder's footprint."""
    a = np.linspace(0.0, 2 * math.pi, sides, endpoint=False)
    return np.column_stack([cylinder.center[0] + cylinder.radius * np.cos(a),
                            cylinder.center[1] + cylinder.radius * np.sin(a)])


def obstacle_pieces(obstacles: list[Obstacle] | tuple[Obstacle, ...], *,
                    circle_sides: int = CIRCLE_SIDES) -> list[np.ndarray]:
    """Convex floor pieces (k x 2 vertex arrays), each a subset of an obstacle's footprint."""
    out: list[np.ndarray] = []
    for o in obstacles:
        if isinstance(o, BoxObstacle):
            out.append(np.array(rectangle_corners((*o.center, o.yaw), *o.size)))
        elif isinstance(o, CylinderObstacle):
            out.append(_inscribed_polygon(o, circle_sides))
        elif isinstance(o, PolygonObstacle):
            pts = np.asarray(o.points, dtype=float)
            out.extend(pts[list(tri)] for tri in triangulate(o.points))
    return out


def obstacle_footprint(obstacle: Obstacle, *, circle_sides: int = CIRCLE_SIDES) -> BaseGeometry:
    """The obstacle's whole floor footprint (a cylinder: its inscribed polygon)."""
    if isinstance(obstacle, BoxObstacle):
        return shapely.Polygon(rectangle_corners((*obstacle.center, obstacle.yaw),
                                                 *obstacle.size))
    if isinstance(obstacle, CylinderObstacle):
        return shapely.Polygon(_inscribed_polygon(obstacle, circle_sides))
    return shapely.Polygon(obstacle.points)


def meeting_hulls(pieces: list[np.ndarray], body: np.ndarray) -> list[BaseGeometry]:
    """Per piece, the positions of a reference point at which a convex body meets it.

    ``body``: the body's points (m x 2) relative to the reference point; the body is their
    convex hull. The set is the hull of ``piece - body`` (a Minkowski sum of convex sets).
    """
    if not pieces:
        return []
    diffs = [(k[:, None, :] - body[None, :, :]).reshape(-1, 2) for k in pieces]
    index = np.repeat(np.arange(len(diffs)), [len(d) for d in diffs])
    points = shapely.points(np.concatenate(diffs))
    return list(shapely.convex_hull(shapely.multipoints(points, indices=index)))


def grid_inside(hull: BaseGeometry, xs: np.ndarray,
                ys: np.ndarray) -> tuple[slice, slice, np.ndarray]:
    """The points of the grid ``xs`` x ``ys`` strictly inside a convex polygon.

    ``xs``, ``ys``: increasing coordinates. Returns the index ranges of the grid points inside
    the polygon's bounding box and their mask (``True`` inside), as ``shapely.contains_xy``
    would give, from the polygon's edges taken as the lines bounding each grid column from
    below and above (the grid is rasterised one column at a time, not point by point).
    """
    if hull.geom_type != "Polygon" or hull.is_empty:
        return slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=bool)
    x0, y0, x1, y1 = hull.bounds
    i0, i1 = np.searchsorted(xs, x0, side="right"), np.searchsorted(xs, x1, side="left")
    j0, j1 = np.searchsorted(ys, y0, side="right"), np.searchsorted(ys, y1, side="left")
    cols, rows = slice(int(i0), int(max(i0, i1))), slice(int(j0), int(max(j0, j1)))
    ring = shapely.get_coordinates(hull.exterior)
    p, q = ring[:-1], ring[1:]
    if np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]) < 0.0:  # clockwise: the inside is right
        p, q = q, p
    d = q - p
    x = xs[cols][:, None]
    lo = np.full(x.shape[0], -np.inf)
    hi = np.full(x.shape[0], np.inf)
    # an edge running right bounds the inside from below, one running left from above; the
    # vertical ones lie at the bounding box's sides, outside the columns taken
    for sel, out, reduce in ((d[:, 0] > 1e-12, lo, np.max), (d[:, 0] < -1e-12, hi, np.min)):
        if np.any(sel):
            ps, ds = p[sel], d[sel]
            y = ps[:, 1] + ds[:, 1] / ds[:, 0] * (x - ps[:, 0])
            out[:] = reduce(y, axis=1)
    y = ys[rows][None, :]
    return cols, rows, (y > lo[:, None]) & (y < hi[:, None])

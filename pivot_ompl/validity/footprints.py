"""Obstacle footprints on the floor as shapely geometry, and where a body meets them.

Two uses, both relaxations that must never forbid what the exact (coal) checks allow:
the lower bound on regrasps (:mod:`pivot_ompl.analysis.regrasp_bound`) and the walking floor
field (:mod:`pivot_ompl.transit.floor_grid`). So the pieces are *subsets* of the obstacles
(a cylinder by its inscribed polygon), and a body's forbidden positions are computed exactly
for those pieces (Minkowski sums of convex polygons: convex hulls of vertex differences).

Two routes give the same hulls: shapely geometry (:func:`meeting_hulls`, rasterised one at a
time by :func:`~pivot_ompl.validity.rasters.grid_inside`), and numpy for many (piece, body)
pairs at once (:func:`~pivot_ompl.validity.minkowski.meeting_edges`: certified to have exactly
GEOS's vertices, GEOS where it cannot be certified; rasterised together by
:func:`~pivot_ompl.validity.rasters.grid_union`, with the same float expressions, so the same
grid points).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

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


def _convex_outlines(obstacles: Sequence[Obstacle], circle_sides: int
                     ) -> dict[int, np.ndarray]:
    """Index -> vertex array of every box (its corners) and cylinder (its inscribed polygon).

    Computed for all of them at once (100 000 obstacles one at a time took 1.3 s).
    """
    out: dict[int, np.ndarray] = {}
    boxes = [(i, o) for i, o in enumerate(obstacles) if isinstance(o, BoxObstacle)]
    if boxes:
        p = np.array([(*o.center, o.yaw, *o.size) for _, o in boxes], dtype=float)
        c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
        hx, hy = 0.5 * p[:, 3], 0.5 * p[:, 4]
        lx = np.stack([hx, -hx, -hx, hx], axis=1)  # the order of se2.rectangle_corners
        ly = np.stack([hy, hy, -hy, -hy], axis=1)
        xy = np.stack([p[:, :1] + c[:, None] * lx - s[:, None] * ly,
                       p[:, 1:2] + s[:, None] * lx + c[:, None] * ly], axis=2)
        out.update((i, xy[k]) for k, (i, _) in enumerate(boxes))
    cyls = [(i, o) for i, o in enumerate(obstacles) if isinstance(o, CylinderObstacle)]
    if cyls:
        p = np.array([(*o.center, o.radius) for _, o in cyls], dtype=float)
        a = np.linspace(0.0, 2 * math.pi, circle_sides, endpoint=False)
        xy = np.stack([p[:, :1] + p[:, 2:3] * np.cos(a), p[:, 1:2] + p[:, 2:3] * np.sin(a)],
                      axis=2)
        out.update((i, xy[k]) for k, (i, _) in enumerate(cyls))
    return out


def obstacle_pieces(obstacles: list[Obstacle] | tuple[Obstacle, ...], *,
                    circle_sides: int = CIRCLE_SIDES) -> list[np.ndarray]:
    """Convex floor pieces (k x 2 vertex arrays), each a subset of an obstacle's footprint."""
    convex = _convex_outlines(obstacles, circle_sides)
    out: list[np.ndarray] = []
    for i, o in enumerate(obstacles):
        if isinstance(o, PolygonObstacle):
            pts = np.asarray(o.points, dtype=float)
            out.extend(pts[list(tri)] for tri in triangulate(o.points))
        else:
            out.append(convex[i])
    return out


def _by_size(pieces: list[np.ndarray]) -> dict[int, np.ndarray]:
    """The indices of ``pieces`` grouped by vertex count."""
    counts = np.fromiter(map(len, pieces), dtype=np.int64, count=len(pieces))
    return {int(k): np.flatnonzero(counts == k) for k in np.unique(counts)}


def piece_polygons(pieces: list[np.ndarray]) -> np.ndarray:
    """Each piece as a shapely polygon (an object array), built a vertex count at a time.

    The polygons ``shapely.Polygon`` makes of each piece, in a few calls for a building's
    thousands of wall boxes.
    """
    out = np.empty(len(pieces), dtype=object)
    for k, idx in _by_size(pieces).items():
        out[idx] = shapely.polygons(np.stack([pieces[i] for i in idx.tolist()]).reshape(-1, k, 2))
    return out


def piece_bounds(pieces: list[np.ndarray]) -> np.ndarray:
    """Each piece's bounding box ``(n, 4)``: ``x0, y0, x1, y1`` (m).

    Stacked by vertex count (a building's thousands of wall boxes in a few numpy calls).
    """
    out = np.zeros((len(pieces), 4))
    for k, idx in _by_size(pieces).items():
        stack = np.stack([pieces[i] for i in idx.tolist()]).reshape(-1, k, 2)
        out[idx, :2], out[idx, 2:] = stack.min(axis=1), stack.max(axis=1)
    return out


def symmetric_centres(pieces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Each piece's vertex mean ``(n, 2)``, and whether the piece is its reflection about it.

    A piece whose vertices, reflected about their mean, are its vertices again (within
    1e-9 of its size) is centrally symmetric about that point (a rectangle, a wall box).
    Stacked by vertex count: each piece's means and gaps are its own floats.
    """
    centres = np.zeros((len(pieces), 2))
    symmetric = np.zeros(len(pieces), dtype=bool)
    for k, idx in _by_size(pieces).items():
        stack = np.stack([pieces[i] for i in idx.tolist()]).reshape(-1, k, 2)
        c = stack.mean(axis=1)
        gap = np.abs((2.0 * c[:, None, :] - stack)[:, :, None, :] - stack[:, None, :, :]
                     ).max(axis=3).min(axis=2)
        size = np.maximum(1.0, np.abs(stack - c[:, None, :]).max(axis=(1, 2)))
        centres[idx] = c
        symmetric[idx] = gap.max(axis=1) <= 1e-9 * size
    return centres, symmetric


def obstacle_footprint(obstacle: Obstacle, *, circle_sides: int = CIRCLE_SIDES) -> BaseGeometry:
    """The obstacle's whole floor footprint (a cylinder: its inscribed polygon)."""
    if isinstance(obstacle, BoxObstacle):
        return shapely.Polygon(rectangle_corners((*obstacle.center, obstacle.yaw),
                                                 *obstacle.size))
    if isinstance(obstacle, CylinderObstacle):
        return shapely.Polygon(_inscribed_polygon(obstacle, circle_sides))
    return shapely.Polygon(obstacle.points)


def obstacle_footprints(obstacles: Sequence[Obstacle], *, circle_sides: int = CIRCLE_SIDES
                        ) -> list[BaseGeometry]:
    """:func:`obstacle_footprint` of every obstacle, boxes and cylinders built at once."""
    convex = _convex_outlines(obstacles, circle_sides)
    built: dict[int, BaseGeometry] = {i: shapely.Polygon(o.points)
                                      for i, o in enumerate(obstacles)
                                      if isinstance(o, PolygonObstacle)}
    for n in {len(v) for v in convex.values()}:
        idx = [i for i, v in convex.items() if len(v) == n]
        polys = shapely.polygons(np.stack([convex[i] for i in idx]))
        built.update(zip(idx, polys, strict=True))
    return [built[i] for i in range(len(obstacles))]


#: Polygons with more points than this are not grown by :func:`disk_clear` (GEOS took 5.8 s to
#: buffer a jagged 10 000-point polygon): the set stays a superset.
GROW_MAX_POINTS = 256


def disk_clear(bounds: tuple[float, float, float, float], obstacles: Sequence[Obstacle], *,
               radius: float, clearance: float) -> BaseGeometry:
    """Centres of a disk of ``radius`` inside ``bounds`` and ``clearance`` from ``obstacles``.

    A superset of the true set: the obstacles' footprints (cylinders as inscribed polygons)
    are grown by the polygon of chords of the round offset, which lies inside it; polygons of
    more than :data:`GROW_MAX_POINTS` points are not grown at all.
    """
    x0, y0, x1, y1 = bounds
    free: BaseGeometry = shapely.box(x0 + radius, y0 + radius, x1 - radius, y1 - radius)
    if not obstacles:
        return free
    shapes = np.array(obstacle_footprints(obstacles), dtype=object)
    large = np.array([isinstance(o, PolygonObstacle) and len(o.points) > GROW_MAX_POINTS
                      for o in obstacles])
    grown = shapes.copy()
    grown[~large] = shapely.buffer(shapes[~large], radius + clearance, quad_segs=4)
    return free.difference(shapely.union_all(grown))


def region_vertices(obstacles: Sequence[Obstacle], *, circle_sides: int = CIRCLE_SIDES) -> int:
    """The vertices of :func:`disk_clear`'s grown footprints (a measure of its cost)."""
    return sum(4 if isinstance(o, BoxObstacle) else circle_sides
               if isinstance(o, CylinderObstacle) else min(len(o.points), GROW_MAX_POINTS)
               for o in obstacles)


def meeting_hulls(pieces: list[np.ndarray], body: np.ndarray) -> list[BaseGeometry]:
    """Per piece, the positions of a reference point at which a convex body meets it.

    ``body``: the body's points (m x 2) relative to the reference point; the body is their
    convex hull. The set is the hull of ``piece - body`` (a Minkowski sum of convex sets).
    """
    return pair_hulls(pieces, [body] * len(pieces))


def pair_hulls(pieces: list[np.ndarray], bodies: list[np.ndarray]) -> list[BaseGeometry]:
    """:func:`meeting_hulls` of each ``(pieces[i], bodies[i])`` pair, all in one GEOS call."""
    if not pieces:
        return []
    diffs = [(k[:, None, :] - b[None, :, :]).reshape(-1, 2)
             for k, b in zip(pieces, bodies, strict=True)]
    index = np.repeat(np.arange(len(diffs)), [len(d) for d in diffs])
    points = shapely.points(np.concatenate(diffs))
    return list(shapely.convex_hull(shapely.multipoints(points, indices=index)))

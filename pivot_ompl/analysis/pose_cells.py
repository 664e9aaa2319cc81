"""Where the held assembly may stand over a range of yaws: free box positions, certified.

The held assembly at grasp ``k`` is two convex floor bodies (the box's footprint and the
holding robot's outline, :meth:`~pivot_ompl.grasp.BoxGraspModel.held_outline`), both prisms
standing on the floor as the obstacles do, so a pose is valid only where both keep the
checker's clearance from every obstacle's floor piece. For a *yaw bin* ``[a, b]`` this module
gives the box positions at which the assembly may be valid at *some* yaw of the bin
(:func:`free_components`): an over-approximation, never missing a valid pose.

How: every yaw of the bin covers the bin's *core* (:func:`rotation_core`, a convex polygon
inside each body turned by every yaw of the bin); a position at which the core comes within
the clearance of an obstacle piece is invalid at every yaw of the bin. Those positions are the
Minkowski sums ``piece + disk - core`` (:func:`convex_sums`, exact for convex polygons; the
disk inscribed, a hair smaller than the clearance), and the rest of the floor, cut into its
connected parts, is what is returned.

Why the core is inside every turned body: for an edge with outward normal ``n`` at distance
``d`` from the box centre, the normal turned by ``t`` in ``[-h, h]`` is ``a n(-h) + b n(h)``
with ``a, b >= 0`` and ``a + b = cos t / cos h`` (in ``[1, 1 / cos h]``). So a point with
``n(+-h) . x <= d cos h`` (``d >= 0``) or ``<= d`` (``d < 0``) has ``n(t) . x <= d`` for every
``t``: it lies inside the body turned by ``t``.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.grasp import GRASPS, BoxGraspModel
from pivot_ompl.se2 import place_points, rectangle_corners

#: Sides of the polygon inscribed in the clearance's disk added to every obstacle piece.
DISK_SIDES = 16
#: Kept off the clearance (m): round-off never closes a position that is valid.
ROUND_OFF = 1e-5


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex hull's vertices (counter-clockwise, not closed) of a point set."""
    ring = shapely.MultiPoint(points).convex_hull
    return np.asarray(shapely.get_exterior_ring(shapely.orient_polygons(ring)).coords)[:-1]


def held_bodies(model: BoxGraspModel) -> list[list[np.ndarray]]:
    """Per grasp, the assembly's convex bodies in the box's frame: the box, the robot."""
    box = np.array(rectangle_corners((0.0, 0.0, 0.0), model.object_size[0],
                                     model.object_size[1]), dtype=float)
    out = []
    for g in GRASPS:
        robot = np.array(place_points(model.robot_pose((0.0, 0.0, 0.0), g),
                                      model.held_outline(g)), dtype=float)
        out.append([_hull(box), _hull(robot)])
    return out


def _clip(poly: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The convex polygon ``poly`` cut to the half-plane ``normal . x <= offset``."""
    out = []
    k = len(poly)
    for i in range(k):
        a, b = poly[i], poly[(i + 1) % k]
        fa, fb = float(normal @ a) - offset, float(normal @ b) - offset
        if fa <= 0.0:
            out.append(a)
        if fa * fb < 0.0:
            out.append(a + (b - a) * (fa / (fa - fb)))
    return np.array(out).reshape(-1, 2)


def _turn(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def rotation_core(body: np.ndarray, half: float) -> np.ndarray | None:
    """A convex polygon inside ``body`` turned by every angle in ``[-half, half]``.

    ``body``: a convex polygon's vertices (counter-clockwise) about the turning centre;
    ``half`` < pi / 2 (rad). ``None`` when the core found is empty.
    """
    k = len(body)
    poly = body.copy()
    for i in range(k):
        a, b = body[i], body[(i + 1) % k]
        e = b - a
        n = np.array([e[1], -e[0]]) / math.hypot(e[0], e[1])  # outward (counter-clockwise)
        d = float(n @ a)
        offset = d * math.cos(half) if d >= 0.0 else d
        for t in (-half, half):
            poly = _clip(poly, _turn(t) @ n, offset)
            if len(poly) < 3:
                return None
    return poly


def _edges(polys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge vectors ``(..., k, 2)`` of polygons ``(..., k, 2)`` and their angles (rad)."""
    e = np.roll(polys, -1, axis=-2) - polys
    return e, np.arctan2(e[..., 1], e[..., 0])


def convex_sums(pieces: np.ndarray, body: np.ndarray) -> np.ndarray:
    """Vertices ``(n, k + m, 2)`` of each ``pieces[i] + body`` (Minkowski sums, convex).

    ``pieces`` ``(n, k, 2)`` and ``body`` ``(m, 2)``: convex, counter-clockwise. The sum's
    boundary is both polygons' edges in the order of their angles: it starts at the sum of
    the two vertices from which each polygon's edge of least angle leaves, and walks the
    merged edges (an edge of length zero, a repeated vertex, adds a repeated vertex).
    """
    n, k = pieces.shape[:2]
    m = len(body)
    piece_edges, piece_angles = _edges(pieces)
    body_edges, body_angles = _edges(body)
    start = pieces[np.arange(n), np.argmin(piece_angles, axis=1)] + body[np.argmin(body_angles)]
    edges = np.concatenate([piece_edges, np.broadcast_to(body_edges, (n, m, 2))], axis=1)
    order = np.argsort(np.concatenate([piece_angles, np.broadcast_to(body_angles, (n, m))],
                                      axis=1), axis=1, kind="stable")
    walk = np.take_along_axis(edges, order[..., None], axis=1)
    out = np.empty((n, k + m, 2))
    out[:, 0] = start
    np.cumsum(walk[:, :-1], axis=1, out=out[:, 1:])
    out[:, 1:] += start[:, None]
    return out


def grown_pieces(pieces: list[np.ndarray], clearance: float) -> list[np.ndarray]:
    """Each convex piece (counter-clockwise) grown by a polygon inside the clearance's disk.

    The pieces' hulls taken at once, and summed with the disk once per vertex count.
    """
    r = max(clearance - ROUND_OFF, 0.0)
    a = np.linspace(0.0, 2.0 * math.pi, DISK_SIDES, endpoint=False)
    disk = r * np.stack([np.cos(a), np.sin(a)], axis=1)
    if not pieces:
        return []
    points = [np.asarray(p, dtype=float).reshape(-1, 2) for p in pieces]
    which = np.repeat(np.arange(len(points)), [len(p) for p in points])
    hulls = shapely.orient_polygons(shapely.convex_hull(
        shapely.multipoints(np.concatenate(points), indices=which)))
    coords, ring = shapely.get_coordinates(shapely.get_exterior_ring(hulls), return_index=True)
    ends = np.cumsum(np.bincount(ring, minlength=len(points)))
    ccw = np.split(coords, ends[:-1])
    out: list[np.ndarray] = [c[:-1] for c in ccw]  # rings closed: the last vertex repeated
    if r > 0.0:
        sizes = [len(c) for c in out]  # before any is grown (a grown piece has more vertices)
        for k, stack in by_size(out).items():
            at = [i for i, n in enumerate(sizes) if n == k]
            for i, grown in zip(at, convex_sums(stack, disk), strict=True):
                out[i] = grown
    return out


def centre_room(grown: dict[int, np.ndarray], radius: float, area: BaseGeometry,
                xy: tuple[float, float]) -> BaseGeometry | None:
    """The part of ``area`` round ``xy`` where a disk of ``radius`` keeps the clearance.

    The disk inscribed in the box (about its centre) is inside it at every yaw: a box centre
    outside this part's room can never be valid, and the centre moves continuously (a regrasp
    leaves it where it is), so every plan's box centre stays in the start's part. ``None``
    when ``xy`` is in no part.
    """
    a = np.linspace(0.0, 2.0 * math.pi, DISK_SIDES, endpoint=False)
    disk = radius * np.stack([np.cos(a), np.sin(a)], axis=1)
    blocked = [p for stack in grown.values() for p in shapely.polygons(convex_sums(stack, disk))]
    free = area.difference(shapely.union_all(blocked)) if blocked else area
    point = shapely.Point(xy)
    return next((g for g in getattr(free, "geoms", [free]) if g.covers(point)), None)


def near(grown: dict[int, np.ndarray], room: BaseGeometry,
         distance: float) -> dict[int, np.ndarray]:
    """The pieces within ``distance`` of ``room`` (the others cannot meet a body there).

    ``room`` prepared for the test (a large floor's room has thousands of vertices) and left
    as it came.
    """
    out = {}
    prepared = bool(shapely.is_prepared(room))
    shapely.prepare(room)
    for k, stack in grown.items():
        keep = shapely.dwithin(room, shapely.polygons(stack), distance)
        if keep.any():
            out[k] = stack[keep]
    if not prepared:
        shapely.destroy_prepared(room)
    return out


def bound_slabs(bounds: tuple[float, float, float, float], thickness: float) -> list[np.ndarray]:
    """Four slabs just outside the floor's bounds (counter-clockwise), as pieces.

    The bodies must lie inside the bounds but need no clearance from them: the slabs are not
    grown, and start :data:`ROUND_OFF` outside.
    """
    x0, y0, x1, y1 = bounds
    e, t = ROUND_OFF, thickness
    boxes = [(x0 - t, y0 - t, x1 + t, y0 - e), (x0 - t, y1 + e, x1 + t, y1 + t),
             (x0 - t, y0 - t, x0 - e, y1 + t), (x1 + e, y0 - t, x1 + t, y1 + t)]
    return [np.array([(a, b), (c, b), (c, d), (a, d)], dtype=float) for a, b, c, d in boxes]


def free_region(grown: dict[int, np.ndarray], cores: list[np.ndarray | None], yaw: float,
                area: BaseGeometry) -> BaseGeometry:
    """What of ``area`` a box centre may stand on at the bin of ``yaw`` (one geometry).

    ``grown``: the grown obstacle pieces stacked by vertex count; ``cores``: the bodies'
    rotation cores about the bin's middle yaw ``yaw`` (a ``None`` core closes nothing).
    """
    turn = _turn(yaw)
    blocked = []
    for core in cores:
        if core is None:
            continue
        reflected = -(core @ turn.T)  # piece - core: still counter-clockwise (a half turn)
        for stack in grown.values():
            blocked.extend(shapely.polygons(convex_sums(stack, reflected)))
    return area.difference(shapely.union_all(blocked)) if blocked else area


def free_components(grown: dict[int, np.ndarray], cores: list[np.ndarray | None],
                    yaw: float, area: BaseGeometry) -> list[BaseGeometry]:
    """:func:`free_region`'s connected parts."""
    free = free_region(grown, cores, yaw, area)
    return [g for g in getattr(free, "geoms", [free]) if not g.is_empty]


def by_size(pieces: list[np.ndarray]) -> dict[int, np.ndarray]:
    """Pieces stacked by vertex count (one numpy call per count)."""
    out: dict[int, list[np.ndarray]] = {}
    for p in pieces:
        out.setdefault(len(p), []).append(p)
    return {k: np.stack(v) for k, v in out.items()}

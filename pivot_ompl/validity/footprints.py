"""Obstacle footprints on the floor as shapely geometry, and where a body meets them.

Two uses, both relaxations that must never forbid what the exact (coal) checks allow:
the lower bound on regrasps (:mod:`pivot_ompl.analysis.regrasp_bound`) and the walking floor
field (:mod:`pivot_ompl.transit.field`). So the pieces are *subsets* of the obstacles
(a cylinder by its inscribed polygon), and a body's forbidden positions are computed exactly
for those pieces (Minkowski sums of convex polygons: convex hulls of vertex differences).

Two routes give the same hulls: shapely geometry (:func:`meeting_hulls`, rasterised one at a
time by :func:`grid_inside`), and numpy for many (piece, body) pairs at once
(:func:`meeting_edges`: certified to have exactly GEOS's vertices, GEOS where it cannot be
certified; rasterised together by :func:`grid_union`, with the same float expressions, so
the same grid points).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.errors import Interrupted
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


#: Relative error bound of the floating orientation determinant (Shewchuk's ``ccwerrboundA``,
#: (3 + 16 eps) eps, rounded up): a sign beyond it is certain.
_ORIENT_ERR = 4e-16

#: Relative error bound (generous) of a difference's distance left of an edge's line computed
#: as the sum of its piece vertex's and its body vertex's parts.
_SPLIT_ERR = 1e-14


@dataclass(frozen=True)
class EdgeSet:
    """Convex polygons as padded edge arrays, ready for :func:`grid_union`.

    ``start``, ``end``: ``(n, e, 2)``, each polygon's edges counter-clockwise (the same edges
    as the convex hull geometry :func:`meeting_hulls` gives, from the same vertices); ``used``:
    ``(n, e)``, which slots are edges (the others are padding); ``bounds``: ``(n, 4)``
    bounding boxes (``x0, y0, x1, y1``; ``inf, inf, -inf, -inf`` for an empty polygon).
    """

    start: np.ndarray
    end: np.ndarray
    used: np.ndarray
    bounds: np.ndarray


def _ccw(poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Polygons ``(g, k, 2)`` with their vertices counter-clockwise, and which were reversed."""
    x, y = poly[..., 0], poly[..., 1]
    flip = np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1) < 0.0
    return np.where(flip[:, None, None], poly[:, ::-1], poly), flip


def _dots(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``(g, s, k)`` dot products of directions ``u`` ``(g, s, 2)`` and points ``(g, k, 2)``."""
    return u[:, :, None, 0] * v[:, None, :, 0] + u[:, :, None, 1] * v[:, None, :, 1]


def _three_least(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Along the last axis, the indices of the two least values and the three least values.

    By repeated ``argmin`` (faster than sorting many short rows); ``inf`` where fewer.
    """
    v = v.copy()
    idx, least = [], []
    for _ in range(3):
        i = np.argmin(v, axis=-1)[..., None]
        idx.append(i)
        least.append(np.take_along_axis(v, i, axis=-1))
        np.put_along_axis(v, i, np.inf, axis=-1)
    return np.concatenate(idx[:2], axis=-1), np.concatenate(least, axis=-1)


def _after_last(edge: np.ndarray, mine: np.ndarray, count: int) -> np.ndarray:
    """Per slot, the vertex after the last edge (``edge`` where ``mine``) up to it, cyclically."""
    slot = np.broadcast_to(np.arange(edge.shape[1]), edge.shape)
    last = np.maximum.accumulate(np.where(mine, slot, -1), axis=1)
    last = np.where(last < 0, last[:, -1:], last)
    return (np.take_along_axis(edge, last, axis=1) + 1) % count


def _sum_hulls(pieces: np.ndarray, bodies: np.ndarray, *, certify: bool = True
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Hulls of ``piece - body`` per row (``(g, k, 2)``, ``(g, m, 2)`` convex polygons).

    The Minkowski sum's vertices in counter-clockwise order, found from the merged edge
    normals of both polygons (the vertex pair extreme between two consecutive normals), then
    certified against every vertex difference: each is on or left of every edge, each other
    vertex strictly left (certain from the split distances, or else by an exact-sign
    orientation test). So a certified row has exactly the
    vertex set of the exact convex hull of the differences (as GEOS computes it).

    Returns the vertices ``(g, s, 2)`` (a padding slot repeats the next vertex), the next
    slot ``(g, s)``, which slots are vertices ``(g, s)``, and which rows are certified
    ``(g,)``.

    ``certify=False``: no certificate; a row is accepted when both polygons have a vertex
    and no edge shorter than :data:`_SHORT_EDGE` times their extent (the merged normals
    then give the sum's region to rounding, perhaps with a vertex more or less on an edge's
    line than GEOS's hull; a row with a vanishing edge is refused, as an uncertified one).
    """
    cand, pair, nxt, valid, ok = _sum_candidates(pieces, bodies)
    rows = np.arange(pieces.shape[0])[:, None]
    verts = cand[rows, pair]
    if certify:
        ok &= _certified(pieces, bodies, cand, pair, nxt, valid)
    else:
        ok &= ~(_has_short_edge(pieces) | _has_short_edge(bodies))
    return verts, nxt, valid, ok


#: Relative length below which an edge makes :func:`_sum_hulls` without a certificate refuse
#: a row (a near-degenerate polygon, whose edge normals are not reliable).
_SHORT_EDGE = 1e-9


def _has_short_edge(polys: np.ndarray) -> np.ndarray:
    """Per row of ``(g, k, 2)`` polygons: an edge shorter than :data:`_SHORT_EDGE` x extent."""
    e = np.linalg.norm(np.roll(polys, -1, axis=1) - polys, axis=2)
    extent = np.ptp(polys, axis=1).max(axis=1)
    return np.any(e <= _SHORT_EDGE * np.maximum(extent, 1.0)[:, None], axis=1)


def _sum_candidates(pieces: np.ndarray, bodies: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The vertex differences and, per slot of the merged edge normals, the hull's vertex.

    Returns the differences ``(g, k m, 2)``, each slot's vertex pair and next slot, which
    slots are vertices, and which rows have a vertex at all.
    """
    g, k, m = pieces.shape[0], pieces.shape[1], bodies.shape[1]
    cand = (pieces[:, :, None, :] - bodies[:, None, :, :]).reshape(g, k * m, 2)
    (p, pflip), (q, qflip) = _ccw(pieces), _ccw(-bodies)
    normals = []
    for poly in (p, q):
        e = np.roll(poly, -1, axis=1) - poly
        normals.append(np.arctan2(-e[..., 0], e[..., 1]) % (2 * math.pi))
    ang = np.concatenate(normals, axis=1)
    order = np.argsort(ang, axis=1)
    ang = np.take_along_axis(ang, order, axis=1)
    gap = np.diff(ang, axis=1, append=ang[:, :1] + 2 * math.pi)
    # between two consecutive normals, each polygon's extreme vertex is the one after the
    # edge of the last of its normals so far (cyclically)
    ip = _after_last(order, order < k, k)
    iq = _after_last(order - k, order >= k, m)
    # the vertex as one of the differences (same floats): p's vertex minus the body's
    pidx = np.where(pflip[:, None], k - 1 - ip, ip)
    qidx = np.where(qflip[:, None], m - 1 - iq, iq)
    pair = pidx * m + qidx
    valid = gap > 1e-12
    s = ang.shape[1]
    slot = np.arange(s)
    big = np.where(valid, slot[None, :], 2 * s)
    after = np.minimum.accumulate(big[:, ::-1], axis=1)[:, ::-1]
    nxt = np.concatenate([after[:, 1:], np.full((g, 1), 2 * s)], axis=1)
    nxt = np.where(nxt >= s, after[:, :1], nxt)
    ok = np.any(valid, axis=1)
    nxt = np.where(ok[:, None], nxt, 0)
    pair = np.where(valid, pair, np.take_along_axis(pair, nxt, axis=1))
    return cand, pair, nxt, valid, ok


def _certified(pieces: np.ndarray, bodies: np.ndarray, cand: np.ndarray, pair: np.ndarray,
               nxt: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per row: every difference on or left of every edge, the others strictly left."""
    g, k, m = pieces.shape[0], pieces.shape[1], bodies.shape[1]
    s = pair.shape[1]
    rows = np.arange(g)[:, None]
    verts = cand[rows, pair]
    a, b = verts, verts[rows, nxt]
    bpair = np.take_along_axis(pair, nxt, axis=1)
    is_vertex = np.zeros((g, k * m), dtype=bool)
    is_vertex[np.broadcast_to(rows, pair.shape)[valid], pair[valid]] = True
    # per edge a -> b, a difference's distance left of its line, split as the piece
    # vertex's part plus the body vertex's part (floats: certain beyond a bound ``tol``)
    e = b - a
    normal = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    dp = _dots(normal, pieces)
    dq = -_dots(normal, bodies)
    gp = dp - np.take_along_axis(dp, (pair // m)[..., None], axis=2)
    gq = dq - np.take_along_axis(dq, (pair % m)[..., None], axis=2)
    scale = np.abs(pieces).max(axis=(1, 2)) + np.abs(bodies).max(axis=(1, 2)) \
        + np.abs(cand).max(axis=(1, 2))
    tol = _SPLIT_ERR * np.abs(e).sum(axis=-1) * scale[:, None]
    ip, sp = _three_least(gp)
    iq, sq = _three_least(gq)
    # every difference but those of the two nearest piece and body vertices is strictly
    # left; those (at most 4 per edge) are tested with exact-sign orientations
    far = (sp[..., 2] + sq[..., 0] > tol) & (sq[..., 2] + sp[..., 0] > tol)
    near = (ip[..., :, None] * m + iq[..., None, :]).reshape(g, s, -1)
    split = (np.take_along_axis(gp, ip, axis=2)[..., :, None]
             + np.take_along_axis(gq, iq, axis=2)[..., None, :]).reshape(g, s, -1)
    c = cand[rows[..., None], near]
    left = (a[:, :, None, 0] - c[..., 0]) * (b[:, :, None, 1] - c[..., 1])
    right = (a[:, :, None, 1] - c[..., 1]) * (b[:, :, None, 0] - c[..., 0])
    det = left - right
    err = _ORIENT_ERR * (np.abs(left) + np.abs(right))
    sure = (np.abs(det) > err) | (err == 0.0)
    ends = (near == pair[..., None]) | (near == bpair[..., None])
    strict = np.take_along_axis(is_vertex, near.reshape(g, -1), axis=1).reshape(near.shape)
    good = (split > tol[..., None]) | ends \
        | (sure & np.where(strict, det > 0.0, det >= 0.0))
    return np.all((far & np.all(good, axis=2)) | ~valid, axis=1)


def _edges_of(verts: np.ndarray, nxt: np.ndarray, used: np.ndarray) -> EdgeSet:
    """The :class:`EdgeSet` of counter-clockwise vertex slots (padding repeats a vertex)."""
    end = np.take_along_axis(verts, nxt[..., None], axis=1)
    lo, hi = verts.min(axis=1), verts.max(axis=1)
    return EdgeSet(verts, end, used, np.concatenate([lo, hi], axis=1))


def _geos_edges(hulls: list[BaseGeometry]) -> EdgeSet:
    """The :class:`EdgeSet` of convex hull geometries (non-polygons: empty)."""
    rings = [shapely.get_coordinates(h.exterior) if h.geom_type == "Polygon" and not h.is_empty
             else np.zeros((0, 2)) for h in hulls]
    e = max([1, *(len(r) - 1 for r in rings)])
    start = np.zeros((len(rings), e, 2))
    end = np.zeros((len(rings), e, 2))
    used = np.zeros((len(rings), e), dtype=bool)
    bounds = np.tile([np.inf, np.inf, -np.inf, -np.inf], (len(rings), 1))
    for i, ring in enumerate(rings):
        if len(ring) == 0:
            continue
        p, q = ring[:-1], ring[1:]
        if np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]) < 0.0:  # clockwise
            p, q = q, p
        n = len(p)
        start[i, :n], end[i, :n], used[i, :n] = p, q, True
        bounds[i] = hulls[i].bounds
    return EdgeSet(start, end, used, bounds)


#: (piece, body) pairs :func:`meeting_edges` sums between two polls of its ``should_stop``
#: (about 40 ms of work with the walking body's 20 vertices).
MEETING_BATCH = 512


def meeting_edges(pieces: list[np.ndarray], bodies: list[np.ndarray], *,
                  should_stop: Callable[[], bool] | None = None,
                  certify: bool = True) -> EdgeSet:
    """:func:`meeting_hulls` as edges, for many (piece, body) pairs at once (vectorised).

    ``pieces[i]`` meets ``bodies[i]`` (each a convex polygon's vertices, ``body`` relative to
    the reference point). The same polygons as the convex hulls of ``piece - body`` (exactly:
    the same vertices, see :func:`_sum_hulls`; a pair whose hull cannot be certified, e.g.
    with differences on an edge's line, falls back to the convex hull geometry). Linear in
    the pairs, summed :data:`MEETING_BATCH` at a time. ``certify=False``: the sums without
    their certificate (:func:`_sum_hulls`; about three times cheaper), the same regions to
    rounding, for rasters that guide rather than certify.

    Raises:
        Interrupted: ``should_stop()`` became true (polled before every batch).
    """
    n = len(pieces)
    if n == 0:
        return EdgeSet(np.zeros((0, 1, 2)), np.zeros((0, 1, 2)), np.zeros((0, 1), dtype=bool),
                       np.zeros((0, 4)))
    groups: dict[tuple[int, int], list[int]] = {}
    for i in range(n):
        groups.setdefault((len(pieces[i]), len(bodies[i])), []).append(i)
    batches = [idx[b0:b0 + MEETING_BATCH] for idx in groups.values()
               for b0 in range(0, len(idx), MEETING_BATCH)]
    parts: list[tuple[list[int], EdgeSet]] = []
    failed: list[int] = []
    for idx in batches:
        if should_stop is not None and should_stop():
            raise Interrupted("summing obstacle pieces and bodies")
        verts, nxt, used, ok = _sum_hulls(np.stack([pieces[i] for i in idx]),
                                          np.stack([bodies[i] for i in idx]), certify=certify)
        good = np.flatnonzero(ok)
        if len(good):
            parts.append(([idx[i] for i in good], _edges_of(verts[good], nxt[good], used[good])))
        failed.extend(idx[i] for i in np.flatnonzero(~ok))
    hulls: list[BaseGeometry] = []
    for f0 in range(0, len(failed), MEETING_BATCH):  # GEOS, one pair at a time
        if should_stop is not None and should_stop():
            raise Interrupted("summing obstacle pieces and bodies")
        hulls.extend(meeting_hulls([pieces[i]], bodies[i])[0]
                     for i in failed[f0:f0 + MEETING_BATCH])
    if failed:
        parts.append((failed, _geos_edges(hulls)))
    e = max(part.start.shape[1] for _, part in parts)
    start, end = np.zeros((n, e, 2)), np.zeros((n, e, 2))
    used, bounds = np.zeros((n, e), dtype=bool), np.zeros((n, 4))
    for idx, part in parts:
        w = part.start.shape[1]
        start[idx, :w], end[idx, :w] = part.start, part.end
        used[idx, :w], bounds[idx] = part.used, part.bounds
    return EdgeSet(start, end, used, bounds)


def _bound(p: np.ndarray, slope: np.ndarray, sel: np.ndarray, poly: np.ndarray,
           x: np.ndarray, reduce: np.ufunc, empty: float) -> np.ndarray:
    """Per (polygon ``poly``, column ``x``) pair, ``reduce`` of its edges' lines (``sel``).

    The line of edge ``p``, ``slope`` at ``x`` is ``p_y + slope * (x - p_x)`` (evaluated as
    :func:`grid_inside` does). The selected edges are moved to the front of each polygon's
    row first (so the arrays are only as wide as the most edges one polygon has on that
    side), the others made lines constant at ``empty``.
    """
    order = np.argsort(~sel, axis=1, kind="stable")[:, :max(1, int(sel.sum(axis=1).max()))]
    use = np.take_along_axis(sel, order, axis=1)
    px = np.where(use, np.take_along_axis(p[..., 0], order, axis=1), 0.0)[poly]
    py = np.where(use, np.take_along_axis(p[..., 1], order, axis=1), empty)[poly]
    k = np.where(use, np.take_along_axis(slope, order, axis=1), 0.0)[poly]
    y = np.subtract(x[:, None], px, out=px)
    np.multiply(k, y, out=y)
    np.add(py, y, out=y)
    return reduce.reduce(y, axis=1)


def grid_union(edges: EdgeSet, xs: np.ndarray, ys: np.ndarray,
               groups: np.ndarray | None = None, n_groups: int = 1) -> np.ndarray:
    """The grid points strictly inside any of the polygons, per group of polygons.

    The same test as :func:`grid_inside` (each polygon's column intervals from its edges,
    the grid points strictly inside its bounding box), for all polygons at once: per polygon
    and column of its bounding box the interval of rows inside. ``groups``: each polygon's
    group (default all in group 0). Returns ``(n_groups, len(xs), len(ys))``.
    """
    nx, ny = len(xs), len(ys)
    n = edges.start.shape[0]
    groups = np.zeros(n, dtype=np.int64) if groups is None else np.asarray(groups)
    if n == 0:
        return np.zeros((n_groups, nx, ny), dtype=bool)
    p, d = edges.start, edges.end - edges.start
    lower = edges.used & (d[..., 0] > 1e-12)  # runs right: bounds the inside from below
    upper = edges.used & (d[..., 0] < -1e-12)
    slope = np.divide(d[..., 1], d[..., 0], out=np.zeros(d.shape[:2]), where=lower | upper)
    x0, y0, x1, y1 = (edges.bounds[:, i] for i in range(4))
    c0 = np.searchsorted(xs, x0, side="right")  # the columns strictly inside the box
    c1 = np.maximum(c0, np.searchsorted(xs, x1, side="left"))
    width = c1 - c0
    poly = np.repeat(np.arange(n), width)  # the (polygon, column) pairs of the boxes
    cols = c0[poly] + np.arange(len(poly)) - np.repeat(np.cumsum(width) - width, width)
    x = xs[cols]
    lo = np.maximum(_bound(p, slope, lower, poly, x, np.maximum, -np.inf), y0[poly])
    hi = np.minimum(_bound(p, slope, upper, poly, x, np.minimum, np.inf), y1[poly])
    first = np.searchsorted(ys, lo, side="right")
    stop = np.searchsorted(ys, hi, side="left")
    keep = first < stop
    key = (groups[poly] * nx + cols)[keep]
    if 2 * len(key) > n_groups * nx:  # many pairs per column: a difference array
        size = n_groups * nx * (ny + 1)
        base = key * (ny + 1)
        marks = np.bincount(base + first[keep], minlength=size) \
            - np.bincount(base + stop[keep], minlength=size)
        return np.cumsum(marks.reshape(n_groups, nx, ny + 1), axis=2)[:, :, :ny] > 0
    rows = np.arange(ny)  # few: their rows, or-ed per (group, column) run of the sorted pairs
    inside = (rows >= first[keep, None]) & (rows < stop[keep, None])
    out = np.zeros((n_groups * nx, ny), dtype=bool)
    if len(key):
        order = np.argsort(key, kind="stable")
        key = key[order]
        runs = np.flatnonzero(np.diff(key, prepend=-1))
        out[key[runs]] = np.logical_or.reduceat(inside[order], runs, axis=0)
    return out.reshape(n_groups, nx, ny)

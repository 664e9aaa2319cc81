"""Where convex bodies meet convex pieces, for many pairs at once: vectorised Minkowski sums.

:func:`meeting_edges` gives, per (piece, body) pair, the convex hull of ``piece - body`` (the
positions of the body's reference point at which it meets the piece) as padded edge arrays
(:class:`EdgeSet`, rasterised by :func:`~pivot_ompl.validity.rasters.grid_union`). The hulls
are certified to have exactly the vertices GEOS gives
(:func:`~pivot_ompl.validity.footprints.meeting_hulls`, the shapely route); a pair that cannot
be certified falls back to GEOS.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.errors import Interrupted
from pivot_ompl.validity.footprints import pair_hulls
from pivot_ompl.validity.polygon_terms import DistinctPolygons, PolygonTerms, own_terms

#: (3 + 16 eps) eps, rounded up): a sign beyond it is certain.
_ORIENT_ERR = 4e-16

#: Relative error bound (generous) of a difference's distance left of an edge's line computed
#: as the sum of its piece vertex's and its body vertex's parts.
_SPLIT_ERR = 1e-14


@dataclass(frozen=True)
class EdgeSet:
    """Convex polygons as padded edge arrays, ready for ``grid_union`` (:mod:`.rasters`).

    ``start``, ``end``: ``(n, e, 2)``, each polygon's edges counter-clockwise (the same edges
    as the convex hull geometry :func:`~pivot_ompl.validity.footprints.meeting_hulls` gives,
    from the same vertices); ``used``:
    ``(n, e)``, which slots are edges (the others are padding); ``bounds``: ``(n, 4)``
    bounding boxes (``x0, y0, x1, y1``; ``inf, inf, -inf, -inf`` for an empty polygon).
    """

    start: np.ndarray
    end: np.ndarray
    used: np.ndarray
    bounds: np.ndarray


def reflected_bounds(bounds: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Bounding boxes ``(n, 4)`` of polygons reflected through their ``centres`` (``(n, 2)``).

    The box ``x0, y0, x1, y1`` of a polygon point-reflected about ``c`` is ``2 c - (x1, y1)``
    to ``2 c - (x0, y0)``; an empty polygon's (``inf, inf, -inf, -inf``) stays as it is.
    """
    cx, cy = 2.0 * centres[:, 0], 2.0 * centres[:, 1]
    out = np.column_stack([cx - bounds[:, 2], cy - bounds[:, 3],
                           cx - bounds[:, 0], cy - bounds[:, 1]])
    empty = ~np.isfinite(bounds[:, 0])
    out[empty] = bounds[empty]
    return out


def _dots(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``(g, s, k)`` dot products of directions ``u`` ``(g, s, 2)`` and points ``(g, k, 2)``.

    ``u_x v_x + u_y v_y``, in place into one array (no temporaries but one).
    """
    out = np.multiply(u[:, :, None, 0], v[:, None, :, 0])
    out += np.multiply(u[:, :, None, 1], v[:, None, :, 1])
    return out


def _three_least(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Along the last axis, the indices of the two least values and the three least values.

    The values from one partition (the third least in its place, the two least before it);
    the first index the first least value's (``argmin``), the second the first other index
    holding the second least value: the indices repeated ``argmin`` with the first masked
    would give, ties included. ``inf`` third value where the axis has fewer than three.
    """
    if v.shape[-1] < 3:
        v = np.concatenate([v, np.full((*v.shape[:-1], 3 - v.shape[-1]), np.inf)], axis=-1)
    part = np.partition(v, 2, axis=-1)
    least = np.empty((*v.shape[:-1], 3))
    np.minimum(part[..., 0], part[..., 1], out=least[..., 0])
    np.maximum(part[..., 0], part[..., 1], out=least[..., 1])
    least[..., 2] = part[..., 2]
    idx = np.empty((*v.shape[:-1], 2), dtype=np.intp)
    first = np.argmin(v, axis=-1)
    idx[..., 0] = first
    second = v == least[..., 1:2]
    np.put_along_axis(second, first[..., None], False, axis=-1)
    idx[..., 1] = np.argmax(second, axis=-1)
    return idx, least


def _gather(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``a[i, index[i]]`` per row ``i`` (``(g, n, ...)`` by ``(g, s)``: ``(g, s, ...)``).

    Rows whose sums share their slots (a class of wall boxes) share ``index``: one row of
    indices taken from every row at once then (the same values, a fraction of the time).
    """
    if len(index) and bool((index == index[0]).all()):
        return a[:, index[0]]
    return a[np.arange(len(index))[:, None], index]


def _gather_last(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``a[i, j, index[i, j]]`` kept as ``(g, s, 1)`` (``a``: ``(g, s, n)``), as :func:`_gather`."""
    if len(index) and bool((index == index[0]).all()):
        return a[:, np.arange(index.shape[1]), index[0]][..., None]
    return np.take_along_axis(a, index[..., None], axis=2)


def _after_last(edge: np.ndarray, mine: np.ndarray, count: int) -> np.ndarray:
    """Per slot, the vertex after the last edge (``edge`` where ``mine``) up to it, cyclically."""
    slot = np.broadcast_to(np.arange(edge.shape[1]), edge.shape)
    last = np.maximum.accumulate(np.where(mine, slot, -1), axis=1)
    last = np.where(last < 0, last[:, -1:], last)
    return (np.take_along_axis(edge, last, axis=1) + 1) % count


def _sum_hulls(pieces: np.ndarray, bodies: np.ndarray, *, certify: bool = True,
               terms: tuple[PolygonTerms, PolygonTerms] | None = None,
               classes: np.ndarray | None = None
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
    and no edge shorter than :data:`~pivot_ompl.validity.polygon_terms.SHORT_EDGE` times
    their extent (the merged normals then give the sum's region to rounding, perhaps with a
    vertex more or less on an edge's line than GEOS's hull; a row with a vanishing edge is
    refused, as an uncertified one).

    ``terms``: the pieces' and the bodies' own terms
    (:func:`~pivot_ompl.validity.polygon_terms.own_terms`), computed once
    per distinct polygon by the caller (the same floats as per row); ``classes``: per row,
    equal for rows of equal terms (:func:`_sum_candidates`).
    """
    pt, bt = terms if terms is not None else (own_terms(pieces, reflect=False),
                                              own_terms(bodies, reflect=True))
    cand, pair, nxt, valid, ok = _sum_candidates(pieces, bodies, pt, bt, classes)
    verts = _gather(cand, pair)
    if certify:
        ok &= _certified(pieces, bodies, cand, pair, nxt, valid)
    else:
        ok &= ~(pt.short | bt.short)
    return verts, nxt, valid, ok


def _sum_candidates(pieces: np.ndarray, bodies: np.ndarray, pt: PolygonTerms, bt: PolygonTerms,
                    classes: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The vertex differences and, per slot of the merged edge normals, the hull's vertex.

    ``pt``, ``bt``: the pieces' and the bodies' own terms
    (:func:`~pivot_ompl.validity.polygon_terms.own_terms`). Returns the differences
    ``(g, k m, 2)``, each slot's vertex pair and next slot, which slots are vertices, and
    which rows have a vertex at all. ``classes``: per row, a number equal
    for rows whose terms' orientations and normals are equal (wall boxes of any size and
    place share theirs): the slots depend on those alone (:func:`_slots`), so they are
    computed once per class and gathered (the same integers).
    """
    g, k, m = pieces.shape[0], pieces.shape[1], bodies.shape[1]
    cand = (pieces[:, :, None, :] - bodies[:, None, :, :]).reshape(g, k * m, 2)
    if classes is not None and g > 1:
        if bool((classes == classes[0]).all()):  # one class (the usual batch): no sort
            first, inverse = np.zeros(1, dtype=np.int64), np.zeros(g, dtype=np.int64)
        else:
            _, first, inverse = np.unique(classes, return_index=True, return_inverse=True)
        if len(first) < g:
            slots = _slots(pt.rows(first), bt.rows(first), k, m)
            return (cand, *(a[inverse] for a in slots))
    return (cand, *_slots(pt, bt, k, m))


def _slots(pt: PolygonTerms, bt: PolygonTerms, k: int, m: int
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_sum_candidates`' slots from the terms alone: pair, next slot, valid, ok."""
    g = pt.flipped.shape[0]
    pflip, qflip = pt.flipped, bt.flipped
    ang = np.concatenate([pt.normals, bt.normals], axis=1)
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
    return pair, nxt, valid, ok


def _certified(pieces: np.ndarray, bodies: np.ndarray, cand: np.ndarray, pair: np.ndarray,
               nxt: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Per row: every difference on or left of every edge, the others strictly left."""
    g, k, m = pieces.shape[0], pieces.shape[1], bodies.shape[1]
    s = pair.shape[1]
    rows = np.arange(g)[:, None]
    verts = _gather(cand, pair)
    a, b = verts, _gather(verts, nxt)
    bpair = _gather(pair, nxt)
    # per edge a -> b, a difference's distance left of its line, split as the piece
    # vertex's part plus the body vertex's part (floats: certain beyond a bound ``tol``)
    e = b - a
    normal = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    dp = _dots(normal, pieces)
    dp -= _gather_last(dp, pair // m)
    gp = dp
    # the body's part is minus its dot: (-x) - (-y) is y - x, the same float, one pass less
    dq = _dots(normal, bodies)
    gq = np.subtract(_gather_last(dq, pair % m), dq, out=dq)
    scale = np.abs(pieces).max(axis=(1, 2)) + np.abs(bodies).max(axis=(1, 2)) \
        + np.abs(cand).max(axis=(1, 2))
    tol = _SPLIT_ERR * np.abs(e).sum(axis=-1) * scale[:, None]
    ip, sp = _three_least(gp)
    iq, sq = _three_least(gq)
    # every difference but those of the two nearest piece and body vertices is strictly
    # left; those (at most 4 per edge) are tested with exact-sign orientations
    far = (sp[..., 2] + sq[..., 0] > tol) & (sq[..., 2] + sp[..., 0] > tol)
    near = (ip[..., :, None] * m + iq[..., None, :]).reshape(g, s, -1)
    split = (sp[..., :2, None] + sq[..., None, :2]).reshape(g, s, -1)  # their values
    ends = (near == pair[..., None]) | (near == bpair[..., None])
    good = (split > tol[..., None]) | ends
    # the orientations only where they decide: a near difference not certain by its split,
    # of an edge whose other differences are (elsewhere the answer is known without them)
    gi, si, ni = np.nonzero(~good & (far & valid)[..., None])
    if len(gi):
        at = near[gi, si, ni]
        cx, cy = cand[gi, at, 0], cand[gi, at, 1]
        left = (a[gi, si, 0] - cx) * (b[gi, si, 1] - cy)
        right = (a[gi, si, 1] - cy) * (b[gi, si, 0] - cx)
        det = left - right
        err = _ORIENT_ERR * (np.abs(left) + np.abs(right))
        sure = (np.abs(det) > err) | (err == 0.0)
        is_vertex = np.zeros((g, k * m), dtype=bool)
        is_vertex[np.broadcast_to(rows, pair.shape)[valid], pair[valid]] = True
        strict = is_vertex[gi, at]
        good[gi, si, ni] = sure & np.where(strict, det > 0.0, det >= 0.0)
    return np.all((far & np.all(good, axis=2)) | ~valid, axis=1)


def _edges_of(verts: np.ndarray, nxt: np.ndarray, used: np.ndarray) -> EdgeSet:
    """The :class:`EdgeSet` of counter-clockwise vertex slots (padding repeats a vertex)."""
    end = _gather(verts, nxt)
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
    """``meeting_hulls`` as edges, for many (piece, body) pairs at once (vectorised).

    :func:`~pivot_ompl.validity.footprints.meeting_hulls`, the shapely route, one pair at a
    time.

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
    # a piece and a body are usually each one array passed many times (a body per yaw, a
    # piece per yaw and body): their own terms computed once, the pairs indexed by numpy
    distinct_pieces = DistinctPolygons(pieces, reflect=False)
    distinct_bodies = DistinctPolygons(bodies, reflect=True)
    ks, ms = distinct_pieces.sizes, distinct_bodies.sizes
    order = np.argsort(ks * (int(ms.max()) + 1) + ms, kind="stable")  # by (k, m), in order
    starts = np.flatnonzero(np.diff(ks[order] * (int(ms.max()) + 1) + ms[order],
                                    prepend=-1))
    batches = [sub for g0, g1 in zip(starts.tolist(), [*starts[1:].tolist(), n], strict=True)
               for sub in np.split(order[g0:g1], range(MEETING_BATCH, g1 - g0, MEETING_BATCH))]
    parts: list[tuple[np.ndarray, EdgeSet]] = []
    failed: list[np.ndarray] = []
    for idx in batches:
        if should_stop is not None and should_stop():
            raise Interrupted("summing obstacle pieces and bodies")
        p, pt, pc = distinct_pieces.rows(idx, int(ks[idx[0]]))
        b, bt, bc = distinct_bodies.rows(idx, int(ms[idx[0]]))
        verts, nxt, used, ok = _sum_hulls(p, b, certify=certify, terms=(pt, bt),
                                          classes=pc * distinct_bodies.n_classes + bc)
        good = np.flatnonzero(ok)
        if len(good):
            parts.append((idx[good], _edges_of(verts[good], nxt[good], used[good])))
        failed.append(idx[~ok])
    gone = np.concatenate(failed).tolist()
    hulls: list[BaseGeometry] = []
    for f0 in range(0, len(gone), MEETING_BATCH):  # GEOS, one pair at a time
        if should_stop is not None and should_stop():
            raise Interrupted("summing obstacle pieces and bodies")
        hulls.extend(pair_hulls([pieces[i] for i in gone[f0:f0 + MEETING_BATCH]],
                                 [bodies[i] for i in gone[f0:f0 + MEETING_BATCH]]))
    if gone:
        parts.append((np.asarray(gone, dtype=np.int64), _geos_edges(hulls)))
    e = max(part.start.shape[1] for _, part in parts)
    start, end = np.zeros((n, e, 2)), np.zeros((n, e, 2))
    used, bounds = np.zeros((n, e), dtype=bool), np.zeros((n, 4))
    for idx, part in parts:
        w = part.start.shape[1]
        start[idx, :w], end[idx, :w] = part.start, part.end
        used[idx, :w], bounds[idx] = part.used, part.bounds
    return EdgeSet(start, end, used, bounds)


def meeting_polygons(pieces: list[np.ndarray], bodies: list[np.ndarray], *,
                     should_stop: Callable[[], bool] | None = None) -> np.ndarray:
    """:func:`meeting_edges` as shapely polygons (an object array, one per pair).

    The polygons of the same vertices as :func:`~pivot_ompl.validity.footprints.meeting_hulls`
    gives (certified, else GEOS's hull), about three times cheaper for many pairs; a pair
    whose hull is no polygon (nothing to sum) gives an empty polygon.

    Raises:
        Interrupted: ``should_stop()`` became true (:func:`meeting_edges`).
    """
    edges = meeting_edges(pieces, bodies, should_stop=should_stop)
    counts = edges.used.sum(axis=1)
    out = np.full(len(counts), shapely.Polygon(), dtype=object)
    full = np.flatnonzero(counts >= 3)
    if not len(full):
        return out
    rings = shapely.linearrings(edges.start[full][edges.used[full]],
                                indices=np.repeat(np.arange(len(full)), counts[full]))
    out[full] = shapely.polygons(rings)
    return out

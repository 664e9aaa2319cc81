"""Grid points strictly inside convex polygons: one polygon at a time, or many at once.

:func:`grid_inside` rasterises one shapely polygon, :func:`grid_union` many polygons given as
edges (:class:`~pivot_ompl.validity.minkowski.EdgeSet`) together, with the same float
expressions, so the same grid points. Both take each polygon's edges as the lines bounding
each grid column from below and above (a column at a time, not point by point).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.validity.minkowski import EdgeSet


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


def _bound(p: np.ndarray, slope: np.ndarray, sel: np.ndarray, width: np.ndarray,
           x: np.ndarray, reduce: np.ufunc, empty: float) -> np.ndarray:
    """Per (polygon, column ``x``) pair, ``reduce`` of its edges' lines (``sel``).

    The pairs run through the polygons in order, ``width[i]`` columns for polygon ``i``.
    The line of edge ``p``, ``slope`` at ``x`` is ``p_y + slope * (x - p_x)`` (evaluated as
    :func:`grid_inside` does). The selected edges are moved to the front of each polygon's
    row first (so there are only as many edge slots as the most edges one polygon has on
    that side), the others made lines constant at ``empty``. One edge slot at a time over
    all pairs, ``reduce`` folding each into the result: the same values as a pairs x slots
    array reduced along the slots, without its gathers (a third of the time); each slot's
    terms repeated over their polygon's columns from contiguous rows (a fifth less again).
    """
    order = np.argsort(~sel, axis=1, kind="stable")[:, :max(1, int(sel.sum(axis=1).max()))]
    use = np.take_along_axis(sel, order, axis=1)
    px = np.where(use, np.take_along_axis(p[..., 0], order, axis=1), 0.0).T.copy()
    py = np.where(use, np.take_along_axis(p[..., 1], order, axis=1), empty).T.copy()
    k = np.where(use, np.take_along_axis(slope, order, axis=1), 0.0).T.copy()
    out = np.empty(len(x))
    y = np.empty(len(x))
    for e in range(order.shape[1]):
        np.subtract(x, np.repeat(px[e], width), out=y)
        np.multiply(np.repeat(k[e], width), y, out=y)
        np.add(np.repeat(py[e], width), y, out=out if e == 0 else y)
        if e:
            reduce(out, y, out=out)
    return out


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
    lo = np.maximum(_bound(p, slope, lower, width, x, np.maximum, -np.inf), y0[poly])
    hi = np.minimum(_bound(p, slope, upper, width, x, np.minimum, np.inf), y1[poly])
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

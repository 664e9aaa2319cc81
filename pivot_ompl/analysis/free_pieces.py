"""The free box positions of one yaw bin: the bounds' box less where a held body meets a piece.

The polygon relaxation (:func:`~pivot_ompl.analysis.regrasp_bound.free_cover`) asks, per yaw
bin and grasp parity, where the box's centre may be with each held body kept inside the bounds
and clear of every obstacle piece. A convex body meets a convex piece exactly where its
reference point is in the hull of ``piece - body`` (a Minkowski sum); :func:`meeting_per_yaw`
gives those hulls for several yaws at once (:func:`~pivot_ompl.validity.minkowski.
meeting_polygons`: vectorised, the same vertices as GEOS's convex hulls), and
:func:`free_region` removes their union from the box of centres that keeps every eroded body
inside the bounds, as connected pieces (those that touch joined: a path may pass where they
meet).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.graph import UnionFind
from pivot_ompl.validity.minkowski import meeting_polygons

__all__ = ["HULL_PAIRS", "free_region", "meeting_per_yaw"]

#: (piece, body) pairs whose meeting hulls are summed together (a few yaw bins at a time:
#: their polygons are held at once).
HULL_PAIRS = 4096


def meeting_per_yaw(bodies: list[list[np.ndarray]], pieces: list[np.ndarray], *,
                    should_stop: Callable[[], bool] | None = None
                    ) -> list[list[BaseGeometry]]:
    """Per yaw, where each of its bodies meets each piece (polygons; none for no pair).

    ``bodies[i]``: the convex bodies (vertices relative to the box's centre) at the ``i``-th
    yaw; ``pieces``: the convex obstacle pieces.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    pairs = [(k, e) for per_yaw in bodies for e in per_yaw for k in pieces]
    if not pairs:
        return [[] for _ in bodies]
    polys = meeting_polygons([k for k, _ in pairs], [e for _, e in pairs],
                             should_stop=should_stop)
    ends = np.cumsum([0, *(len(per_yaw) * len(pieces) for per_yaw in bodies)]).tolist()
    return [[h for h in polys[a:b] if not h.is_empty]
            for a, b in zip(ends[:-1], ends[1:], strict=True)]


def free_region(bounds: tuple[float, float, float, float], inner: list[np.ndarray | None],
                hulls: list[BaseGeometry]) -> list[BaseGeometry]:
    """Connected pieces of the box positions inside ``bounds`` and outside every hull.

    ``inner``: per body, its vertices eroded as the bounds ask (``None``: nothing left, no
    constraint); every vertex of each stays inside ``bounds``. ``hulls``: where a body meets
    an obstacle piece (:func:`meeting_per_yaw`).
    """
    x0, y0, x1, y1 = bounds
    lo, hi = [x0, y0], [x1, y1]
    for e in inner:
        if e is not None:
            lo = [max(lo[0], x0 - e[:, 0].min()), max(lo[1], y0 - e[:, 1].min())]
            hi = [min(hi[0], x1 - e[:, 0].max()), min(hi[1], y1 - e[:, 1].max())]
    if lo[0] > hi[0] or lo[1] > hi[1]:
        return []
    region: BaseGeometry = shapely.box(lo[0], lo[1], hi[0], hi[1])
    if hulls:
        region = region.difference(shapely.union_all(hulls))
    geoms = [g for g in getattr(region, "geoms", [region]) if not g.is_empty]
    return merge_touching(geoms)


def merge_touching(geoms: list[BaseGeometry]) -> list[BaseGeometry]:
    """Pieces that touch (a common point) joined: a path may pass where they meet."""
    if len(geoms) < 2:
        return geoms
    sets: UnionFind[int] = UnionFind()
    for i in range(len(geoms)):
        sets.add(i)
    tree = shapely.STRtree(geoms)
    a, b = tree.query(geoms, predicate="intersects")
    for i, j in zip(a.tolist(), b.tolist(), strict=True):
        sets.union(i, j)
    groups: dict[int, list[BaseGeometry]] = {}
    for i, g in enumerate(geoms):
        groups.setdefault(sets.find(i), []).append(g)
    return [gs[0] if len(gs) == 1 else shapely.union_all(gs) for gs in groups.values()]

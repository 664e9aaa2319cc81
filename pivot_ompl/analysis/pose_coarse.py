"""Fewer, larger convex pieces holding a floor's obstacles: for under-approximations only.

The held poses' regions (:mod:`~pivot_ompl.analysis.pose_bins`) cost GEOS unions whose
inputs are the obstacle pieces' Minkowski sums, one per piece near the region: on a SLAM map
of pixel boxes (1506 on the lab map) that is hundreds of deeply overlapping sums per union,
and their count, not their vertices, sets the cost. :func:`coarse_pieces` merges touching
pieces into their convex hull while the hull adds little area: a pixel staircase or a row of
boxes along a wall becomes one piece (the lab's 1506 boxes become about 130).

Every given piece lies inside some returned piece, so the obstacles only grow: the free set
found from them is inside the exact one. That suits a test that may only under-approximate
the free set (:class:`~pivot_ompl.analysis.pose_inner.EveryYawRegions`, whose answer
"joined" only spares a proof); it must never feed a proof that some pose is not free.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely

from pivot_ompl.errors import Interrupted

#: Area a merge's hull may add (m²) per metre of its outline: the added slivers' mean width.
#: One centimetre keeps the every-yaw answers of the shipped scenes, the corridor rows and the
#: corpus maps measured (docs/buildings.md).
TOLERANCE = 0.01
#: Pieces closer than this (m) touch (grid-aligned boxes' shared edges carry round-off).
TOUCH = 1e-9
#: Most rounds of merges (each merges every piece at most once).
MOST_ROUNDS = 16


def coarse_pieces(pieces: list[np.ndarray], *, tolerance: float = TOLERANCE,
                  should_stop: Callable[[], bool] | None = None) -> list[np.ndarray]:
    """Convex pieces (counter-clockwise, not closed) holding every piece of ``pieces``.

    ``pieces``: convex polygons (vertices ``(k, 2)``, in metres).
    Each round pairs touching pieces, the pairs whose hull adds the least area per metre of
    the hull's outline first, each piece in one pair at most, and replaces each pair whose
    hull adds at most ``tolerance`` m² per metre by the hull; rounds end when none merges
    (or after :data:`MOST_ROUNDS`). ``should_stop`` is polled every round
    (:class:`~pivot_ompl.errors.Interrupted` when true).
    """
    if not pieces:
        return []
    polys = np.asarray([shapely.Polygon(np.asarray(p, dtype=float)) for p in pieces],
                       dtype=object)
    for _ in range(MOST_ROUNDS):
        if should_stop is not None and should_stop():
            raise Interrupted("the coarse pieces")
        i, j = shapely.STRtree(polys).query(polys, predicate="dwithin", distance=TOUCH)
        pair = i < j
        i, j = i[pair], j[pair]
        if not len(i):
            break
        joined = shapely.union(polys[i], polys[j])
        hulls = shapely.convex_hull(joined)
        hull_area = shapely.area(hulls)
        added = (hull_area - shapely.area(joined)) / shapely.length(hulls)
        ok = np.flatnonzero(added <= tolerance)
        used = np.zeros(len(polys), dtype=bool)
        merged = []
        for k in ok[np.argsort(added[ok], kind="stable")]:
            if not (used[i[k]] or used[j[k]]):
                used[i[k]] = used[j[k]] = True
                merged.append(k)
        if not merged:
            break
        polys = np.concatenate([polys[~used], hulls[merged]])
    rings = shapely.get_exterior_ring(shapely.orient_polygons(polys))
    return [np.asarray(r.coords)[:-1] for r in rings]

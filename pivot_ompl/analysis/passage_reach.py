"""Whether the start and the goal share a region of the passage search, without its union.

:func:`~pivot_ompl.analysis.passage.blocking_passage` cuts the floor into regions by closing
every gap narrower than the held assembly: the union of the walls and the sealed gaps, whose
cost is most of the search on a map of hundreds of wall pieces (a 14 x 21 m warehouse of 866
pieces: about 0.3 s of 0.4 s). Where the start and the goal lie in one region, no passage
blocks them and the regions are not needed. :func:`share_region` looks for a polyline from
the start to the goal that keeps clear of every wall and every gap segment:

* a raster proposes it: the cell centres farther than half a cell (and twice the seal) from
  every wall and gap, joined 4-adjacent (a point of the segment between two such centres is
  within half a cell of one of them, so it keeps clear too), their components by
  ``scipy.ndimage.label``;
* the start and the goal join the nearest of those centres by straight segments that an
  exact query finds clear (farther than twice the seal from every wall and gap).

A start and a goal joined to one component are joined by a clear polyline, so they lie in
one region of the floor less the walls and the sealed gaps (the answer the union would
give). Given more gaps than the search seals (every gap, before it drops those that meet a
third wall), the answer holds for the gaps it seals: a polyline clear of all is clear of
those. ``False`` says nothing: the union decides.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import shapely
from scipy import ndimage
from shapely.geometry.base import BaseGeometry

#: Most raster cells tried (about 0.15 s); a larger floor goes straight to the union (a
#: 56 x 61 m office map of 5049 pieces, 70 000 cells, whose start and goal lie apart: the
#: raster would cost 0.26 s before the gap count ends the search).
MAX_CELLS = 50_000
#: Most raster cells tried per wall and gap: the raster costs about 3 us a cell, the union
#: grows faster than its pieces (0.07 s for 364 on a house, 0.7 s for 1866 on a warehouse,
#: 0.03 s for the 195 of a long row of 32 rooms, whose bounds hold 150 000 cells).
CELLS_PER_PIECE = 20
#: Cell centres, nearest first, each end tries to join by a straight segment.
JOIN_TRIES = 16


def share_region(walls: Sequence[BaseGeometry], gaps: np.ndarray,
                 bounds: tuple[float, float, float, float], start: tuple[float, float],
                 goal: tuple[float, float], *, cell: float, seal: float,
                 max_cells: int = MAX_CELLS,
                 should_stop: Callable[[], bool] | None = None) -> bool:
    """Whether a polyline clear of ``walls`` and ``gaps`` joins ``start`` to ``goal``.

    Args:
        walls: the walls (polygons; slabs outside ``bounds`` included).
        gaps: the gap segments (``LineString`` array), sealed ``seal`` m either side.
        bounds: the floor's ``(x0, y0, x1, y1)`` (m).
        start: the first point (m, world frame).
        goal: the second point (m, world frame).
        cell: the raster's cell side (m, > 0).
        seal: the gaps' sealing half-thickness (m): the polyline keeps twice that clear.
        max_cells: no try where the raster would hold more cells (:func:`cell_budget`).
        should_stop: polled before the raster's query.

    Returns ``True`` when found (see the module docstring); ``False`` says nothing (also
    when not tried).
    """
    x0, y0, x1, y1 = bounds
    nx, ny = int((x1 - x0) / cell), int((y1 - y0) / cell)
    if nx < 1 or ny < 1 or nx * ny > max_cells:
        return False
    if should_stop is not None and should_stop():
        return False
    tree = shapely.STRtree(list(walls) + list(gaps))
    gx = x0 + cell * (np.arange(nx) + 0.5)
    gy = y0 + cell * (np.arange(ny) + 0.5)
    xs, ys = np.meshgrid(gx, gy, indexing="ij")
    centres = shapely.points(xs.ravel(), ys.ravel())
    near = tree.query(centres, predicate="dwithin", distance=0.5 * cell + 2.0 * seal)[0]
    clear = np.ones(nx * ny, dtype=bool)
    clear[near] = False
    labels = ndimage.label(clear.reshape(nx, ny))[0].ravel()
    ends = [_joined_labels(tree, labels, xs.ravel(), ys.ravel(), p, seal) for p in (start, goal)]
    return bool(ends[0] & ends[1])


def _joined_labels(tree: shapely.STRtree, labels: np.ndarray, xs: np.ndarray, ys: np.ndarray,
                   point: tuple[float, float], seal: float) -> set[int]:
    """Components of the clear centres ``point`` joins by a clear straight segment."""
    free = np.flatnonzero(labels > 0)
    if len(free) == 0:
        return set()
    d = np.hypot(xs[free] - point[0], ys[free] - point[1])
    nearest = free[np.argsort(d, kind="stable")[:JOIN_TRIES]]
    coords = np.stack([np.broadcast_to(np.asarray(point, dtype=float), (len(nearest), 2)),
                       np.column_stack([xs[nearest], ys[nearest]])], axis=1)
    segments = shapely.linestrings(coords)
    blocked = np.unique(tree.query(segments, predicate="dwithin", distance=2.0 * seal)[0])
    ok = np.ones(len(nearest), dtype=bool)
    ok[blocked] = False
    return {int(labels[i]) for i in nearest[ok]}


def cell_budget(pieces: int) -> int:
    """Most raster cells worth a try before a union of ``pieces`` walls and gaps.

    :data:`CELLS_PER_PIECE` per piece, at most :data:`MAX_CELLS`: beyond, the union is the
    cheaper.
    """
    return min(MAX_CELLS, CELLS_PER_PIECE * pieces)


def raster_cell(need: float) -> float:
    """The raster's cell side (m) for an assembly ``need`` m wide: a quarter of it.

    The openings between the walls that the gaps leave open are mostly at least ``need``
    wide, so they hold clear centres.
    """
    return max(need / 4.0, 1e-3) if math.isfinite(need) else 1.0

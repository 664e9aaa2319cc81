"""The route bound's shortest route as a polyline, kept off the walls by a margin.

The route bound (:func:`~pivot_ompl.analysis.route_bound.route_on`) measures the shortest
path of the box's centre through a raster of free cells; :func:`route_polyline` returns that
path itself, from any point to any other, as a few straight segments: a guide a plan's
transfer may follow (:mod:`pivot_ompl.planners.follow_route`). The shortest path hugs the
walls (the relaxation keeps only the box's inscribed disk off them), where the held
assembly, larger than the disk, often cannot pass or can only by small rotations. A
``margin`` (m) makes a cell closer than that to the cells outside the mask dearer
(:data:`WALL_PENALTY` x its shortfall, relative to the margin): the path keeps the margin
where there is room and squeezes through narrower passages. The simplification keeps what
the path kept: a segment replaces a stretch only if every cell it crosses is free and as far
from the walls as the stretch's nearest cell was, up to the margin.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.ndimage import distance_transform_edt
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import neighbour_edges

__all__ = ["WALL_PENALTY", "FreeField", "Route", "route_polyline"]

#: Extra price of a metre through cells with no clearance, relative to a metre that keeps the
#: margin (linear in the shortfall between): a detour of up to this many times a wall-hugging
#: stretch's length is preferred to it.
WALL_PENALTY = 3.0

Point = tuple[float, float]


class Route(NamedTuple):
    """A route through the free cells.

    Attributes:
        points: the polyline's points, the route's start first and its goal last.
        cost: the graph search's cost of the route before its simplification: its length (m)
            with ``margin = 0``, more where it comes closer than the margin to a wall.
        cells: the flat indices of the cells the route passes, in order.
    """

    points: list[Point]
    cost: float
    cells: np.ndarray


@dataclass(frozen=True)
class FreeField:
    """Free cells of a raster, their distance to the nearest cell that is not free, the graph.

    Attributes:
        raster: the raster.
        mask: the free cells (a boolean ``raster.shape`` array).
        clearance: for each free cell the distance (m) between its centre and the nearest
            non-free cell's centre (0 outside ``mask``).
        graph: the raster graph over ``mask`` (a CSR matrix of flat cell indices whose
            entries, both ways, are the moves' lengths, m:
            :func:`~pivot_ompl.analysis.route_bound.neighbour_edges`).
        edge_clearance: each of ``graph``'s entries' least clearance of its two cells.
    """

    raster: FloorRaster
    mask: np.ndarray
    clearance: np.ndarray
    graph: csr_matrix
    edge_clearance: np.ndarray

    @classmethod
    def of(cls, raster: FloorRaster, mask: np.ndarray) -> FreeField:
        """The field of ``mask`` over ``raster``."""
        clear = distance_transform_edt(mask) * raster.cell if mask.any() else \
            np.zeros(mask.shape)
        rows, cols, steps = neighbour_edges(mask)
        # both directions stored: the searches need not transpose the graph each time
        rows, cols, steps = (np.concatenate([rows, cols]), np.concatenate([cols, rows]),
                             np.concatenate([steps, steps]))
        n = mask.size
        ids = coo_matrix((np.arange(1.0, len(rows) + 1.0), (rows, cols)), shape=(n, n)).tocsr()
        order = ids.data.astype(np.int64) - 1
        graph = csr_matrix((raster.cell * steps[order], ids.indices, ids.indptr), shape=(n, n))
        flat = clear.ravel()
        return cls(raster, mask, clear, graph, np.minimum(flat[rows], flat[cols])[order])

    def cells(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Flat indices of the cells holding the points ``(x, y)`` (clipped to the floor)."""
        (x0, y0), h = self.raster.origin, self.raster.cell
        nx, ny = self.raster.shape
        i = np.clip(((x - x0) // h).astype(int), 0, nx - 1)
        j = np.clip(((y - y0) // h).astype(int), 0, ny - 1)
        return i * ny + j


def route_polyline(field: FreeField, start: Point, goal: Point, *, margin: float,
                   via: Route | None = None, poll: Callable[[], None] = lambda: None
                   ) -> Route | None:
    """The shortest route from ``start`` to ``goal`` through the free cells, simplified.

    Args:
        field: the free cells.
        start: the route's first point (m); its cell must be free.
        goal: the route's last point (m); its cell must be free.
        margin: clearance (m) the route keeps from non-free cells where there is room (module
            docstring); 0: the plain shortest route.
        via: a route between the same cells, if known: what it costs with ``margin`` bounds
            the search (it looks no farther).
        poll: called between the steps (it may raise to stop).

    Returns:
        The route; ``None`` when either end's cell is not free or no route within ``limit``
        joins them.
    """
    flat, clear = field.mask.ravel(), field.clearance.ravel()
    ends = [int(field.cells(np.array([p[0]]), np.array([p[1]]))[0]) for p in (start, goal)]
    if not (flat[ends[0]] and flat[ends[1]]):
        return None
    graph = field.graph
    if margin > 0:
        graph = csr_matrix((graph.data * _penalty(field.edge_clearance, margin),
                            graph.indices, graph.indptr), shape=graph.shape)
    limit = math.inf
    if via is not None and via.cells[0] == ends[0] and via.cells[-1] == ends[1]:
        c = via.cells
        steps = np.hypot(*np.divmod(c[1:], field.raster.shape[1])
                         - np.array(np.divmod(c[:-1], field.raster.shape[1])))
        cost = field.raster.cell * steps * _penalty(np.minimum(clear[c[1:]], clear[c[:-1]]),
                                                    margin)
        limit = float(cost.sum()) * (1.0 + 1e-9) + 1e-9
    poll()
    dist, pred = dijkstra(graph, directed=True, indices=ends[0], return_predecessors=True,
                          limit=limit)
    cost = float(dist[ends[1]])
    if not math.isfinite(cost):
        return None
    chain = [ends[1]]
    while chain[-1] != ends[0]:
        chain.append(int(pred[chain[-1]]))
    chain.reverse()
    poll()
    gx, gy = field.raster.gx.ravel(), field.raster.gy.ravel()
    pts = [start, *((float(gx[c]), float(gy[c])) for c in chain[1:-1]), goal]
    cells = np.array(chain)
    return Route(_simplified(field, pts, np.minimum(clear[cells], margin)), cost, cells)


def _penalty(clearance: np.ndarray, margin: float) -> np.ndarray:
    """Factor on the length of moves whose cells are ``clearance`` m clear (module docstring)."""
    if margin <= 0:
        return np.ones_like(clearance)
    return 1.0 + WALL_PENALTY * np.clip(1.0 - clearance / margin, 0.0, 1.0)


def _simplified(field: FreeField, pts: list[Point], need: np.ndarray) -> list[Point]:
    """``pts`` with stretches replaced by segments that keep their clearance ``need``.

    From each kept point the next is found by galloping (1, 2, 4, ... points ahead) to the
    first segment refused, then bisecting back: every segment kept is checked (a few
    checks a point, not one per point passed).
    """
    out = [pts[0]]
    i, n = 0, len(pts)
    tol = field.raster.half_diag

    def ok(j: int) -> bool:
        return _clear(field, pts[i], pts[j], float(need[i:j + 1].min()) - tol)

    while i < n - 1:
        good, step = i + 1, 1
        while good + step < n and ok(good + step):
            good += step
            step *= 2
        bad = min(n, good + step)
        while bad - good > 1:  # good passes; bad fails or lies past the end
            mid = (good + bad) // 2
            if ok(mid):
                good = mid
            else:
                bad = mid
        out.append(pts[good])
        i = good
    return out


def _clear(field: FreeField, a: Point, b: Point, need: float) -> bool:
    """Whether every cell the segment ``a b`` crosses is free and ``need`` m clear.

    Points half a cell apart at most, so two consecutive ones lie in the same or neighbouring
    cells; where they are diagonal neighbours the segment crosses one of the two cells beside
    both, and both are checked (a superset of the cells crossed).
    """
    d = math.hypot(b[0] - a[0], b[1] - a[1])
    k = max(2, math.ceil(2.0 * d / field.raster.cell) + 1)
    t = np.linspace(0.0, 1.0, k)
    c = field.cells(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
    ny = field.raster.shape[1]
    i, j = np.divmod(c, ny)
    diag = (np.diff(i) != 0) & (np.diff(j) != 0)
    c = np.concatenate([c, i[:-1][diag] * ny + j[1:][diag], i[1:][diag] * ny + j[:-1][diag]])
    return bool(field.mask.ravel()[c].all() and (field.clearance.ravel()[c] >= need).all())

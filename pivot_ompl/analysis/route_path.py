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

import numpy as np
from scipy.ndimage import distance_transform_edt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import neighbour_edges

__all__ = ["WALL_PENALTY", "FreeField", "route_polyline"]

#: Extra price of a metre through cells with no clearance, relative to a metre that keeps the
#: margin (linear in the shortfall between): a detour of up to this many times a wall-hugging
#: stretch's length is preferred to it.
WALL_PENALTY = 3.0

Point = tuple[float, float]


@dataclass(frozen=True)
class FreeField:
    """Free cells of a raster and their distance to the nearest cell that is not free.

    Attributes:
        raster: the raster.
        mask: the free cells (a boolean ``raster.shape`` array).
        clearance: for each free cell the distance (m) between its centre and the nearest
            non-free cell's centre (0 outside ``mask``).
        edges: the raster graph's ``(rows, cols, steps)`` over ``mask``
            (:func:`~pivot_ompl.analysis.route_bound.neighbour_edges`).
    """

    raster: FloorRaster
    mask: np.ndarray
    clearance: np.ndarray
    edges: tuple[np.ndarray, np.ndarray, np.ndarray]

    @classmethod
    def of(cls, raster: FloorRaster, mask: np.ndarray) -> FreeField:
        """The field of ``mask`` over ``raster``."""
        clear = distance_transform_edt(mask) * raster.cell if mask.any() else \
            np.zeros(mask.shape)
        return cls(raster, mask, clear, neighbour_edges(mask))

    def cells(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Flat indices of the cells holding the points ``(x, y)`` (clipped to the floor)."""
        (x0, y0), h = self.raster.origin, self.raster.cell
        nx, ny = self.raster.shape
        i = np.clip(((x - x0) // h).astype(int), 0, nx - 1)
        j = np.clip(((y - y0) // h).astype(int), 0, ny - 1)
        return i * ny + j


def route_polyline(field: FreeField, start: Point, goal: Point, *, margin: float,
                   poll: Callable[[], None] = lambda: None) -> list[Point] | None:
    """The shortest route from ``start`` to ``goal`` through the free cells, simplified.

    Args:
        field: the free cells.
        start: the route's first point (m); its cell must be free.
        goal: the route's last point (m); its cell must be free.
        margin: clearance (m) the route keeps from non-free cells where there is room (module
            docstring); 0: the plain shortest route.
        poll: called between the steps (it may raise to stop).

    Returns:
        The polyline's points, ``start`` first and ``goal`` last; ``None`` when either end's
        cell is not free or no route joins them.
    """
    flat, clear = field.mask.ravel(), field.clearance.ravel()
    ends = [int(field.cells(np.array([p[0]]), np.array([p[1]]))[0]) for p in (start, goal)]
    if not (flat[ends[0]] and flat[ends[1]]):
        return None
    rows, cols, steps = field.edges
    weight = field.raster.cell * steps
    if margin > 0:
        short = np.clip(1.0 - np.minimum(clear[rows], clear[cols]) / margin, 0.0, 1.0)
        weight = weight * (1.0 + WALL_PENALTY * short)
    n = flat.size
    graph = coo_matrix((weight, (rows, cols)), shape=(n, n)).tocsr()
    poll()
    dist, pred = dijkstra(graph, directed=False, indices=ends[0], return_predecessors=True)
    if not math.isfinite(float(dist[ends[1]])):
        return None
    chain = [ends[1]]
    while chain[-1] != ends[0]:
        chain.append(int(pred[chain[-1]]))
    chain.reverse()
    poll()
    gx, gy = field.raster.gx.ravel(), field.raster.gy.ravel()
    pts = [start, *((float(gx[c]), float(gy[c])) for c in chain[1:-1]), goal]
    need = np.minimum(clear[np.array(chain)], margin)
    return _simplified(field, pts, need)


def _simplified(field: FreeField, pts: list[Point], need: np.ndarray) -> list[Point]:
    """``pts`` with stretches replaced by segments that keep their clearance ``need``."""
    out = [pts[0]]
    i, n = 0, len(pts)
    tol = field.raster.half_diag
    while i < n - 1:
        j = i + 1
        while j + 1 < n and _clear(field, pts[i], pts[j + 1],
                                   float(need[i:j + 2].min()) - tol):
            j += 1
        out.append(pts[j])
        i = j
    return out


def _clear(field: FreeField, a: Point, b: Point, need: float) -> bool:
    """Whether every cell the segment ``a b`` crosses is free and ``need`` m clear."""
    d = math.hypot(b[0] - a[0], b[1] - a[1])
    k = max(2, math.ceil(2.0 * d / field.raster.cell) + 1)
    t = np.linspace(0.0, 1.0, k)
    c = field.cells(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
    return bool(field.mask.ravel()[c].all() and (field.clearance.ravel()[c] >= need).all())

"""Floor distances in a window round the goals: nothing computed over the whole floor.

A walk's floor distances (:meth:`~pivot_ompl.transit.field.FloorField.distances`) are
wanted within a ``limit`` of its goal positions: beyond it they hold the limit, a lower
bound. A grid path no longer than the limit never leaves the square of half-side
``limit`` round the goals (a grid step is at least as long as the straight line), so the
Dijkstra needs the open positions of that window alone (grown by :data:`WINDOW_MARGIN`
cells, so the settled positions' every neighbour is in it and the frontier test is
complete): its answer is the whole floor's, exact within the limit, ``inf`` where the goals'
positions within reach were all settled (no walk leaves them), the limit elsewhere.

The open positions are computed a tile of :data:`TILE` x :data:`TILE` grid positions at a
time, on first use, against the obstacle pieces near the tile (:class:`FloorTiles`): a
walk round a box in a long turned building pays for the floor round the box, not for the
bounds' rectangle, whose area grows with the square of the building's length.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.transit.floor_graph import OpenGraph, open_components
from pivot_ompl.transit.floor_grid import FloorGrid
from pivot_ompl.transit.lattice import HEADING_VECTORS

#: Side (grid positions) of the tiles in which the open positions are computed and kept.
TILE = 64
#: Cells a window extends beyond the limit (the longest heading vector is two cells long).
WINDOW_MARGIN = 3


@dataclass(frozen=True)
class FloorWindow:
    """Floor distances (m) over a window of the grid, and the value everywhere outside it.

    Attributes:
        values: the distances over grid rows ``x0 ..`` and columns ``y0 ..``.
        x0, y0: the window's first grid position.
        outside: the distance of every position outside the window (the limit, a lower
            bound, or ``inf`` when no walk reaches the goals from there).
    """

    values: np.ndarray
    x0: int
    y0: int
    outside: float

    def __getitem__(self, cell: tuple[int, int]) -> float:
        """The distance at grid position ``(ix, iy)``."""
        i, j = cell[0] - self.x0, cell[1] - self.y0
        if 0 <= i < self.values.shape[0] and 0 <= j < self.values.shape[1]:
            return float(self.values[i, j])
        return self.outside

    def dense(self, nx: int, ny: int) -> np.ndarray:
        """The distances over the whole ``nx`` x ``ny`` grid (for tests and pictures)."""
        out = np.full((nx, ny), self.outside)
        wx, wy = self.values.shape
        out[self.x0:self.x0 + wx, self.y0:self.y0 + wy] = self.values
        return out


class FloorTiles:
    """The open positions (obstacles and bounds only) of a :class:`FloorGrid`, by tiles.

    Args:
        grid: the floor grid.
        tile: the tiles' side (grid positions).

    Attributes:
        tiles_built: tiles computed so far.
    """

    def __init__(self, grid: FloorGrid, tile: int | None = None) -> None:
        """No tile yet."""
        self.grid = grid
        self.tile = TILE if tile is None else tile
        self.tiles_built = 0
        self._tiles: dict[tuple[int, int], np.ndarray] = {}

    def window(self, wx: slice, wy: slice, should_stop: Callable[[], bool] | None = None
               ) -> np.ndarray:
        """The open positions of grid rows ``wx`` and columns ``wy`` (a new array).

        Raises:
            Interrupted: ``should_stop()`` became true (polled before every tile built; the
                tiles built are kept).
        """
        g, t = self.grid, self.tile
        out = np.zeros((wx.stop - wx.start, wy.stop - wy.start), dtype=bool)
        for tx in range(wx.start // t, (wx.stop - 1) // t + 1):
            for ty in range(wy.start // t, (wy.stop - 1) // t + 1):
                tile = self._tiles.get((tx, ty))
                if tile is None:
                    if should_stop is not None and should_stop():
                        raise Interrupted("walking floor field")
                    tile = g.open_block(slice(tx * t, min(g.nx, (tx + 1) * t)),
                                        slice(ty * t, min(g.ny, (ty + 1) * t)), should_stop)
                    self._tiles[(tx, ty)] = tile
                    self.tiles_built += 1
                x0, x1 = max(wx.start, tx * t), min(wx.stop, (tx + 1) * t)
                y0, y1 = max(wy.start, ty * t), min(wy.stop, (ty + 1) * t)
                out[x0 - wx.start:x1 - wx.start, y0 - wy.start:y1 - wy.start] = \
                    tile[x0 - tx * t:x1 - tx * t, y0 - ty * t:y1 - ty * t]
        return out


def goal_window(grid: FloorGrid, goals: list[tuple[int, int]], limit: float
                ) -> tuple[slice, slice]:
    """The grid rows and columns within ``limit`` (plus :data:`WINDOW_MARGIN`) of ``goals``."""
    reach = math.ceil(limit / grid.resolution) + WINDOW_MARGIN
    gx, gy = [g[0] for g in goals], [g[1] for g in goals]
    return (slice(max(0, min(gx) - reach), min(grid.nx, max(gx) + reach + 1)),
            slice(max(0, min(gy) - reach), min(grid.ny, max(gy) + reach + 1)))


def flood_distances(tiles: FloorTiles, closes: Callable[[slice, slice], np.ndarray],
                    goals: list[tuple[int, int]], limit: float,
                    should_stop: Callable[[], bool] | None = None) -> tuple[FloorWindow, int]:
    """Floor distances to ``goals`` within ``limit``, over the tiles the Dijkstra reaches.

    Starts with the goals' tiles and their neighbours; while a settled position has a
    neighbour in a tile not loaded (inside :func:`goal_window`: no farther position can be
    within the limit), the tiles round that tile are loaded (1, then 2, 4, ... tiles round
    it: few rounds on an open floor) and the Dijkstra run again.
    When none has, its settled positions and distances are the whole floor's (every edge the
    whole floor's Dijkstra relaxes from them lies in the loaded tiles). ``closes(wx, wy)``:
    the positions the resting box closes in a block. Returns the distances (unloaded tiles
    hold the limit, or ``inf`` when no settled position leads on) and how many positions
    the last Dijkstra's graph held.

    Raises:
        Interrupted: ``should_stop()`` became true (polled before every tile built).
    """
    g, t = tiles.grid, tiles.tile
    wx, wy = goal_window(g, goals, limit)
    tx0, tx1 = wx.start // t, (wx.stop - 1) // t + 1
    ty0, ty1 = wy.start // t, (wy.stop - 1) // t + 1
    loaded: set[tuple[int, int]] = set()
    todo = {(gx // t + dx, gy // t + dy) for gx, gy in goals for dx in (-1, 0, 1)
            for dy in (-1, 0, 1)}
    ring = 1  # tiles loaded round a tile reached, doubled every round
    while True:
        loaded |= {(a, b) for a, b in todo if tx0 <= a < tx1 and ty0 <= b < ty1}
        ax0, ax1 = min(a for a, _ in loaded), max(a for a, _ in loaded) + 1
        ay0, ay1 = min(b for _, b in loaded), max(b for _, b in loaded) + 1
        bx = slice(ax0 * t, min(g.nx, ax1 * t))
        by = slice(ay0 * t, min(g.ny, ay1 * t))
        open_ = np.zeros((bx.stop - bx.start, by.stop - by.start), dtype=bool)
        known = np.zeros_like(open_)
        for a, b in loaded:
            sx = slice(a * t, min(g.nx, (a + 1) * t))
            sy = slice(b * t, min(g.ny, (b + 1) * t))
            lx = slice(sx.start - bx.start, sx.stop - bx.start)
            ly = slice(sy.start - by.start, sy.stop - by.start)
            open_[lx, ly] = tiles.window(sx, sy, should_stop)
            known[lx, ly] = True
        res, settled = _distances(open_, known, closes(bx, by), bx.start, by.start, goals,
                                  g.resolution, limit)
        todo = set()
        if len(settled):
            px, py = np.divmod(settled, by.stop - by.start)
            px, py = px + bx.start, py + by.start
            near = (px % t < 2) | (px % t >= t - 2) | (py % t < 2) | (py % t >= t - 2)
            v = np.asarray(HEADING_VECTORS)
            nx_ = (px[near][:, None] + v[None, :, 0]).ravel()
            ny_ = (py[near][:, None] + v[None, :, 1]).ravel()
            ok = (nx_ >= 0) & (nx_ < g.nx) & (ny_ >= 0) & (ny_ < g.ny)
            grow = range(-ring, ring + 1)
            for a, b in set(zip((nx_[ok] // t).tolist(), (ny_[ok] // t).tolist(),
                                strict=True)) - loaded:
                todo |= {(a + dx, b + dy) for dx in grow for dy in grow}
        todo -= loaded
        ring *= 2
        if not {(a, b) for a, b in todo if tx0 <= a < tx1 and ty0 <= b < ty1}:
            return res


def _distances(open_: np.ndarray, known: np.ndarray, closed: np.ndarray, x0: int, y0: int,
               goals: list[tuple[int, int]], resolution: float, limit: float
               ) -> tuple[tuple[FloorWindow, int], np.ndarray]:
    """One Dijkstra over a block: the distances, graph size, settled positions (block flat)."""
    wnx, wny = open_.shape
    flat = np.asarray([(ix - x0) * wny + (iy - y0) for ix, iy in goals], dtype=np.int64)
    is_open = open_.ravel()[flat] & ~closed.ravel()[flat]
    values = np.full((wnx, wny), math.inf)
    outside = math.inf
    settled_cells = np.zeros(0, dtype=np.int64)
    searched = 0
    if is_open.any():
        free = open_ & ~closed
        cells = np.flatnonzero(free.ravel())
        labels = open_components(free)  # the goals' components alone: the graph's nodes
        keep = np.isin(labels, labels[np.searchsorted(cells, flat[is_open])])
        free = np.zeros(wnx * wny, dtype=bool)
        free[cells[keep]] = True
        graph = OpenGraph(free.reshape(wnx, wny), resolution)
        graph.add_rows(0, wnx)
        csr = graph.csr()
        searched = len(graph.cells)
        dist = np.asarray(dijkstra(csr, directed=True, min_only=True, limit=limit,
                                   indices=graph.node[flat[is_open]]))
        settled = np.isfinite(dist)
        settled_cells = graph.cells[settled]
        if _frontier(csr, settled, len(HEADING_VECTORS)):
            outside = limit  # farther positions: a lower bound
            values[open_ | ~known] = limit
        values.ravel()[settled_cells] = dist[settled]
    values.ravel()[flat] = 0.0  # a goal that is not open is its own distance 0 away
    return (FloorWindow(values, x0, y0, outside), searched), settled_cells


def _frontier(graph, settled: np.ndarray, slots: int) -> bool:  # noqa: ANN001 - csr_matrix
    """Whether an open edge of ``graph`` leads from a settled node to one not settled."""
    nodes = np.flatnonzero(settled)
    entries = (nodes[:, None] * slots + np.arange(slots)[None, :]).ravel()
    open_ = np.isfinite(graph.data[entries])
    return bool((~settled[graph.indices[entries[open_]]]).any())

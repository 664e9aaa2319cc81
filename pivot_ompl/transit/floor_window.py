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
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.transit.floor_graph import open_components
from pivot_ompl.transit.floor_grid import FloorGrid
from pivot_ompl.transit.lattice import HEADING_VECTORS

#: Side (grid positions) of the tiles in which the open positions are computed and kept.
TILE = 64
#: Rounds of the flood that load one ring of tiles round those its Dijkstra leads into,
#: before the rings double (a walk round a box pays for the tiles it enters, and a long one
#: runs few Dijkstras).
SINGLE_RINGS = 4
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

    @property
    def built(self) -> set[tuple[int, int]]:
        """The tiles built so far: ``(tx, ty)``, from grid position ``(tx, ty) * tile``."""
        return set(self._tiles)

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

    Starts with the goals' tiles and their neighbours, all inside :func:`goal_window` (no
    farther position can be within the limit); then while a settled position of the Dijkstra
    has a neighbour in a tile not loaded, the tiles round that tile are loaded (one ring of
    tiles round it for :data:`SINGLE_RINGS` rounds, then 2, 4, ...) and the Dijkstra run
    again. Only the tiles the Dijkstra leads into are built: loading first every tile the
    goals' component reaches in the window (a labelling) built tiles no walk within the
    limit enters (on the Willow Garage office, a regrasp walk's 25 m window: 52 tiles built
    where the Dijkstra needed 14, 2.3 s more).
    When none has, its settled positions and distances are the whole floor's (every edge the
    whole floor's Dijkstra relaxes from them lies in the loaded tiles). ``closes(wx, wy)``:
    the positions the resting box closes in a block. Returns the distances (unloaded tiles
    hold the limit, or ``inf`` when no settled position leads on) and how many positions
    the last Dijkstra's graph held.

    Raises:
        Interrupted: ``should_stop()`` became true (polled before every tile built and
            every Dijkstra).
    """
    g, t = tiles.grid, tiles.tile
    wx, wy = goal_window(g, goals, limit)
    square = (wx.start // t, (wx.stop - 1) // t + 1, wy.start // t, (wy.stop - 1) // t + 1)
    loaded = _within({(gx // t + dx, gy // t + dy) for gx, gy in goals for dx in (-1, 0, 1)
                      for dy in (-1, 0, 1)}, square)
    bx, by, open_, known = _assemble(tiles, loaded, should_stop)
    ring, rounds = 1, 0  # while the Dijkstra leads out: the tiles round those it enters
    while True:
        if should_stop is not None and should_stop():
            raise Interrupted("walking floor field")
        res, settled = _distances(open_, known, closes(bx, by), bx.start, by.start, goals,
                                  g.resolution, limit)
        todo = _within(_next_tiles(tiles, settled, bx, by, loaded, ring), square)
        if not todo:
            return res
        loaded |= todo
        rounds += 1
        if rounds >= SINGLE_RINGS:  # then 2, 4, ... tiles round them: few Dijkstras
            ring *= 2
        bx, by, open_, known = _assemble(tiles, loaded, should_stop)


def _within(tiles: set[tuple[int, int]], square: tuple[int, int, int, int]
            ) -> set[tuple[int, int]]:
    """The tiles of ``tiles`` inside ``square`` (``tx0, tx1, ty0, ty1``, ends excluded)."""
    return {(a, b) for a, b in tiles if square[0] <= a < square[1] and square[2] <= b < square[3]}


def _assemble(tiles: FloorTiles, loaded: set[tuple[int, int]],
              should_stop: Callable[[], bool] | None
              ) -> tuple[slice, slice, np.ndarray, np.ndarray]:
    """The block of the loaded tiles' bounding box: its open and its loaded positions."""
    g, t = tiles.grid, tiles.tile
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
    return bx, by, open_, known


def _next_tiles(tiles: FloorTiles, cells: np.ndarray, bx: slice, by: slice,
                loaded: set[tuple[int, int]], ring: int) -> set[tuple[int, int]]:
    """The tiles within ``ring`` of each tile not loaded that ``cells`` may lead into.

    ``cells``: flat indices of the block ``bx`` x ``by``. A heading vector is at most two
    positions long along each axis: a position leads into a neighbouring tile only from the
    strip two positions wide along their common side (or corner).
    """
    g, t = tiles.grid, tiles.tile
    if not len(cells):
        return set()
    reached = np.zeros((bx.stop - bx.start, by.stop - by.start), dtype=bool)
    reached.ravel()[cells] = True
    sides = {-1: slice(0, 2), 0: slice(None), 1: slice(-2, None)}
    grow = range(-ring, ring + 1)
    out: set[tuple[int, int]] = set()
    for a, b in loaded:
        x0, y0 = a * t - bx.start, b * t - by.start
        sub = reached[x0:x0 + t, y0:y0 + t]
        if not sub.any():
            continue
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                n = (a + dx, b + dy)
                if n in loaded or not (0 <= n[0] * t < g.nx and 0 <= n[1] * t < g.ny):
                    continue
                if sub[sides[dx], sides[dy]].any():
                    out |= {(n[0] + i, n[1] + j) for i in grow for j in grow}
    return out - loaded


def _graph(free: np.ndarray, resolution: float) -> tuple[np.ndarray, np.ndarray, csr_matrix]:
    """The open grid's graph over ``free``, as :class:`~.floor_graph.OpenGraph`'s, at once.

    Returns its positions (flat indices), each position's node (``-1``: none), the graph.
    """
    wnx, wny = free.shape
    nd = len(HEADING_VECTORS)
    cells = np.flatnonzero(free.ravel())
    m = len(cells)
    padded = np.full((wnx + 4, wny + 4), -1, dtype=np.int32)
    padded[2:-2, 2:-2][free] = np.arange(m, dtype=np.int32)
    node = padded[2:-2, 2:-2].ravel()
    ix, iy = np.divmod(cells, wny)
    v = np.asarray(HEADING_VECTORS)
    base = (ix + 2) * (wny + 4) + iy + 2
    there = padded.ravel()[base[:, None] + (v[:, 0] * (wny + 4) + v[:, 1])[None, :]]
    both = there >= 0
    indices = np.where(both, there, np.arange(m, dtype=np.int32)[:, None])
    lengths = resolution * np.hypot(v[:, 0], v[:, 1])
    weights = np.where(both, lengths[None, :], np.inf)
    graph = csr_matrix((weights.ravel(), indices.ravel(),
                        np.arange(0, nd * m + 1, nd, dtype=np.int64)), shape=(m, m))
    return cells, node, graph


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
        gcells, node, csr = _graph(free.reshape(wnx, wny), resolution)
        searched = len(gcells)
        dist = np.asarray(dijkstra(csr, directed=True, min_only=True, limit=limit,
                                   indices=node[flat[is_open]]))
        settled = np.isfinite(dist)
        settled_cells = gcells[settled]
        if _frontier(csr, settled, len(HEADING_VECTORS)):
            outside = limit  # farther positions: a lower bound
            values[open_ | ~known] = limit
        values.ravel()[settled_cells] = dist[settled]
    values.ravel()[flat] = 0.0  # a goal that is not open is its own distance 0 away
    return (FloorWindow(values, x0, y0, outside), searched), settled_cells


def _frontier(graph: csr_matrix, settled: np.ndarray, slots: int) -> bool:
    """Whether an open edge of ``graph`` leads from a settled node to one not settled.

    ``graph`` has ``slots`` entries a row (:func:`_graph`'s).
    """
    weights = graph.data.reshape(-1, slots)[settled]
    targets = graph.indices.reshape(-1, slots)[settled]
    return bool((~settled[targets[np.isfinite(weights)]]).any())

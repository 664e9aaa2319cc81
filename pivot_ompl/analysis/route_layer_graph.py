"""The layered route bound's graph: layers of raster cells, their joins, the lazy checks.

:mod:`~pivot_ompl.analysis.route_layers` says what the graph is and why it bounds every
plan's route; here it is built (:meth:`LayerGraph.build`) and searched round by round
(:meth:`LayerGraph.search`), its joins narrowed where the regrasps they stand for are refused.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import ndimage
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import grid_bound, neighbour_edges
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose

__all__ = ["CHECK_HALF", "GROW", "MAX_CELL", "MAX_CHECKS", "MAX_NODES", "MAX_ROUNDS", "MIN_CELL",
           "Components", "Edge", "LayerGraph", "LayerPair", "LayeredRoute"]

log = logging.getLogger(__name__)

#: Cells (over all layers together) at most.
MAX_NODES = 400_000
#: Smallest cell side (m): finer cells cost more than the grid's slack they save.
MIN_CELL = 0.08
#: Largest cell side (m); a floor that would need larger ones is left to the plain bound.
MAX_CELL = 0.15
#: Rounds (graph searches) at most (where the route does not lengthen in the first few, the
#: places it changes layers at are mostly where regrasps may happen).
MAX_ROUNDS = 3
#: Regrasp parts asked about at most (a few milliseconds each).
MAX_CHECKS = 1500
#: Cells the layers and their joins are grown by (:mod:`~pivot_ompl.analysis.route_layers`).
GROW = 2
#: Added to distances (m): keeps the joins on the safe side of round-off.
ROUND_OFF = 1e-7
#: Half the side (m) of the square round a layer change in which its regrasps are asked about
#: (small enough for the walk relaxation's samples).
CHECK_HALF = 0.25

#: Each node's layer and each layer's footprint (a polygon).
Components = tuple[dict[int, int], list[BaseGeometry]]
#: A regrasp edge of the relaxation: its two pieces (node indices) and its name.
Edge = tuple[int, int, Hashable]


@dataclass(frozen=True)
class LayeredRoute:
    """Outcome of :func:`~pivot_ompl.analysis.route_layers.layered_route`.

    Attributes:
        route: lower bound (m) on any plan's box route; ``None`` when no layered route joins
            start and goal (only a relaxation that refutes itself could say so).
        layers: transfer components used as layers.
        cell: the raster's cell side (m).
        rounds: graph searches made.
        checked: regrasp edges checked by ``allowed`` here.
        complete: every layer change of the last route is at an allowed regrasp.
        seconds: wall-clock time (s).
        stopped: the stop ended the rounds (the route is a proof, maybe a weaker one).
    """

    route: float | None
    layers: int
    cell: float
    rounds: int
    checked: int
    complete: bool
    seconds: float
    stopped: bool = False


@dataclass
class LayerPair:
    """The regrasps between two layers and the cells where the graph joins them."""

    edges: list[tuple[int, int, Hashable]]
    cells: np.ndarray
    open: dict[int, BaseGeometry] = field(default_factory=dict)
    boxes: np.ndarray | None = None

    def near(self, pieces: Sequence[BaseGeometry], box: tuple[float, float, float, float]
             ) -> list[int]:
        """The regrasps whose pieces' bounding boxes both meet ``box`` (open parts made)."""
        if self.boxes is None:
            b = np.array([[*pieces[u].bounds, *pieces[v].bounds] for u, v, _ in self.edges])
            self.boxes = np.column_stack([np.maximum(b[:, 0], b[:, 4]),
                                          np.maximum(b[:, 1], b[:, 5]),
                                          np.minimum(b[:, 2], b[:, 6]),
                                          np.minimum(b[:, 3], b[:, 7])])
        c = self.boxes
        hit = np.flatnonzero((c[:, 0] <= box[2]) & (c[:, 2] >= box[0]) & (c[:, 1] <= box[3])
                             & (c[:, 3] >= box[1]))
        for e in hit.tolist():
            if e not in self.open:
                u, v, _ = self.edges[e]
                self.open[e] = pieces[u].intersection(pieces[v])
        return hit.tolist()


@dataclass
class LayerGraph:
    """The layered graph: the raster, each node's layer, the layers' moves and joins."""

    raster: FloorRaster
    pieces: Sequence[BaseGeometry]
    layer_of: dict[int, int]
    masks: list[np.ndarray]
    moves: tuple[np.ndarray, np.ndarray, np.ndarray]
    pairs: dict[tuple[int, int], LayerPair]

    @classmethod
    def build(cls, pieces: Sequence[BaseGeometry], regrasps: Sequence[Edge],
              bounds: tuple[float, float, float, float], poll: Callable[[], None],
              components: Components, min_cell: float = MIN_CELL) -> LayerGraph | None:
        """The layers of the components reached, joined where their footprints meet.

        ``min_cell``: the raster's smallest cell side (m; larger where the layers need it).

        A pair's joins start as every cell of both layers (a superset of its regrasps'
        cells, no region computed) and are narrowed as its regrasps are refused.
        """
        layer_of, unions = components
        count = len(unions)
        raster = FloorRaster(bounds, min_cell=min_cell, max_cells=MAX_NODES // max(1, count))
        if raster.cell > MAX_CELL:
            log.debug("layered route bound skipped: %d layers need cells of %.3f m", count,
                      raster.cell)
            return None
        masks = []
        for union in unions:
            poll()
            mask = np.zeros(raster.shape, dtype=bool)
            mask.ravel()[_meeting(raster, [union], grow=GROW)] = True
            masks.append(mask)
        cells = masks[0].size
        r, k, w = [], [], []
        for i, mask in enumerate(masks):
            poll()
            a, b, steps = neighbour_edges(mask, poll=poll)
            r.append(a + i * cells)
            k.append(b + i * cells)
            w.append(raster.cell * steps)
        moves = (np.concatenate(r), np.concatenate(k), np.concatenate(w))
        pairs: dict[tuple[int, int], LayerPair] = {}
        for u, v, name in regrasps:
            if u in layer_of and v in layer_of and layer_of[u] != layer_of[v]:
                key = (min(layer_of[u], layer_of[v]), max(layer_of[u], layer_of[v]))
                if key not in pairs:
                    pairs[key] = LayerPair([], np.flatnonzero(masks[key[0]] & masks[key[1]]))
                pairs[key].edges.append((u, v, name))
        return cls(raster, pieces, layer_of, masks, moves, pairs)

    @property
    def count(self) -> int:
        """Layers."""
        return len(self.masks)

    def search(self, allowed: Callable[[Hashable, BaseGeometry], bool], starts: Sequence[int],
               goals: Sequence[int], start: Pose, goal: Pose, poll: Callable[[], None],
               max_rounds: int, max_checks: int, t0: float) -> LayeredRoute | None:
        """The rounds of :mod:`~pivot_ompl.analysis.route_layers`."""
        cells = self.masks[0].size
        ny = self.raster.shape[1]
        ends = []
        for p in (start, goal):
            i, j = self.raster.index(p[0], p[1])
            ends.append(i * ny + j)
        src = sorted({self.layer_of[u] * cells + ends[0] for u in starts if u in self.layer_of})
        dst = np.array(sorted({self.layer_of[u] * cells + ends[1] for u in goals
                               if u in self.layer_of}), dtype=np.int64)
        if not src or not len(dst):
            return None
        best: float | None = None
        rounds = checked = 0
        complete = False
        stopped = False
        while rounds < max_rounds:
            try:
                poll()
                dist, pred, _ = dijkstra(self._graph(), directed=False, indices=src,
                                         min_only=True, return_predecessors=True)
                rounds += 1
                end = int(dst[np.argmin(dist[dst])])
                if not math.isfinite(dist[end]):
                    break
                found = grid_bound(float(dist[end]), self.raster.cell)
                best = found if best is None else max(best, found)
                refuted = False
                for a, b, cell in self._changes(pred, end, cells):
                    ok, spent = self._check((min(a, b), max(a, b)), cell, allowed, poll,
                                            max_checks - checked)
                    checked += spent
                    refuted |= not ok
                if not refuted or checked >= max_checks:
                    complete = True
                    break
            except Interrupted:
                if best is None:
                    raise
                stopped = True
                break
        seconds = time.perf_counter() - t0
        log.debug("layered route %s m: %d layers, cell %.3f m, %d rounds, %d regrasps checked, "
                  "%.2f s", best, self.count, self.raster.cell, rounds, checked, seconds)
        return LayeredRoute(best, self.count, self.raster.cell, rounds, checked, complete,
                            seconds, stopped)

    def _graph(self) -> csr_matrix:
        """The layers' moves and the zero-cost joins of every pair.

        One COO matrix made CSR (its explicit zeros stay edges; a sum of sparse matrices
        would drop them).
        """
        cells = self.masks[0].size
        r, c, w = [self.moves[0]], [self.moves[1]], [self.moves[2]]
        for (a, b), pair in self.pairs.items():
            r.append(a * cells + pair.cells)
            c.append(b * cells + pair.cells)
            w.append(np.zeros(len(pair.cells)))
        n = self.count * cells
        return coo_matrix((np.concatenate(w), (np.concatenate(r), np.concatenate(c))),
                          shape=(n, n)).tocsr()

    @staticmethod
    def _changes(pred: np.ndarray, end: int, cells: int) -> list[tuple[int, int, int]]:
        """The layer changes ``(layer from, layer to, cell)`` along the route ending at ``end``."""
        out = []
        v = end
        while pred[v] >= 0:
            u = int(pred[v])
            if u // cells != v // cells:
                out.append((u // cells, v // cells, v % cells))
            v = u
        return out

    def _check(self, change: tuple[int, int], cell: int,
               allowed: Callable[[Hashable, BaseGeometry], bool], poll: Callable[[], None],
               budget: int) -> tuple[bool, int]:
        """Ask the regrasps near a layer change at ``cell``; ``(it may happen, checks made)``.

        ``change``: the two layers (the change may happen when one of their pair's regrasps
        may in the cell's square). For every pair with an open part within reach of the
        cell, its regrasps are asked about their open parts in squares of side ``2``
        :data:`CHECK_HALF`: the cell's first, then, while every regrasp of a square is
        refused, its neighbours (a flood over the squares the open parts meet, so a place
        where no regrasp can happen is cut out in one round). A part refused is cut out of
        the regrasp's open part, and the pair's joins there are narrowed to the cells near
        the open parts left. At most ``budget`` checks.
        """
        x, y = float(self.raster.gx.ravel()[cell]), float(self.raster.gy.ravel()[cell])
        reach = self._reach
        some, spent = False, 0
        for key, pair in self.pairs.items():
            if not pair.near(self.pieces, (x - reach, y - reach, x + reach, y + reach)):
                continue
            todo, seen, cut = [(0, 0)], {(0, 0)}, []
            while todo and spent < budget:
                di, dj = todo.pop(0)
                cx, cy = x + 2.0 * CHECK_HALF * di, y + 2.0 * CHECK_HALF * dj
                half = CHECK_HALF + ROUND_OFF  # asked and cut alike: no sliver left between
                box = (cx - half, cy - half, cx + half, cy + half)
                square = shapely.box(*box)
                may = met = False
                for e in pair.near(self.pieces, box):
                    part = pair.open[e].intersection(square)
                    if part.is_empty:
                        continue
                    met = True
                    poll()
                    spent += 1
                    if allowed(pair.edges[e][2], part):
                        may = True
                        break
                    pair.open[e] = pair.open[e].difference(square)
                    cut.append(box)
                some |= may and (di, dj) == (0, 0) and key == change
                if may or not met:
                    continue
                for step in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1),
                             (-1, -1)):
                    nxt = (di + step[0], dj + step[1])
                    if nxt not in seen:
                        seen.add(nxt)
                        todo.append(nxt)
            if cut:
                self._narrow(key, cut)
        return some, spent

    @property
    def _reach(self) -> float:
        """How far (m) a join's cell may lie from its regrasp's region (:func:`_meeting`)."""
        return self.raster.half_diag + GROW * self.raster.cell * math.sqrt(2.0) + ROUND_OFF

    def _narrow(self, key: tuple[int, int], cut: list[tuple[float, float, float, float]]
                ) -> None:
        """Drop the pair's joins near the squares ``cut`` that no open part comes near."""
        pair, reach = self.pairs[key], self._reach
        x0, y0 = min(c[0] for c in cut) - reach, min(c[1] for c in cut) - reach
        x1, y1 = max(c[2] for c in cut) + reach, max(c[3] for c in cut) + reach
        gx, gy = self.raster.gx.ravel()[pair.cells], self.raster.gy.ravel()[pair.cells]
        inside = (gx >= x0) & (gx <= x1) & (gy >= y0) & (gy <= y1)
        if not inside.any():
            return
        zone = (x0 - reach, y0 - reach, x1 + reach, y1 + reach)
        parts = [pair.open[e] for e in pair.near(self.pieces, zone) if not pair.open[e].is_empty]
        keep = np.ones(len(pair.cells), dtype=bool)
        idx = np.flatnonzero(inside)
        if parts:
            union = shapely.union_all([g.intersection(shapely.box(*zone)) for g in parts])
            shapely.prepare(union)
            keep[idx] = shapely.dwithin(union, shapely.points(gx[idx], gy[idx]), reach)
        else:
            keep[idx] = False
        pair.cells = pair.cells[keep]


def _meeting(raster: FloorRaster, regions: list[BaseGeometry], *, grow: int) -> np.ndarray:
    """Flat indices of the cells near ``regions``, found in their window.

    The cells within ``grow`` cells of one whose centre lies within half a diagonal of a
    region: a superset of the cells meeting them, grown.
    """
    regions = [g for g in regions if not g.is_empty]
    if not regions:
        return np.zeros(0, dtype=np.int64)
    region = shapely.union_all(regions)
    wi, wj = raster.window(region)
    gx, gy = raster.gx[wi, wj], raster.gy[wi, wj]
    shapely.prepare(region)
    near = shapely.dwithin(region, shapely.points(gx.ravel(), gy.ravel()), raster.half_diag)
    nx, ny = raster.shape
    i0, j0 = max(0, wi.start - grow), max(0, wj.start - grow)
    i1, j1 = min(nx, wi.stop + grow), min(ny, wj.stop + grow)
    block = np.zeros((i1 - i0, j1 - j0), dtype=bool)
    block[wi.start - i0:wi.stop - i0, wj.start - j0:wj.stop - j0] = near.reshape(gx.shape)
    block = ndimage.binary_dilation(block, structure=np.ones((2 * grow + 1,) * 2, dtype=bool))
    ii, jj = np.nonzero(block)
    return (ii + i0) * ny + (jj + j0)

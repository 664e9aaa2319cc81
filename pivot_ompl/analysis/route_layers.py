"""A route bound that knows where regrasps may happen: one layer of cells per transfer component.

The relaxation of :mod:`~pivot_ompl.analysis.regrasp_bound` joins its free pieces by
transfers (free) and regrasps (allowed only where the walk relaxation admits a walk round the
resting box). The pieces joined by transfers alone fall into *transfer components*: a plan's
transfer phase (one grasp, the box moving with the robot) stays inside one component, so the
box's route during it lies in the component's *footprint* (the union of its pieces'
positions); a regrasp passes from one component to another only at a point shared by two of
their pieces whose regrasp edge is allowed (the relaxation's own condition, sound); a regrasp
between pieces of one component changes nothing here.

**The layered graph.** One layer per component reached by the relaxation, over a raster of
cells (:class:`~pivot_ompl.analysis.raster.FloorRaster`): a layer holds the cells that meet
its footprint, joined by :func:`~pivot_ompl.analysis.route_bound.route_on`'s 16-neighbour
moves; two layers are joined at no cost at the cells that meet an allowed regrasp region
between them. Both sets are grown by :data:`GROW` cells (supersets: the grid path that bounds
a continuous route, built as :func:`~pivot_ompl.analysis.route_bound.route_on`'s argument
builds it, visits cells within two cells of the route's points in their order, so it may
change layers at a vertex near, not at, the regrasp point). Every plan's box route, cut at its
regrasps, is then a path of this graph from a start layer to a goal layer, and the shortest
one, reduced by the grid's slack (:func:`~pivot_ompl.analysis.route_bound.grid_bound`), is a
lower bound of every plan's route whatever its regrasp count. Where the relaxation proves a
regrasp is needed, that route must pass a place where one is possible: the plain route
through the union of every piece (today's bound) does not know it.

**Lazily checked regrasps.** The walk relaxation is costly; a regrasp edge not checked yet is
taken as allowed (a superset again: every round's route is a proof). Round by round: the
shortest layered route; the regrasp edges its layer changes use are checked; where all those
a change could use are refused, its cells are removed and the next round starts. The rounds
end when every change of the route is allowed (``complete``), at :data:`MAX_ROUNDS`, or when
``should_stop`` says stop (polled between rounds and checks; the last route stands).

**Bounded cost.** At most :data:`MAX_NODES` cells over all layers (the raster coarsens with
the layers' count); where that needs cells larger than :data:`MAX_CELL` the bound is not
computed (``None``: the caller keeps the plain route bound).
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
from scipy.sparse.csgraph import connected_components, dijkstra
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import grid_bound, neighbour_edges
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose

__all__ = ["CHECK_HALF", "GROW", "MAX_CELL", "MAX_CHECKS", "MAX_NODES", "MAX_ROUNDS", "MIN_CELL",
           "LayeredRoute", "layered_route"]

log = logging.getLogger(__name__)

#: Cells (over all layers together) at most.
MAX_NODES = 400_000
#: Smallest cell side (m): finer cells cost more than the grid's slack they save.
MIN_CELL = 0.08
#: Largest cell side (m); a floor that would need larger ones is left to the plain bound.
MAX_CELL = 0.15
#: Rounds (graph searches) at most (where the route does not lengthen in the first few, the
#: places it changes layers at are mostly where regrasps may happen).
MAX_ROUNDS = 4
#: Regrasp parts asked about at most (a few milliseconds each).
MAX_CHECKS = 1500
#: Cells the layers and their joins are grown by (module docstring).
GROW = 2
#: Added to distances (m): keeps the joins on the safe side of round-off.
ROUND_OFF = 1e-7
#: Half the side (m) of the square round a layer change in which its regrasps are asked about
#: (small enough for the walk relaxation's samples).
CHECK_HALF = 0.25

#: A regrasp edge of the relaxation: its two pieces (node indices) and its name for
#: ``allowed``.
Edge = tuple[int, int, Hashable]



@dataclass(frozen=True)
class LayeredRoute:
    """Outcome of :func:`layered_route`.

    Attributes:
        route: lower bound (m) on any plan's box route; ``None`` when no layered route joins
            start and goal (only a relaxation that refutes itself could say so).
        layers: transfer components used as layers.
        cell: the raster's cell side (m).
        rounds: graph searches made.
        checked: regrasp edges checked by ``allowed`` here.
        complete: every layer change of the last route is at an allowed regrasp.
        seconds: wall-clock time (s).
    """

    route: float | None
    layers: int
    cell: float
    rounds: int
    checked: int
    complete: bool
    seconds: float


def layered_route(pieces: Sequence[BaseGeometry], transfers: Sequence[Sequence[int]],
                  regrasps: Sequence[Edge], allowed: Callable[[Hashable, BaseGeometry], bool], *,
                  reached: set[int], starts: Sequence[int], goals: Sequence[int],
                  start: Pose, goal: Pose, bounds: tuple[float, float, float, float],
                  should_stop: Callable[[], bool] | None = None,
                  max_rounds: int = MAX_ROUNDS, max_checks: int = MAX_CHECKS
                  ) -> LayeredRoute | None:
    """The layered route bound (module docstring) over the relaxation's pieces.

    Args:
        pieces: each node's free positions (a polygon, the floor's frame).
        transfers: each node's neighbours by a transfer.
        regrasps: the regrasp edges ``(u, v, name)``.
        allowed: whether the regrasp edge ``name`` may happen with the box in a part of its
            region (the walk relaxation: ``False`` proves it cannot there).
        reached: the nodes the relaxation reaches from the start (the others are left out).
        starts: the nodes holding the start pose.
        goals: the nodes holding the goal pose.
        start: the box's start pose.
        goal: the box's goal pose.
        bounds: the floor ``(xmin, ymin, xmax, ymax)``.
        should_stop: polled between the steps, rounds and checks.
        max_rounds: most graph searches.
        max_checks: most regrasp parts asked about.

    Returns:
        The bound, or ``None`` when the raster would need cells over :data:`MAX_CELL` or when
        stopped before the first route.
    """
    t0 = time.perf_counter()

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the layered route bound")

    try:
        layers = _Layers.build(pieces, transfers, regrasps, reached, bounds, poll)
        if layers is None:
            return None
        return layers.search(allowed, starts, goals, start, goal, poll, max_rounds, max_checks,
                             t0)
    except Interrupted:
        return None


@dataclass
class _Pair:
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
class _Layers:
    """The layered graph: the raster, each node's layer, the layers' moves and joins."""

    raster: FloorRaster
    pieces: Sequence[BaseGeometry]
    layer_of: dict[int, int]
    masks: list[np.ndarray]
    moves: tuple[np.ndarray, np.ndarray, np.ndarray]
    pairs: dict[tuple[int, int], _Pair]

    @classmethod
    def build(cls, pieces: Sequence[BaseGeometry], transfers: Sequence[Sequence[int]],
              regrasps: Sequence[Edge], reached: set[int],
              bounds: tuple[float, float, float, float], poll: Callable[[], None]
              ) -> _Layers | None:
        """The layers of the components reached, joined where their footprints meet.

        A pair's joins start as every cell of both layers (a superset of its regrasps'
        cells, no region computed) and are narrowed as its regrasps are refused.
        """
        n = len(pieces)
        rows = [u for u in range(n) for _ in transfers[u]]
        cols = [v for u in range(n) for v in transfers[u]]
        joined = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
        _, label = connected_components(joined, directed=False)
        comps = sorted({int(label[u]) for u in reached})
        index = {c: i for i, c in enumerate(comps)}
        layer_of = {u: index[int(label[u])] for u in reached}
        count = len(comps)
        raster = FloorRaster(bounds, min_cell=MIN_CELL, max_cells=MAX_NODES // max(1, count))
        if raster.cell > MAX_CELL:
            log.debug("layered route bound skipped: %d layers need cells of %.3f m", count,
                      raster.cell)
            return None
        masks = []
        for c in comps:
            poll()
            mask = np.zeros(raster.shape, dtype=bool)
            mask.ravel()[_meeting(raster, [pieces[u] for u in reached if label[u] == c],
                                  grow=GROW)] = True
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
        pairs: dict[tuple[int, int], _Pair] = {}
        for u, v, name in regrasps:
            if u in layer_of and v in layer_of and layer_of[u] != layer_of[v]:
                key = (min(layer_of[u], layer_of[v]), max(layer_of[u], layer_of[v]))
                if key not in pairs:
                    pairs[key] = _Pair([], np.flatnonzero(masks[key[0]] & masks[key[1]]))
                pairs[key].edges.append((u, v, name))
        return cls(raster, pieces, layer_of, masks, moves, pairs)

    @property
    def count(self) -> int:
        """Layers."""
        return len(self.masks)

    def search(self, allowed: Callable[[Hashable, BaseGeometry], bool], starts: Sequence[int],
               goals: Sequence[int], start: Pose, goal: Pose, poll: Callable[[], None],
               max_rounds: int, max_checks: int, t0: float) -> LayeredRoute | None:
        """The rounds of the module docstring."""
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
        while rounds < max_rounds:
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
        seconds = time.perf_counter() - t0
        log.debug("layered route %s m: %d layers, cell %.3f m, %d rounds, %d regrasps checked, "
                  "%.2f s", best, self.count, self.raster.cell, rounds, checked, seconds)
        return LayeredRoute(best, self.count, self.raster.cell, rounds, checked, complete,
                            seconds)

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

"""The regrasp and route lower bounds on the raster cover: fast on real floors, still sound.

The relaxation of :mod:`~pivot_ompl.analysis.regrasp_bound` (same yaw bins, bodies, erosions,
walk condition and search), with each bin's free positions covered by raster cells
(:mod:`~pivot_ompl.analysis.raster_cover`) instead of exact polygons: nodes are the labelled
pieces of free cells per bin and grasp; a transfer joins pieces of neighbouring bins that
share a cell, a regrasp pieces of two grasps in one bin that share a cell (checked by the
walk relaxation on the shared cells, lazily). Every piece of the polygon cover lies in one
piece of the raster cover, so every path of the exact relaxation is one here: the result is
at most the polygons' bound, itself at most any plan's regrasps. The route bound is the
shortest path (:func:`~pivot_ompl.analysis.route_bound.route_on`) through the cells of every
reached piece, and never below the straight line.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from pivot_ompl.analysis.piece_graph import PieceGraph
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.raster_cover import EPS, RasterCover, floor_raster, raster_cover
from pivot_ompl.analysis.regrasp_bound import RegraspBound, yaw_bins
from pivot_ompl.analysis.regrasp_walk import MAX_SAMPLES, SAMPLE, WalkRelaxation
from pivot_ompl.analysis.route_bound import route_on
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

log = logging.getLogger(__name__)

#: Default cell side (m); a larger floor gets larger cells
#: (:data:`~pivot_ompl.analysis.raster_cover.MAX_CELLS`).
CELL = 0.1
#: A shared region larger than this (m²) is allowed a regrasp without the walk check (which
#: answers "may" for regions needing more than its samples anyway; a quarter of them cover it).
WALK_AREA = 4.0 * MAX_SAMPLES * SAMPLE * SAMPLE


def raster_lower_bound(scene: Scene, *, cell: float = CELL, resolution: float | None = None,
                       tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                       walks: bool = True, should_stop: Callable[[], bool] | None = None,
                       cover: RasterCover | None = None,
                       graph: RasterGraph | None = None) -> RegraspBound:
    """Fewest regrasps any plan of ``scene`` needs, on the raster cover (module docstring).

    Args:
        scene: the scene.
        cell: the raster's cell side (m; at least, see :data:`MAX_CELLS`).
        resolution: largest erosion (m) of the rotation within a yaw bin; default half the
            cell (the two losses alike).
        tolerance: the swept checks' tolerance (m).
        clearance: distance (m) the checkers keep every body from the obstacles.
        walks: allow a regrasp only where the walking robot may get round the resting box.
        should_stop: polled once per layer and per regrasp checked.
        cover: the scene's :func:`~pivot_ompl.analysis.raster_cover.raster_cover` of these
            arguments when already built (``None``: built here).
        graph: ``cover``'s :func:`raster_graph` of these arguments when already built.

    Returns:
        A :class:`~pivot_ompl.analysis.regrasp_bound.RegraspBound` (``exhaustive`` False).
    """
    t0 = time.perf_counter()
    if cover is None:
        cover = raster_cover(scene, cell=cell, resolution=resolution, tolerance=tolerance,
                             clearance=clearance, should_stop=should_stop)
    if cover is None:
        raster = floor_raster(scene.bounds, cell)
        n = yaw_bins(scene, 0.5 * raster.cell if resolution is None else resolution)
        return _timed(RegraspBound(None, None, n, 0, 0.0, exhaustive=False), t0)
    raster, n, layers = cover.raster, cover.bins, cover.layers
    unknown = RegraspBound(None, None, n, 0, 0.0, exhaustive=False)
    try:
        joined = graph if graph is not None else raster_graph(
            scene, cover, tolerance=tolerance, clearance=clearance, walks=walks,
            should_stop=should_stop)
    except Interrupted:
        return _timed(unknown, t0)
    holding, total = joined.holding, joined.total
    try:
        best, reached = joined.graph.fewest_regrasps(
            holding(scene.start), set(holding(scene.goal)), joined.allowed, should_stop,
            check_beyond=False)
    except Interrupted:
        return _timed(unknown, t0)
    route, complete = None, True
    if best is not None:
        try:
            route = _route(scene, raster, layers, joined.base, reached, n, joined.layer,
                           should_stop)
        except Interrupted:
            complete = False
    seconds = time.perf_counter() - t0
    log.debug("raster regrasp bound %s: %d bins, cell %.3f m, %d pieces, %.2f s", best, n,
              raster.cell, total, seconds)
    return RegraspBound(best, best is not None, n, total, seconds, route, complete,
                        exhaustive=False)


@dataclass
class RasterGraph:
    """The relaxation's graph over a :class:`~pivot_ompl.analysis.raster_cover.RasterCover`.

    Attributes:
        graph: the pieces joined by transfers and regrasps.
        base: the first node of each ``(bin, grasp)`` (its pieces follow, label ``c`` at
            ``base + c - 1``).
        layer: the cover's layer ``(grasp % 2, bin)`` of a ``(bin, grasp)``.
        allowed: whether a regrasp edge is allowed (the walk relaxation, lazily).
        holding: the nodes holding a pose (every grasp).
        total: the number of nodes.
        walk: the walk relaxation the regrasps are checked by (built at the first call).
    """

    graph: PieceGraph
    base: dict[tuple[int, int], int]
    layer: Callable[[int, int], tuple[int, int]]
    allowed: Callable[[tuple[int, int, int, int, int]], bool]
    holding: Callable[[Pose], list[int]]
    total: int
    walk: Callable[[], WalkRelaxation]


def raster_graph(scene: Scene, cover: RasterCover, *, tolerance: float = SWEEP_TOLERANCE,
                 clearance: float = KEEP_CLEARANCE, walks: bool = True,
                 should_stop: Callable[[], bool] | None = None,
                 relaxation: WalkRelaxation | None = None,
                 pairs: dict | None = None) -> RasterGraph:
    """The pieces of ``cover`` joined as :func:`raster_lower_bound` joins them.

    ``should_stop`` is polled once per bin and raises :class:`~pivot_ompl.errors.Interrupted`.
    ``relaxation``: the walk relaxation to check regrasps by (built at its first use when ``None``;
    one of the same scene, bin width, tolerance and clearance may be shared by graphs).
    ``pairs``: a dict kept between graphs of covers sharing layers (the guided rounds'
    covers share every layer their window misses): the pieces two layers share are found
    once per pair of label arrays (:func:`shared_pairs`).
    """
    raster, n, layers = cover.raster, cover.bins, cover.layers
    half = n // 2

    def layer(b: int, k: int) -> tuple[int, int]:
        return k % 2, (b + half * (k // 2)) % n

    base: dict[tuple[int, int], int] = {}
    total = 0
    for b in range(n):
        for k in range(4):
            base[(b, k)] = total
            total += layers[layer(b, k)][1]
    graph = PieceGraph(np.ones(total).tolist())
    some = np.zeros(raster.shape[0] * raster.shape[1], dtype=bool)
    for lab, count in layers.values():
        if count:
            some |= lab.ravel() > 0
    cells = np.flatnonzero(some)  # free in some layer: the only cells two layers may share
    read: dict[tuple[int, int], np.ndarray] = {}
    pairs = {} if pairs is None else pairs

    def labels_at(lay: tuple[int, int]) -> np.ndarray:
        if lay not in read:
            read[lay] = layers[lay][0].ravel()[cells]
        return read[lay]

    def link(b1: int, k1: int, b2: int, k2: int, regrasp: bool) -> None:
        la, lb = layer(b1, k1), layer(b2, k2)
        ia, ib = shared_pairs(pairs, layers, la, lb, lambda: (labels_at(la), labels_at(lb)))
        us, vs = (ia + (base[(b1, k1)] - 1)).tolist(), (ib + (base[(b2, k2)] - 1)).tolist()
        if regrasp:
            graph.add_regrasps(us, vs, [(b1, k1, i, k2, j) for i, j in
                                        zip(ia.tolist(), ib.tolist(), strict=True)])
        else:
            graph.add_transfers(us, vs)

    for b in range(n):
        if should_stop is not None and should_stop():
            raise Interrupted("the raster bound's graph")
        for k in range(4):
            link(b, k, (b + 1) % n, k, False)
            for j in range(k + 1, 4):
                link(b, k, b, j, True)
    width = 2.0 * math.pi / n
    built: list[WalkRelaxation] = [] if relaxation is None else [relaxation]

    def walk() -> WalkRelaxation:
        if not built:
            built.append(WalkRelaxation(scene, width=width, tolerance=tolerance,
                                        clearance=clearance))
        return built[0]

    def allowed(edge: tuple[int, int, int, int, int]) -> bool:
        if not walks:
            return True
        b, k, i, j, c = edge
        ii, jj = shared_cells(cells, labels_at(layer(b, k)), i, labels_at(layer(b, j)), c,
                              raster.shape)
        if len(ii) * raster.cell * raster.cell > WALK_AREA:
            return True
        return may_regrasp_cells(walk(), raster, ii, jj, -math.pi + (b + 0.5) * width, k, j)

    def holding(pose: Pose) -> list[int]:
        b = cover.bin_of(pose[2])
        return [base[(b, k)] + c - 1 for k in range(4) for c in cover.holding(pose, k)]

    return RasterGraph(graph, base, layer, allowed, holding, total, walk)


def shared_cells(cells: np.ndarray, a: np.ndarray, i: int, b: np.ndarray, c: int,
                 shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The cells of piece ``i`` of one layer that are in piece ``c`` of another, in raster order.

    ``cells``: flat indices (ascending) of the cells free in some layer; ``a``, ``b``: the
    two layers' labels at those cells (every shared cell is free in both, so among them).
    """
    flat = cells[(a == i) & (b == c)]
    return flat // shape[1], flat % shape[1]


def _timed(bound: RegraspBound, t0: float) -> RegraspBound:
    return dataclasses.replace(bound, seconds=time.perf_counter() - t0)


def shared_pairs(pairs: dict, layers: dict[tuple[int, int], tuple[np.ndarray, int]],
                 la: tuple[int, int], lb: tuple[int, int],
                 read: Callable[[], tuple[np.ndarray, np.ndarray]]
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The labels ``(i, j)`` of layers ``la`` and ``lb`` that share a cell (:func:`_shared`).

    ``pairs``: the answers kept by layer pair, each with weak references to the two label
    arrays it was read from: kept while both are still the layers' arrays (the same arrays,
    the same answer), read again (``read()``: the two layers' labels at the same cells, as
    :func:`_shared` takes them) otherwise.
    """
    a, b = layers[la][0], layers[lb][0]
    kept = pairs.get((la, lb))
    if kept is not None and kept[0]() is a and kept[1]() is b:
        return kept[2], kept[3]
    ia, ib = _shared(*read(), layers[la][1], layers[lb][1])
    pairs[(la, lb)] = weakref.ref(a), weakref.ref(b), ia, ib
    return ia, ib


def _shared(a: np.ndarray, b: np.ndarray, count_a: int, count_b: int
            ) -> tuple[np.ndarray, np.ndarray]:
    """The pairs of labels ``(i, j)`` of two layers that share a cell (any shape, the same).

    ``count_a``, ``count_b``: the layers' piece counts. Sorted by ``i`` then ``j``. Counted
    in a table of every pair where it is no larger than the cells (the usual few hundred
    pieces a layer), else the cells' pairs are sorted.
    """
    m = count_b + 1
    if (count_a + 1) * m <= max(len(a), 1 << 16):
        keys = np.multiply(a, m, dtype=np.intp)
        keys += b
        seen = np.bincount(keys, minlength=(count_a + 1) * m)
        ia, ib = np.nonzero(seen.reshape(count_a + 1, m)[1:, 1:])
        return ia + 1, ib + 1
    both = (a > 0) & (b > 0)
    keys = a[both].astype(np.int64) * m + b[both]
    if len(keys) > 1:  # neighbouring cells mostly repeat a pair: sort each run's pair once
        keys = keys[np.concatenate(([True], keys[1:] != keys[:-1]))]
    keys = np.unique(keys)
    return keys // m, keys % m


def may_regrasp_cells(walk: WalkRelaxation, raster: FloorRaster, ii: np.ndarray,
                      jj: np.ndarray, yaw: float, k: int, j: int) -> bool:
    """The walk relaxation's answer for the cells ``(ii, jj)`` of ``raster`` (in raster order).

    Their polygon is built only the first time these cells are asked (a graph's regrasp
    edges, and the guided bound's rounds, ask the same shared cells again and again).
    """
    key = (raster.origin, raster.cell, raster.shape, ii.tobytes(), jj.tobytes())
    return walk.may_regrasp_cells(key, lambda: cells_region(raster, ii, jj), yaw, k, j)


def cells_region(raster: FloorRaster, ii: np.ndarray, jj: np.ndarray) -> shapely.Geometry:
    """The union of the cells ``(ii, jj)`` of ``raster`` as one polygon (or multi-polygon)."""
    (x0, y0), h = raster.origin, raster.cell
    xs, ys = x0 + ii * h, y0 + jj * h
    return shapely.union_all(shapely.box(xs - EPS, ys - EPS, xs + h + EPS, ys + h + EPS))


def _route(scene: Scene, raster: FloorRaster, layers: dict, base: dict, reached: set[int],
           n: int, layer: Callable[[int, int], tuple[int, int]],
           should_stop: Callable[[], bool] | None) -> float | None:
    """Shortest route (m) through the cells of the reached pieces, at least the straight line."""
    ids = np.array(sorted(reached), dtype=np.int64)
    keys = sorted(base.items(), key=lambda kv: kv[1])
    starts = np.array([v for _, v in keys], dtype=np.int64)
    where = np.searchsorted(starts, ids, side="right") - 1
    wanted: dict[tuple[int, int], set[int]] = {}
    for idx, pos in zip(ids.tolist(), where.tolist(), strict=True):
        (b, k), first = keys[pos]
        wanted.setdefault(layer(b, k), set()).add(idx - first + 1)
    mask = np.zeros(raster.shape, dtype=bool)
    for lay, labels in wanted.items():
        if should_stop is not None and should_stop():
            raise Interrupted("the raster route bound")
        lab = layers[lay][0]
        mask |= np.isin(lab, np.fromiter(labels, dtype=np.int32)) & (lab > 0)

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the raster route bound")

    route = route_on(raster, mask, scene.start, scene.goal, poll=poll)
    if route is None:
        return None
    return max(route, math.dist(scene.start[:2], scene.goal[:2]))

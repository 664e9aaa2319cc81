"""The raster regrasp bound with its necks refined: coarse cells and bins outside, fine inside.

:func:`refined_lower_bound` reads the relaxation of :mod:`~pivot_ompl.analysis.raster_bound`
on a mixed cover: the coarse cover's cells outside a window round its necks, and inside it the
fine voxels of :mod:`~pivot_ompl.analysis.raster_refine` (half the cell, a fifth or so of the
yaw bin). Why every plan's path is a path of the graph (so the fewest regrasps on it are a
lower bound of any plan's):

* every state of a plan whose position lies in a closed cell outside the window is in that
  cell of the coarse layer of its bin (the coarse cover's claim), and every one whose position
  lies in a closed fine cell of the window is in that fine voxel at its fine bin (the refined
  cover's claim); a position on the window's edge is in both;
* nodes are the pieces of the coarse layers *without the window's cells* (labelled again) and
  the components of the fine voxels (which already join moves within the window: 8-adjacent
  cells of a fine bin, and yaw crossings at a cell);
* a transfer leaving the window does so through a point of a fine cell and a touching coarse
  cell outside (their closed squares share the point) at one yaw, whose fine bin lies in that
  coarse bin: both free, so the fine component and the coarse piece are joined; transfers
  outside the window are the coarse graph's;
* a regrasp at a point of the window is in one fine cell free at the fine bin in both grasps'
  layers: the two components are joined by a regrasp there, allowed when the walk relaxation
  (:class:`~pivot_ompl.analysis.regrasp_walk.WalkRelaxation`, at the coarse bin's yaw and
  width, which hold the fine bin's) may walk round the box resting in those cells; one outside
  the window is the coarse graph's.

Grasp ``k + 2`` at yaw ``t`` is the layer of grasp ``k`` at ``t + pi`` (half the fine bins on):
one set of components per parity serves both grasps, as nodes of their own.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from pivot_ompl.analysis.piece_graph import PieceGraph
from pivot_ompl.analysis.raster_bound import (
    WALK_AREA,
    RasterGraph,
    may_regrasp_cells,
    raster_graph,
)
from pivot_ompl.analysis.raster_cover import RasterCover, piece_labels
from pivot_ompl.analysis.raster_refine import FineVoxels, neck_window, refine_cover
from pivot_ompl.analysis.regrasp_bound import RegraspBound
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
from pivot_ompl.analysis.route_bound import route_on
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

_EIGHT = np.ones((3, 3), dtype=bool)
#: Voxels read at a time where every voxel of a parity is read (bounds the temporaries).
_CHUNK = 1 << 18
#: The memo's key of the fine regrasp joins kept between rounds.
_REGRASPS = "regrasp joins"
#: The memo's key of the coarse layers' shared pieces kept between rounds (the layers a
#: window misses are the cover's own arrays every round).
_PAIRS = "layer pairs"


@dataclass
class RefinedGraph:
    """The mixed graph: the coarse pieces off the window, then the fine components.

    Attributes:
        coarse: the coarse graph (its cover's layers without the window's cells), extended
            in place by the fine nodes and joins.
        cover: the coarse cover without the window's cells.
        fine: the fine voxels of the window.
        fine_base: per grasp, the node of its first fine component.
        allowed: whether a regrasp edge (coarse or fine) is allowed.
    """

    coarse: RasterGraph
    cover: RasterCover
    fine: FineVoxels
    fine_base: list[int]
    allowed: Callable[[tuple[int, int, int, int, int]], bool]

    def holding(self, pose: Pose) -> list[int]:
        """The nodes (coarse and fine, every grasp) whose cells hold ``pose``."""
        out = list(self.coarse.holding(pose))
        for k in range(4):
            found = self.fine.lookup(k % 2, self.fine.holding_keys(pose, k))
            out += [self.fine_base[k] + int(c) for c in found if c >= 0]
        return out


def refined_graph(scene: Scene, cover: RasterCover, *, tolerance: float, clearance: float,
                  walks: bool = True, window: np.ndarray | None = None,
                  should_stop: Callable[[], bool] | None = None,
                  relaxation: WalkRelaxation | None = None, memo: dict | None = None
                  ) -> RefinedGraph | None:
    """The mixed graph of ``cover`` (module docstring); ``None`` when the window is empty.

    ``window``: the coarse cells to refine (default
    :func:`~pivot_ompl.analysis.raster_refine.neck_window`; any window is sound).
    ``should_stop`` raises :class:`~pivot_ompl.errors.Interrupted`; ``relaxation``: as
    :func:`~pivot_ompl.analysis.raster_bound.raster_graph`'s; ``memo``: as
    :func:`~pivot_ompl.analysis.raster_refine.refine_cover`'s.
    """
    window = neck_window(cover) if window is None else window
    if not window.any():
        return None
    fine = refine_cover(scene, cover, window, tolerance=tolerance, clearance=clearance,
                        should_stop=should_stop, memo=memo)
    layers = {}
    wi, wj = np.nonzero(window)
    for key, (lab, count) in cover.layers.items():
        if should_stop is not None and should_stop():
            raise Interrupted("the refined raster graph")
        if count and (lab[wi, wj] > 0).any():
            layers[key] = piece_labels((lab > 0) & ~window)
        else:
            layers[key] = (lab, count)
    outside = RasterCover(cover.raster, cover.bins, layers, cover.pieces)
    coarse = raster_graph(scene, outside, tolerance=tolerance, clearance=clearance,
                          walks=walks, should_stop=should_stop, relaxation=relaxation,
                          pairs=None if memo is None else memo.setdefault(_PAIRS, {}))
    graph = coarse.graph
    fine_base, total = [], coarse.total
    for k in range(4):
        fine_base.append(total)
        total += fine.count[k % 2]
    graph.areas.extend([1.0] * (total - coarse.total))
    graph.zero.extend([] for _ in range(total - coarse.total))
    graph.one.extend([] for _ in range(total - coarse.total))
    _join_borders(fine, outside, coarse, fine_base)
    regions = _join_regrasps(fine, graph, fine_base, memo)
    width = 2.0 * math.pi / cover.bins
    split = fine.split

    def allowed(edge: tuple[int, int, int, int, int]) -> bool:
        if edge[0] >= 0:
            return coarse.allowed(edge)
        if not walks:
            return True
        cells, box_bin, k, j = regions[-1 - edge[0]]
        f = fine.raster
        if len(cells) * f.cell * f.cell > WALK_AREA:
            return True
        ii, jj = np.divmod(cells, f.shape[1])
        big = box_bin // split
        return may_regrasp_cells(coarse.walk(), f, ii, jj, -math.pi + (big + 0.5) * width,
                                 k, j)

    return RefinedGraph(coarse, outside, fine, fine_base, allowed)


def _join_borders(fine: FineVoxels, outside: RasterCover, coarse: RasterGraph,
                  fine_base: list[int]) -> None:
    """Transfers between fine components and the coarse pieces whose cells they touch."""
    window = fine.window
    nxc, nyc = window.shape
    ny = fine.raster.shape[1]
    n, half = outside.bins, outside.bins // 2
    border = window & ndimage.binary_dilation(~window, structure=_EIGHT)
    for g in (0, 1):
        keys = fine.keys[g]
        near = np.zeros(len(keys), dtype=bool)
        for s in range(0, len(keys), _CHUNK):  # no voxel-sized temporaries but this mask
            cell = keys[s:s + _CHUNK] % fine.cells
            near[s:s + _CHUNK] = border[(cell // ny) // 2, (cell % ny) // 2]
        cell = keys[near] % fine.cells
        a, b, comp = cell // ny, cell % ny, fine.labels[g][near]
        big = (keys[near] // fine.cells) // fine.split  # sorted, as the keys
        cuts = np.searchsorted(big, np.arange(n + 1))
        top = 1 + max((int(outside.layers[(g, bb)][1]) for bb in range(n)), default=0)
        found = []
        for di in (-1, 0):
            for dj in (-1, 0):
                ci, cj = a // 2 + a % 2 + di, b // 2 + b % 2 + dj
                ok = (ci >= 0) & (ci < nxc) & (cj >= 0) & (cj < nyc)
                ci, cj = np.clip(ci, 0, nxc - 1), np.clip(cj, 0, nyc - 1)
                ok &= ~window[ci, cj]
                lab = np.zeros(len(a), dtype=np.int64)
                for bb in range(n):
                    part = slice(int(cuts[bb]), int(cuts[bb + 1]))
                    if part.start < part.stop:
                        lab[part] = outside.layers[(g, bb)][0][ci[part], cj[part]]
                hit = ok & (lab > 0)
                found.append((comp[hit] * n + big[hit]) * top + lab[hit])
        rest, lab_ = np.divmod(np.unique(np.concatenate(found)), top)
        comps, bins = np.divmod(rest, n)
        us, vs = [], []
        for k in (g, g + 2):  # per join, grasp g's then grasp g + 2's
            first = np.array([coarse.base[((b2 - half * (k // 2)) % n, k)] for b2 in range(n)],
                             dtype=np.int64)
            us.append(fine_base[k] + comps)
            vs.append(first[bins] + lab_ - 1)
        coarse.graph.add_transfers(np.stack(us, axis=1).ravel().tolist(),
                                   np.stack(vs, axis=1).ravel().tolist())


def _join_regrasps(fine: FineVoxels, graph: PieceGraph, fine_base: list[int],
                   memo: dict | None = None) -> list[tuple[np.ndarray, int, int, int]]:
    """Regrasps between fine components sharing a voxel at one box bin; their regions.

    ``memo`` (the rounds' memo of :func:`~pivot_ompl.analysis.raster_refine.refine_cover`):
    the regions of the window ``fine`` grew from are kept, their components read through
    the merges, and only the new voxels are joined (a regrasp's voxels share one cell, and
    the new voxels' cells are new): a group of shared voxels may then be two regions, the
    earlier and the new one, each checked on its own (sound: a regrasp lies in one of them).
    """
    kept = None if memo is None else memo.get(_REGRASPS)
    if kept is not None and fine.earlier is not None and np.array_equal(kept[0], fine.earlier):
        _, regions, grasps, comps = kept
        comps = comps.copy()
        for g in (0, 1):
            merged = fine.grown[g].merged
            for col in (0, 1):
                on = grasps[:, col] % 2 == g
                comps[on, col] = merged[comps[on, col]]
        keys = {g: fine.grown[g].new for g in (0, 1)}
        labels = {g: fine.grown[g].new_labels for g in (0, 1)}
        regions = list(regions)
    else:
        keys, labels = fine.keys, fine.labels
        regions, grasps, comps = [], np.zeros((0, 2), np.int64), np.zeros((0, 2), np.int64)
    more, more_grasps, more_comps = _regrasp_regions(fine, keys, labels)
    regions += more
    grasps, comps = np.concatenate([grasps, more_grasps]), np.concatenate([comps, more_comps])
    if memo is not None:
        memo[_REGRASPS] = fine.window.copy(), regions, grasps, comps
    for i, ((k, j), (a, b)) in enumerate(zip(grasps.tolist(), comps.tolist(), strict=True)):
        graph.add(fine_base[k] + a, fine_base[j] + b, (-1 - i, k, a, j, b))
    return regions


def _regrasp_regions(fine: FineVoxels, keys: dict[int, np.ndarray],
                     labels: dict[int, np.ndarray]
                     ) -> tuple[list[tuple[np.ndarray, int, int, int]], np.ndarray, np.ndarray]:
    """The regions where voxels ``keys`` (labelled) of two grasps share a cell at a box bin.

    ``(regions, grasps, comps)``: each region's cells, box bin, grasps ``k < j``; its grasps
    and its two components, one row each.
    """
    regions: list[tuple[np.ndarray, int, int, int]] = []
    pairs: list[tuple[int, int, int, int]] = []
    per_grasp = [box_keys(keys[k % 2], k, fine.bins, fine.cells) for k in range(4)]
    for k in range(4):
        for j in range(k + 1, 4):
            shared, ia, ib = sorted_intersection(per_grasp[k], per_grasp[j])
            if not len(shared):
                continue
            ck, cj = labels[k % 2][ia], labels[j % 2][ib]
            big = (shared // fine.cells) // fine.split
            nb, nc = fine.bins // fine.split, fine.count[j % 2]
            group = (ck.astype(np.int64) * nc + cj) * nb + big
            # each group's cells, sorted and once: one sort of (group, cell) for all groups
            both = np.unique(group * fine.cells + shared % fine.cells)
            found, bounds = np.unique(both // fine.cells, return_index=True)
            bounds = np.append(bounds, len(both))
            cells = both % fine.cells
            for g, key in enumerate(found.tolist()):
                rest, bb = divmod(key, nb)
                a, b = divmod(rest, nc)
                regions.append((cells[bounds[g]:bounds[g + 1]], bb * fine.split, k, j))
                pairs.append((k, j, a, b))
    table = np.array(pairs, dtype=np.int64).reshape(-1, 4)
    return regions, table[:, :2], table[:, 2:]


def box_keys(keys: np.ndarray, grasp: int, bins: int, cells: int
             ) -> tuple[np.ndarray, np.ndarray]:
    """A parity's voxels keyed by the box's fine bin for ``grasp``, sorted, and their order.

    ``keys``: the parity's sorted voxel keys ``f * cells + cell`` (:class:`~pivot_ompl.
    analysis.raster_refine.FineVoxels`); grasp ``k + 2`` holds the box half a turn from
    grasp ``k`` (its box bin is ``f - bins / 2``). Returns the box keys sorted and, for
    each, its index in ``keys``: for the half-turn grasps, the two runs below and from the
    half turn, swapped (no sort).
    """
    if grasp < 2:
        return keys, np.arange(len(keys))
    half = bins // 2
    at = int(np.searchsorted(keys, half * cells))
    order = np.concatenate([np.arange(at, len(keys)), np.arange(at)])
    own = keys[order]
    return ((own // cells - half) % bins) * cells + own % cells, order


def sorted_intersection(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray]
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The keys in both ``a`` and ``b``, with their indices in each (as :func:`box_keys`).

    ``a``, ``b``: sorted unique keys and, per key, an index. The answer of
    ``numpy.intersect1d(ka, kb, assume_unique=True, return_indices=True)`` with the indices
    mapped through ``a``'s and ``b``'s, found by a search of ``b`` (no sort).
    """
    (ka, ia), (kb, ib) = a, b
    if not len(ka) or not len(kb):
        return (np.zeros(0, dtype=ka.dtype), np.zeros(0, dtype=np.int64),
                np.zeros(0, dtype=np.int64))
    pos = np.minimum(np.searchsorted(kb, ka), len(kb) - 1)
    hit = np.flatnonzero(kb[pos] == ka)
    return ka[hit], ia[hit], ib[pos[hit]]


def refined_lower_bound(scene: Scene, cover: RasterCover, *,
                        tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                        walks: bool = True, window: np.ndarray | None = None,
                        should_stop: Callable[[], bool] | None = None) -> RegraspBound | None:
    """The fewest regrasps on the mixed graph of ``cover``, with its route bound.

    A proof like the coarse cover's bound, and never below it in practice (the mixed graph's
    nodes lie in the coarse ones). ``cover``: the scene's coarse
    :func:`~pivot_ompl.analysis.raster_cover.raster_cover` (the same tolerance and
    clearance); ``window``: as :func:`refined_graph`. ``None`` when the window is empty or
    ``should_stop`` said stop.
    """
    t0 = time.perf_counter()
    try:
        joined = refined_graph(scene, cover, tolerance=tolerance, clearance=clearance,
                               walks=walks, window=window, should_stop=should_stop)
        if joined is None:
            return None
        best, reached = joined.coarse.graph.fewest_regrasps(
            joined.holding(scene.start), set(joined.holding(scene.goal)), joined.allowed,
            should_stop, check_beyond=False)
    except Interrupted:
        return None
    route, complete = None, True
    if best is not None:
        try:
            route = _route(scene, joined, reached, should_stop)
        except Interrupted:
            complete = False
    total = joined.fine_base[3] + joined.fine.count[1]
    return RegraspBound(best, best is not None, joined.fine.bins, total,
                        time.perf_counter() - t0, route, complete, exhaustive=False)


def _route(scene: Scene, joined: RefinedGraph, reached: set[int],
           should_stop: Callable[[], bool] | None) -> float | None:
    """Shortest route (m) through the coarse cells of the reached nodes (fine ones too)."""
    cover, coarse, fine = joined.cover, joined.coarse, joined.fine
    ids = np.array(sorted(reached), dtype=np.int64)
    mask = np.zeros(cover.raster.shape, dtype=bool)
    keys = sorted(coarse.base.items(), key=lambda kv: kv[1])
    starts = np.array([v for _, v in keys], dtype=np.int64)
    low = ids[ids < coarse.total]
    wanted: dict[tuple[int, int], list[int]] = {}
    for u, pos in zip(low.tolist(), (np.searchsorted(starts, low, side="right") - 1).tolist(),
                      strict=True):
        (b, k), first = keys[pos]
        wanted.setdefault(coarse.layer(b, k), []).append(u - first + 1)
    for lay, labels in wanted.items():
        if should_stop is not None and should_stop():
            raise Interrupted("the refined route bound")
        lab = cover.layers[lay][0]
        mask |= np.isin(lab, np.array(labels, dtype=np.int32)) & (lab > 0)
    ny = fine.raster.shape[1]
    for k in range(4):
        top = joined.fine_base[k] + fine.count[k % 2]
        comps = ids[(ids >= joined.fine_base[k]) & (ids < top)] - joined.fine_base[k]
        if not len(comps):
            continue
        cell = fine.keys[k % 2][np.isin(fine.labels[k % 2], comps)] % fine.cells
        mask[(cell // ny) // 2, (cell % ny) // 2] = True

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the refined route bound")

    route = route_on(cover.raster, mask, scene.start, scene.goal, poll=poll)
    if route is None:
        return None
    return max(route, math.dist(scene.start[:2], scene.goal[:2]))

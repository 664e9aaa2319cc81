"""The raster graph's joins and its cell-keyed walk answers: those of the plain definitions."""

from __future__ import annotations

import math

import numpy as np
from factories import shipped
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.raster_bound import cells_region, may_regrasp_cells, raster_graph
from pivot_ompl.analysis.raster_cover import RasterCover
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation

_EIGHT = np.ones((3, 3), dtype=bool)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), fill=st.floats(0.3, 0.9))
def test_the_graph_joins_exactly_the_pieces_that_share_a_cell(seed, fill):
    """Random layers: every transfer and regrasp edge joins two pieces sharing a cell, and
    every two such pieces (neighbouring bins, or two grasps in a bin) are joined."""
    rng = np.random.default_rng(seed)
    raster = FloorRaster((0.0, 0.0, 1.2, 0.9), min_cell=0.1, max_cells=10**6)
    bins = 4
    layers = {}
    for g in (0, 1):
        for b in range(bins):
            lab, count = ndimage.label(rng.random(raster.shape) < fill, structure=_EIGHT)
            layers[(g, b)] = (lab, int(count))
    cover = RasterCover(raster, bins, layers)
    joined = raster_graph(shipped("fig10"), cover)

    def piece(u: int) -> tuple[int, int, int]:
        (b, k), first = max(((key, v) for key, v in joined.base.items() if v <= u),
                            key=lambda kv: kv[1])
        return b, k, u - first + 1

    def cells(b: int, k: int, c: int) -> np.ndarray:
        return cover.labels(b, k) == c

    transfers = {(u, v) for u, near in enumerate(joined.graph.zero) for v in near}
    regrasps = {(u, v) for u, near in enumerate(joined.graph.one) for v, _ in near}
    want_transfers, want_regrasps = set(), set()
    for u in range(joined.total):
        for v in range(joined.total):
            (b1, k1, c1), (b2, k2, c2) = piece(u), piece(v)
            if not (cells(b1, k1, c1) & cells(b2, k2, c2)).any():
                continue
            if k1 == k2 and (b2 - b1) % bins in (1, bins - 1):
                want_transfers.add((u, v))
            elif b1 == b2 and k1 != k2:
                want_regrasps.add((u, v))
    assert transfers == want_transfers
    assert regrasps == want_regrasps


def test_cell_keyed_answers_are_those_of_the_cells_region():
    """Cell sets over fig10's floor, asked at two yaws and every grasp pair (each twice): the
    cell-keyed answer is the walk relaxation's answer for the cells' polygon."""
    scene = shipped("fig10")
    width = 2.0 * math.pi / 36
    raster = FloorRaster(scene.bounds, min_cell=0.1, max_cells=10**6)
    rng = np.random.default_rng(3)
    questions = []
    for _ in range(40):
        i, j = int(rng.integers(raster.shape[0] - 3)), int(rng.integers(raster.shape[1] - 3))
        ii, jj = np.nonzero(rng.random((3, 3)) < 0.6)
        for b in rng.choice(36, size=2, replace=False).tolist():
            questions += [(ii + i, jj + j, -math.pi + (b + 0.5) * width, k, g)
                          for k in range(4) for g in range(k + 1, 4)]
    plain = WalkRelaxation(scene, width=width, tolerance=0.002, clearance=0.01)
    want = [plain.may_regrasp(cells_region(raster, ii, jj), yaw, k, g)
            for ii, jj, yaw, k, g in questions]
    keyed = WalkRelaxation(scene, width=width, tolerance=0.002, clearance=0.01)
    for _ in range(2):
        assert [may_regrasp_cells(keyed, raster, ii, jj, yaw, k, g)
                for ii, jj, yaw, k, g in questions] == want
    assert any(want) and not all(want)

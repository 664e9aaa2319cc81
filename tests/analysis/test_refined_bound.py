"""The raster bound refined round its necks: sound (every valid state covered, never above the
exact polygons' bound) and stronger where the coarse cells lose a passage."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import shipped, turned_generated
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.raster_bound import raster_lower_bound
from pivot_ompl.analysis.raster_cover import raster_cover
from pivot_ompl.analysis.raster_refine import neck_window, refine_cover, turn_neck_window
from pivot_ompl.analysis.refined_bound import (
    box_keys,
    refined_graph,
    refined_lower_bound,
    sorted_intersection,
)
from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import rotate_scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE


@pytest.mark.parametrize(("name", "turn", "seed", "kind"),
                         [("slot", None, 1, "necks"), ("fig10", 0.7, 2, "necks"),
                          ("door", -0.4, 5, "turns")])
def test_the_fine_voxels_hold_every_valid_state_in_the_window(name, turn, seed, kind):
    """Valid states sampled in the refined cells, many within 3 cm of contact: each lies in a
    free fine voxel of its grasp (a blocked voxel would be a false proof)."""
    scene = shipped(name) if turn is None else rotate_scene(shipped(name), turn)
    cover = raster_cover(scene, cell=0.1)
    assert cover is not None
    window = neck_window(cover) if kind == "necks" else turn_neck_window(cover)
    fine = refine_cover(scene, cover, window, tolerance=SWEEP_TOLERANCE,
                        clearance=KEEP_CLEARANCE)
    ck = PivotChecker(scene, seed=0)
    rng = np.random.default_rng(seed)
    ii, jj = np.nonzero(window)
    (x0, y0), h = cover.raster.origin, cover.raster.cell
    near = valid = 0
    for _ in range(3000):
        k = int(rng.integers(len(ii)))
        q = (x0 + (ii[k] + rng.random()) * h, y0 + (jj[k] + rng.random()) * h,
             float(rng.uniform(-math.pi, math.pi)))
        assert fine.in_window(q)
        for g in range(4):
            c = ck.clearance(q, g)
            if c > 0:
                valid += 1
                near += c < 0.03
                assert fine.covers(q, g), (q, g, c)
    assert valid > 40 and near > 5


@pytest.mark.parametrize("seed", range(3))
def test_the_refined_bound_lies_between_the_coarse_and_the_exact_ones(seed):
    scene = turned_generated(seed)
    exact = regrasp_lower_bound(scene)
    coarse = raster_lower_bound(scene)
    cover = raster_cover(scene, cell=0.1)
    refined = refined_lower_bound(scene, cover)
    if refined is None:  # no neck: nothing refined
        return
    assert refined.solvable is not None
    if exact.solvable:
        assert refined.solvable and coarse.regrasps <= refined.regrasps <= exact.regrasps
        assert refined.shortest_route <= exact.shortest_route + 1e-6 or \
            refined.shortest_route <= math.dist(scene.start[:2], scene.goal[:2]) + 1e-9
    elif refined.solvable is False:
        assert exact.solvable is False


def test_the_refinement_finds_the_slot_the_coarse_cells_lose():
    """The shipped slot: the exact bound is 1; the 10 cm raster says 0; refined round its
    necks (5 cm cells, bins of 1 cm rotation erosion) it says 1."""
    scene = shipped("slot")
    assert raster_lower_bound(scene).regrasps == 0
    refined = refined_lower_bound(scene, raster_cover(scene, cell=0.1))
    assert refined is not None and refined.regrasps == 1 == regrasp_lower_bound(scene).regrasps
    assert refined.shortest_route >= math.dist(scene.start[:2], scene.goal[:2]) - 1e-9


def test_stopping_gives_nothing_and_an_empty_window_too():
    scene = shipped("slot")
    cover = raster_cover(scene, cell=0.1)
    assert refined_lower_bound(scene, cover, should_stop=lambda: True) is None
    empty = np.zeros(cover.raster.shape, dtype=bool)
    assert refined_lower_bound(scene, cover, window=empty) is None


@pytest.mark.parametrize("name", ["door", "slot"])
def test_a_grown_window_joins_the_same_fine_components_as_a_fresh_one(name):
    """Rounds of a growing window (the guided refinement's memo) join by regrasps the same
    fine components, at the same box bins, as the window refined afresh; every transfer
    and every count alike."""
    scene = shipped(name)
    cover = raster_cover(scene, cell=0.1)
    assert cover is not None
    small = neck_window(cover)
    big = small | turn_neck_window(cover)
    assert small.any() and (big & ~small).any()
    args = {"tolerance": SWEEP_TOLERANCE, "clearance": KEEP_CLEARANCE, "walks": False}
    memo: dict = {}
    assert refined_graph(scene, cover, window=small, memo=memo, **args) is not None
    grown = refined_graph(scene, cover, window=big, memo=memo, **args)
    fresh = refined_graph(scene, cover, window=big, **args)
    assert grown is not None and fresh is not None

    def joins(mixed):
        fine, base = mixed.fine, mixed.fine_base
        first = {g: {} for g in (0, 1)}  # each component named by its first voxel
        for g in (0, 1):
            for key, c in zip(fine.keys[g].tolist(), fine.labels[g].tolist(), strict=True):
                first[g].setdefault(c, key)

        def name_of(u):
            if u < base[0]:
                return -1, u  # a coarse piece: numbered alike (the same window)
            k = max(i for i in range(4) if base[i] <= u)
            return k, first[k % 2][u - base[k]]

        graph = mixed.coarse.graph
        one = {(name_of(u), name_of(v)) for u in range(len(graph.one)) for v, _ in graph.one[u]}
        zero = {(name_of(u), name_of(v)) for u in range(len(graph.zero)) for v in graph.zero[u]}
        return one, zero

    assert joins(grown) == joins(fresh)
    start, goal = grown.holding(scene.start), set(grown.holding(scene.goal))
    count, _ = grown.coarse.graph.fewest_regrasps(start, goal, grown.allowed, None)
    want, _ = fresh.coarse.graph.fewest_regrasps(fresh.holding(scene.start),
                                                 set(fresh.holding(scene.goal)), fresh.allowed,
                                                 None)
    assert count == want


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), half=st.integers(1, 12), cells=st.integers(1, 60),
       sizes=st.tuples(st.integers(0, 400), st.integers(0, 400)))
def test_the_grasps_shared_voxels_are_numpy_s_intersection(seed, half, cells, sizes):
    """Per pair of grasps, the voxels keyed by the box's bin that both hold, with their
    indices in the parities' keys: as ``numpy.intersect1d`` of the unsorted box keys."""
    rng = np.random.default_rng(seed)
    bins = 2 * half
    keys = [np.unique(rng.integers(0, bins * cells, n)) for n in sizes]

    def unsorted(k: int) -> np.ndarray:
        own = keys[k % 2]
        return ((own // cells - half * (k // 2)) % bins) * cells + own % cells

    for k in range(4):
        got = box_keys(keys[k % 2], k, bins, cells)
        assert np.all(np.diff(got[0]) > 0)
        assert np.array_equal(got[0], unsorted(k)[got[1]])
        for j in range(k + 1, 4):
            found = sorted_intersection(got, box_keys(keys[j % 2], j, bins, cells))
            expected = np.intersect1d(unsorted(k), unsorted(j), assume_unique=True,
                                      return_indices=True)
            assert all(np.array_equal(x, y) for x, y in zip(found, expected, strict=True))

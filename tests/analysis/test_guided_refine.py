"""The raster bound refined where its best path cheats: the path is a fewest-regrasp path, the
bound never exceeds the exact polygons' and only rises round by round, and plan's levels use it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import shipped, turned_generated
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import bound_cache
from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.bound_levels import scaled_lower_bound
from pivot_ompl.analysis.guided_paths import best_path
from pivot_ompl.analysis.guided_refine import GuidedRound, guided_lower_bound, thin_crossing
from pivot_ompl.analysis.piece_graph import PieceGraph
from pivot_ompl.analysis.raster_bound import raster_lower_bound
from pivot_ompl.analysis.raster_cover import raster_cover
from pivot_ompl.analysis.raster_refine import neck_window, refine_cover, turn_neck_window
from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

#: The exact polygon bounds of the shipped scenes (``pivot-ompl bound NAME --exhaustive``).
EXACT = {"slot": 1, "fig10": 2, "door": 1}


@st.composite
def graphs(draw):
    n = draw(st.integers(2, 14))
    pair = st.tuples(st.integers(0, n - 1), st.integers(0, n - 1))
    zero = draw(st.lists(pair, max_size=2 * n))
    one = draw(st.lists(pair, max_size=2 * n))
    banned = draw(st.sets(st.integers(0, max(0, len(one) - 1))))
    starts = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=2))
    goals = draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=2))
    return n, zero, one, banned, starts, goals


@given(graphs())
@settings(max_examples=200, deadline=None)
def test_the_best_path_has_the_fewest_allowed_regrasps(case):
    n, zero, one, banned, starts, goals = case

    def build() -> PieceGraph:
        g = PieceGraph([1.0] * n)
        for u, v in zero:
            g.add(u, v, None)
        for i, (u, v) in enumerate(one):
            g.add(u, v, (i, 0, 0, 0, 0))
        return g

    def allowed(e):
        return e[0] not in banned

    count, path = best_path(build(), starts, goals, allowed)
    want, _ = build().fewest_regrasps(starts, goals, allowed, None)
    assert count == want
    if count is None:
        assert path == []
        return
    assert path[0] in starts and path[-1] in goals
    g = build()
    cost = 0
    for u, v in zip(path, path[1:], strict=False):
        if v in g.zero[u]:
            continue
        assert any(w == v and allowed(e) for w, e in g.one[u]), (u, v)
        cost += 1
    assert cost == count


def test_the_thin_parts_on_the_way_through_not_the_dead_ends():
    """Two rooms joined by a one-cell corridor, a one-cell spur off the first room: crossing
    from room to room refines the corridor, not the spur; with no way in, every thin part."""
    piece = np.zeros((40, 20), dtype=bool)
    piece[2:14, 2:14] = True      # room A
    piece[26:38, 2:14] = True     # room B
    piece[14:26, 7] = True        # the corridor
    piece[5, 14:19] = True        # a spur off room A
    enter = np.zeros_like(piece)
    leave = np.zeros_like(piece)
    enter[5, 5] = leave[30, 5] = True
    got = thin_crossing(piece, enter, leave)
    assert not (got & ~piece).any()
    assert got[14:26, 7].all() and not got[5, 15:19].any()
    every = thin_crossing(piece, np.zeros_like(piece), leave)
    assert every[14:26, 7].all() and every[5, 15:19].all()


@pytest.mark.parametrize("seed", range(4))
def test_the_guided_bound_lies_between_the_coarse_and_the_exact_ones(seed):
    scene = turned_generated(seed)
    exact = regrasp_lower_bound(scene)
    coarse = raster_lower_bound(scene)
    trace: list[GuidedRound] = []
    guided = guided_lower_bound(scene, trace=trace)
    assert guided is not None and guided.complete and guided.guided
    if exact.solvable is False:
        return  # any count (or "no plan") is below "no plan"
    assert guided.solvable and coarse.regrasps <= guided.regrasps <= exact.regrasps
    windows = [r.window for r in trace]
    assert windows == sorted(windows)  # each round only refines


@pytest.mark.parametrize("name", sorted(EXACT))
def test_the_shipped_scenes_stay_at_most_their_exact_bound(name):
    scene = shipped(name)
    coarse = raster_lower_bound(scene)
    guided = guided_lower_bound(scene)
    assert guided is not None
    assert coarse.regrasps <= guided.regrasps <= EXACT[name]
    if name == "slot":  # the slot the coarse cells lose is found
        assert coarse.regrasps == 0 and guided.regrasps == 1


def test_a_stop_keeps_the_rounds_done_and_is_never_complete():
    scene = shipped("fig10")
    full = guided_lower_bound(scene)
    assert full is not None
    assert guided_lower_bound(scene, should_stop=lambda: True) is None
    calls = [0]

    def soon() -> bool:
        calls[0] += 1
        return calls[0] > 400

    part = guided_lower_bound(scene, should_stop=soon)
    assert part is None or (not part.complete and not part.guided
                            and part.regrasps <= full.regrasps)


def test_plan_levels_refine_only_when_asked_and_below_the_target(monkeypatch, tmp_path):
    """The slot with the polygons ruled out by their time estimate: the raster says 0, the
    guided level 1 (its exact bound); kept unguided, a guided ask computes it again (the held
    poses' count, which would run in its place on so small a floor, ruled out)."""
    from pivot_ompl.analysis import bound_levels

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(bound_levels, "POSE_SECONDS", 0.0)
    monkeypatch.setattr(bound_levels, "LEVEL_SECONDS", 0.0)  # nor the finer rasters
    bound_cache.clear_memory()
    scene = shipped("slot")
    plain = scaled_lower_bound(scene, target=1, refine_seconds=0.0)
    assert plain.regrasps == 0 and not plain.guided
    guided = scaled_lower_bound(scene, target=1, refine_seconds=0.0, guided_seconds=math.inf)
    assert guided.regrasps == 1 and guided.guided and not guided.exhaustive
    reached = scaled_lower_bound(scene, target=0, refine_seconds=0.0, guided_seconds=math.inf)
    assert reached.guided is False  # the target already met: nothing to refine
    short = scaled_lower_bound(scene, target=1, refine_seconds=0.0, guided_seconds=1e-3)
    assert short.regrasps == 0 and not short.guided  # estimated not to fit: not started
    assert lower_bound(scene, target=1, refine_seconds=0.0).regrasps == 0
    kept = lower_bound(scene, target=1, refine_seconds=0.0, guided_seconds=math.inf)
    assert kept.regrasps == 1 and kept.guided
    bound_cache.clear_memory()  # from the disk now
    assert lower_bound(scene, target=1, refine_seconds=0.0, guided_seconds=math.inf).regrasps == 1


def test_a_growing_window_refined_again_gives_the_fresh_voxels():
    """The memo of the rounds: voxels of the earlier window reused, the result the same as a
    fresh refinement; a window not holding the earlier one starts afresh."""
    scene = shipped("door")
    cover = raster_cover(scene, cell=0.1)
    assert cover is not None
    small = neck_window(cover)
    big = small | turn_neck_window(cover)
    assert small.any() and (big & ~small).any()
    args = {"tolerance": SWEEP_TOLERANCE, "clearance": KEEP_CLEARANCE}
    memo: dict = {}
    refine_cover(scene, cover, small, memo=memo, **args)
    for window in (big, big & ~small):
        again = refine_cover(scene, cover, window, memo=memo, **args)
        fresh = refine_cover(scene, cover, window, **args)
        for g in (0, 1):
            assert np.array_equal(again.keys[g], fresh.keys[g])
            assert again.count[g] == fresh.count[g]
            # the same partition of the voxels, numbered alike or not
            pairs = np.unique(np.stack([again.labels[g], fresh.labels[g]]), axis=1)
            assert pairs.shape[1] == fresh.count[g]


def test_a_plan_with_regrasps_gets_the_guided_bound(monkeypatch, tmp_path):
    """plan's bounds on a floor whose polygons and finer rasters are estimated too slow (the
    slot, made to look so): the raster says 0; asked for, the guided 1, which later plans
    read from the cache; a plan without regrasps needs no refinement."""
    from pivot_ompl.analysis import bound_levels
    from pivot_ompl.analysis.plan_bounds import plan_bounds

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(bound_levels, "exhaustive_estimate", lambda *a, **k: math.inf)
    monkeypatch.setattr(bound_levels, "raster_estimate", lambda *a, **k: math.inf)
    bound_cache.clear_memory()
    scene = shipped("slot")
    assert plan_bounds(scene, 0)[0] == 0
    assert plan_bounds(scene, 2)[0] == 0  # plan's default: not refined
    assert plan_bounds(scene, 2, guided=True)[0] == 1
    bound_cache.clear_memory()  # a later plan reads the refined bound from the disk cache
    assert plan_bounds(scene, 2)[0] == 1

"""The regrasp bound relaxed in more than one frame keeps the strongest frame's proof."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.analysis import bound_cache
from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.bound_levels import scaled_lower_bound
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.wall_frame import wall_frame


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty memory cache and disk cache folder."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    bound_cache.clear_memory()
    return tmp_path


@pytest.fixture(scope="module")
def frames():
    """The turned ``gen:walls:3`` copy and its relaxation in the world's and facing frames."""
    scene = shipped("walls_3_turned")
    facing = wall_frame(scene, facing=True)
    assert facing is not None and wall_frame(scene) is None  # relaxed as it is by default
    return scene, scaled_lower_bound(scene, target=9), scaled_lower_bound(facing.scene, target=9)


def test_frames_disagree_and_the_larger_count_is_kept(fresh, frames):
    scene, world, facing = frames
    assert facing.regrasps is not None and world.regrasps is not None
    assert facing.regrasps < world.regrasps  # the layout's point: frames prove differently
    # a plan with more regrasps than any frame proves: every frame is tried
    got = lower_bound(scene, target=world.regrasps + 1, use_cache=False)
    assert got.regrasps == world.regrasps
    assert got.shortest_route == max(world.shortest_route, facing.shortest_route)


def test_plan_bound_is_the_larger_and_kept(fresh, frames):
    scene, world, facing = frames
    regrasps, route = plan_bounds(scene, world.regrasps + 1)
    assert regrasps == max(world.regrasps, facing.regrasps)
    assert route is not None and route >= max(world.shortest_route, facing.shortest_route)
    kept = bound_cache.cached_bound(scene)  # the merged proof, under the scene's own key
    assert kept is not None and kept.regrasps == regrasps
    assert kept.shortest_route == max(world.shortest_route, facing.shortest_route)


def test_other_frames_not_tried_once_the_plan_count_is_proven(fresh, frames, monkeypatch):
    scene, world, _ = frames
    calls = []
    real = scaled_lower_bound

    def counted(*a, **k):
        calls.append(1)
        return real(*a, **k)

    from pivot_ompl.analysis import bound_frames
    monkeypatch.setattr(bound_frames, "scaled_lower_bound", counted)
    assert lower_bound(scene, target=world.regrasps, use_cache=False).regrasps == world.regrasps
    assert calls == [1]

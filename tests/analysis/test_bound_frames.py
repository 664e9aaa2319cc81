"""The regrasp bound relaxed in more than one frame keeps the strongest frame's proof."""

from __future__ import annotations

import math

import pytest
from factories import shipped

from pivot_ompl.analysis import bound_cache
from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.bound_levels import scaled_lower_bound
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.wall_frame import wall_frame
from pivot_ompl.generate import rotate_scene


def _framed_bounds(monkeypatch) -> list:  # noqa: ANN001
    """The bounds of every frame's scene the relaxation runs on, in order (a spy)."""
    from pivot_ompl.analysis import bound_frames

    seen: list = []

    def spied(relaxed, **k):  # noqa: ANN001, ANN003, ANN202
        seen.append(relaxed.bounds)
        return scaled_lower_bound(relaxed, **k)

    monkeypatch.setattr(bound_frames, "scaled_lower_bound", spied)
    return seen


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


def test_the_walls_frame_is_tried_where_the_first_call_found_it_not_worth_its_cost(fresh,
                                                                                monkeypatch):
    scene = rotate_scene(shipped("door"), 0.5)
    turned = wall_frame(scene, worth=1.0)
    assert wall_frame(scene) is None and turned is not None  # over half the bounds' area
    seen = _framed_bounds(monkeypatch)
    lower_bound(scene, target=9, use_cache=False, refine_seconds=0.1)  # never reached
    assert scene.bounds in seen and turned.scene.bounds in seen


def test_a_plan_s_count_pays_a_finer_raster_from_the_refinement_s_time(fresh, monkeypatch):
    from pivot_ompl.analysis import bound_levels

    monkeypatch.setattr(bound_levels, "POSE_SECONDS", 0.0)  # the rasters, not the held poses
    scene = shipped("slot")  # 0 on the coarsest cells, 1 (its exact count) on finer ones
    assert scaled_lower_bound(scene, target=1, refine_seconds=0.0).regrasps == 0
    finer = scaled_lower_bound(scene, target=1, refine_seconds=0.0, guided_seconds=math.inf)
    assert finer.regrasps == 1 and not finer.guided  # a finer level, not the refinement
    # no plan's count to reach: the refinement's time is not spent on a finer level
    monkeypatch.setattr(bound_levels, "may_guide", lambda *a, **k: False)
    assert scaled_lower_bound(scene, refine_seconds=0.0, guided_seconds=math.inf).regrasps == 0


def test_a_large_floor_turned_in_the_world_is_relaxed_in_its_walls_frame_first(fresh,
                                                                              monkeypatch):
    from pivot_ompl.analysis.raster_cover import floor_raster
    from pivot_ompl.generate.layout import free_complement
    from pivot_ompl.generate.layout import make_scene as layout_scene

    bounds = (0.0, 0.0, 60.0, 60.0)  # a square hall: turned, its bounds hold 6600 m^2
    free = [(0.5, 0.5, 59.5, 29.0), (0.5, 31.0, 59.5, 59.5), (20.0, 28.0, 22.0, 32.0)]
    hall = layout_scene("square_hall", bounds, free_complement(bounds, free),
                        (10.0, 10.0, 0.0), (50.0, 50.0, 0.0))
    scene = rotate_scene(hall, 0.5)
    walls = wall_frame(scene, worth=1.0)
    assert wall_frame(scene) is None and walls is not None  # not worth it by area alone...
    cell = floor_raster(scene.bounds, 0.1).cell
    assert floor_raster(walls.scene.bounds, 0.1).cell < cell  # ...but finer cells there
    seen = _framed_bounds(monkeypatch)
    got = lower_bound(scene, use_cache=False)
    assert seen == [walls.scene.bounds] and got.solvable


def test_a_floor_drawn_square_to_its_walls_and_turned_is_relaxed_in_their_frame_first(
        fresh, monkeypatch):
    from pivot_ompl.analysis import bound_frames
    from pivot_ompl.scene.walls import aligned_share

    scene = rotate_scene(shipped("door"), 0.5)  # every wall turned alike
    walls = wall_frame(scene, worth=1.0)
    assert wall_frame(scene) is None and walls is not None
    assert aligned_share(scene.obstacles, walls.yaw) >= bound_frames.ALIGNED
    seen = _framed_bounds(monkeypatch)
    lower_bound(scene, use_cache=False)
    assert seen == [walls.scene.bounds]
    seen.clear()  # walls running in several directions: the world's frame first, as before
    layout = shipped("walls_3_turned")
    assert aligned_share(layout.obstacles, wall_frame(layout, worth=1.0).yaw) < 0.9
    lower_bound(layout, use_cache=False)
    assert seen == [layout.bounds]

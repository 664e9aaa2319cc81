"""The plan's bounds: as exact as the plan needs, each a proof (the disk relaxation's route)."""

from __future__ import annotations

import math
import time

import pytest
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.plan_bounds import disk_route, held_route, plan_bounds
from pivot_ompl.api import plan
from pivot_ompl.errors import InputError

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


def _wall_with_top_gap():
    """A wall at x = 4 from the floor's bottom edge up to y = 5: the way round is at the top."""
    return make_scene(obstacles=[{"type": "box", "center": [4.0, 2.5], "size": [0.2, 5.0],
                                  "yaw": 0.0, "height": 2.0}],
                      start=[1.5, 1.0, 0.0], goal=[6.5, 1.0, 0.0])


def test_the_disk_route_goes_round_the_wall_and_no_further_than_the_shortest_way():
    r = disk_route(_wall_with_top_gap())
    # any way passes over the wall's top (x 3.9..4.1, y >= 5): at least this long
    over = math.dist((1.5, 1.0), (3.9, 5.0)) + 0.2 + math.dist((4.1, 5.0), (6.5, 1.0))
    # and the box (0.6 m short side) goes this way, its centre 0.21 m from the wall's corners
    way = [(1.5, 1.0), (3.69, 5.21), (4.31, 5.21), (6.5, 1.0)]
    length = sum(math.dist(a, b) for a, b in zip(way, way[1:], strict=False))
    assert r is not None and 0.95 * over <= r <= length


@settings(max_examples=15, deadline=None)
@given(x=st.floats(1.0, 7.0), y=st.floats(1.0, 5.0), gx=st.floats(1.0, 7.0),
       gy=st.floats(1.0, 5.0))
def test_on_an_open_floor_the_disk_route_is_the_straight_line(x, y, gx, gy):
    scene = make_scene(start=[x, y, 0.0], goal=[gx, gy, 1.0])
    assert disk_route(scene) == pytest.approx(math.dist((x, y), (gx, gy)))


@pytest.mark.slow
@pytest.mark.parametrize("name", ["corridor", "slot", "cluttered_room"])
def test_no_plan_moves_its_box_less_than_the_disk_route(name):
    res = plan(shipped(name), time_limit=30.0, seed=0, bound=False)
    assert res.solved
    assert disk_route(shipped(name)) <= res.plan.extra["quality"]["route_length"]


def test_a_plan_without_regrasps_needs_no_relaxation():
    scene = shipped("cluttered_room")
    t0 = time.perf_counter()
    regrasps, route = plan_bounds(scene, 0)
    assert regrasps == 0 and route is not None
    assert time.perf_counter() - t0 < 1.5  # the relaxation takes ~2 s here


def test_a_plan_with_regrasps_carries_the_relaxations_bound():
    scene = shipped("slot")
    assert plan_bounds(scene, 1) == (1, lower_bound(scene).shortest_route)


def test_every_plan_on_a_large_open_floor_carries_its_proof_within_the_limit():
    scene = make_scene(bounds=[0.0, 0.0, 60.0, 40.0], start=[3.0, 3.0, 0.0],
                       goal=[56.0, 36.0, 0.0])
    limit = 8.0
    t0 = time.monotonic()
    res = plan(scene, time_limit=limit, seed=0)
    took = time.monotonic() - t0
    assert res.solved and took <= 1.05 * limit + 0.2, took
    q = res.plan.extra["quality"]
    assert q["regrasps_lower_bound"] == 0 == res.regrasps
    assert q["shortest_route"] == pytest.approx(math.dist((3.0, 3.0), (56.0, 36.0)))
    assert q["route_ratio"] is not None and q["route_ratio"] >= 1.0


def test_a_plan_without_regrasps_takes_the_disk_route_a_plan_of_its_scene_found(monkeypatch):
    import pivot_ompl.analysis.plan_bounds as bounds

    scene = make_scene(obstacles=[{"type": "box", "center": [4.0, 2.5], "size": [0.2, 5.0],
                                   "yaw": 0.0, "height": 2.0}],
                       start=[1.5, 1.0, 0.0], goal=[6.5, 1.25, 0.0])  # a scene of its own
    calls = []

    def counted(*args, **kwargs):
        calls.append(args)
        return held_route(*args, **kwargs)

    monkeypatch.setattr(bounds, "held_route", counted)
    stopped = plan_bounds(scene, 0, should_stop=lambda: True)
    assert stopped == (0, None) and len(calls) == 1  # stopped: nothing kept
    first = plan_bounds(scene, 0)
    assert first[1] is not None and len(calls) == 2
    assert plan_bounds(scene, 0, should_stop=lambda: True) == first and len(calls) == 2


@pytest.mark.parametrize("copy", ["turned", "mirrored"])
def test_a_turned_or_mirrored_fig10_keeps_its_exact_bound(copy, monkeypatch, tmp_path):
    """Regression: fig10 turned by 30 degrees or mirrored (its old bounds kept as walls, 15
    pieces) had the polygons estimated just over the levels' budget, so its plans carried
    the raster's 0 for the exact 2."""
    from pivot_ompl.analysis import bound_cache
    from pivot_ompl.generate import mirror_scene, rotate_scene

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    bound_cache.clear_memory()
    base = shipped("fig10")
    scene = (rotate_scene(base, math.radians(30.0)) if copy == "turned"
             else mirror_scene(base, 0.3))
    assert plan_bounds(scene, 2)[0] == 2


def _corridor_rooms():
    # four rooms joined by a tight corridor: the raster's bound (0) is below the plan's
    # regrasps and the polygons do not fit the plan's 2.5 s
    from pivot_ompl.generate import GeneratorParams, generate

    return generate("building", 0, params=GeneratorParams(
        rooms=4, layout="corridor", rotate=True, side_corridor=(0.87, 0.89),
        side_door=(1.0, 1.0))).scene


def test_a_plan_refines_the_bound_by_default_where_the_quick_one_proves_less(
        monkeypatch, tmp_path):
    """The refinement runs inside every plan whose regrasps the quick bounds do not prove,
    when it fits the limit (``prove=None``; on this small floor the held poses' count, in
    place of the guided raster: 3, the plan's, where the raster proves 0); ``prove=False``
    keeps the quick ones."""
    from pivot_ompl.analysis.bound_cache import cached_bound

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    scene = _corridor_rooms()
    quick = plan(scene, time_limit=30, seed=0, prove=False)
    assert quick.solved and quick.plan.regrasps > 0
    assert cached_bound(scene) is not None and not cached_bound(scene).held
    proved = plan(scene, time_limit=30, seed=0)
    assert proved.solved
    known = cached_bound(scene)
    assert known is not None and known.held and not known.guided and known.regrasps == 3
    assert proved.plan.extra["quality"]["regrasps_lower_bound"] == known.regrasps
    assert known.regrasps <= proved.plan.regrasps


def test_the_refinement_runs_by_estimate_unless_forced(monkeypatch, tmp_path):
    """By default the refinement (here the held poses' count) starts only when its estimate
    fits the time left; forced (``plan --prove``) it runs whatever the estimate."""
    from pivot_ompl.analysis import bound_cache
    from pivot_ompl.analysis.bound_cache import cached_bound

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    bound_cache.clear_memory()
    scene = _corridor_rooms()
    plan_bounds(scene, 2, guided=True, time_left=lambda: 0.01)
    assert cached_bound(scene) is not None and not cached_bound(scene).held
    plan_bounds(scene, 2, guided=True, time_left=lambda: 0.01, guided_by_estimate=False)
    assert cached_bound(scene) is not None and cached_bound(scene).held


def test_prove_needs_the_bounds():
    with pytest.raises(InputError, match="prove"):
        plan("slot", time_limit=5, bound=False, prove=True)
    with pytest.raises(InputError, match="prove"):
        plan("slot", time_limit=5, prove="yes")

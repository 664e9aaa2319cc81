"""Bounds computed once per scene geometry: memory and disk caches, route bound, the verb."""

from __future__ import annotations

import dataclasses
import math

import pytest
from factories import make_scene, scene_file, shipped

from pivot_ompl.analysis import bound_cache, bound_frames
from pivot_ompl.analysis.bound_cache import cache_dir, lower_bound, scene_key
from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.cli.main import main
from pivot_ompl.scene import BoxObstacle


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty memory cache and disk cache folder."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    bound_cache.clear_memory()
    return tmp_path


def test_key_follows_geometry_not_name():
    a = make_scene()
    assert scene_key(a) == scene_key(dataclasses.replace(a, name="other"))
    moved = dataclasses.replace(a, goal=(6.0, 3.1, 0.0))
    assert scene_key(a) != scene_key(moved)
    walled = dataclasses.replace(a, obstacles=(BoxObstacle((4.0, 3.0), (0.3, 6.0), 0.0, 2.0),))
    assert scene_key(a) != scene_key(walled)


def test_computed_once_then_read(fresh, monkeypatch):
    scene = make_scene()
    first = lower_bound(scene)
    assert first.regrasps == 0
    assert (cache_dir() / f"{scene_key(scene)}.json").is_file()
    calls = []
    monkeypatch.setattr(bound_frames, "scaled_lower_bound",
                        lambda *a, **k: calls.append(1) or first)
    assert lower_bound(scene) == first  # memory
    bound_cache.clear_memory()
    assert lower_bound(scene) == first  # disk
    assert not calls
    lower_bound(scene, use_cache=False)
    assert calls == [1]


def test_disk_cache_off_corrupt_and_stopped(fresh, monkeypatch):
    scene = make_scene()
    path = cache_dir() / f"{scene_key(scene)}.json"
    monkeypatch.setenv(bound_cache.CACHE_ENV, "0")
    lower_bound(scene)
    assert not path.exists()
    monkeypatch.delenv(bound_cache.CACHE_ENV)
    bound_cache.clear_memory()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("{not json")
    assert lower_bound(scene).regrasps == 0  # a corrupt file is recomputed
    stopped = make_scene(goal=[6.0, 2.0, 0.0])
    assert lower_bound(stopped, should_stop=lambda: True).solvable is None
    assert not (cache_dir() / f"{scene_key(stopped)}.json").exists()  # never kept


def test_route_bound_is_below_the_straight_line_and_close_to_it():
    scene = make_scene()
    d = math.dist(scene.start[:2], scene.goal[:2])
    r = regrasp_lower_bound(scene).shortest_route
    assert r is not None and 0.85 * d <= r <= d


def test_route_bound_goes_round_a_wall():
    """A wall across the floor with a gap at one end: the bound detours through the gap."""
    wall = BoxObstacle((3.75, 2.0), (0.3, 4.0), 0.0, 2.0)  # the gap: y 4..6
    scene = dataclasses.replace(make_scene(), obstacles=(wall,))
    r = regrasp_lower_bound(scene).shortest_route
    straight = math.dist(scene.start[:2], scene.goal[:2])
    assert r is not None and r > straight + 0.5


def test_verb_prints_the_bound_and_exit_codes(fresh, capsys):
    assert main(["bound", str(scene_file("slot"))]) == 0
    assert "at least 1 regrasp," in capsys.readouterr().out
    assert main(["bound", str(scene_file("enclosed")), "--no-cache"]) == 1
    assert "no plan exists" in capsys.readouterr().out
    assert main(["bound", "scenes/nope.yaml"]) == 2


def test_plan_reports_the_bounds_outside_its_time(fresh):
    from pivot_ompl.api import plan

    res = plan(shipped("slot"), time_limit=20.0, seed=0)
    q = res.plan.extra["quality"]
    assert q["regrasps_lower_bound"] == 1 <= q["regrasps"]
    assert q["route_ratio"] is not None and q["route_ratio"] >= 1.0
    assert q["route_length"] >= q["shortest_route"]
    assert "bound" in res.timings
    off = plan(shipped("slot"), time_limit=20.0, seed=0, bound=False)
    assert off.plan.extra["quality"]["regrasps_lower_bound"] is None

"""The gap-closed route kept on disk: read back by later processes, bad entries dropped."""

from __future__ import annotations

import json
import logging

import pytest
from factories import make_scene

from pivot_ompl.analysis.bound_cache import cache_dir
from pivot_ompl.analysis.plan_bounds import held_route, plan_bounds
from pivot_ompl.analysis.route_cache import forget_route, keep_route, kept_route


def _barrier(width: float):
    """A 1.5 m barrier at x 4-5.5 with a ``width`` m slot on the line from start to goal and a
    1.6 m door above it."""
    wall = {"type": "box", "yaw": 0.0, "height": 2.0}
    low, high = 3.0 - 0.5 * width, 3.0 + 0.5 * width
    return make_scene(bounds=[0.0, 0.0, 10.0, 6.0], start=[1.5, 3.0, 0.0], goal=[8.5, 3.0, 0.0],
                      obstacles=[{**wall, "center": [4.75, 0.5 * low], "size": [1.5, low]},
                                 {**wall, "center": [4.75, 0.5 * (high + 4.4)],
                                  "size": [1.5, 4.4 - high]}])


@pytest.fixture
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    return tmp_path


def _entries() -> list:
    return sorted(cache_dir().glob("*.route.json"))


def test_a_plans_gap_closed_route_is_kept_for_later_processes(own_cache):
    scene = _barrier(0.69)  # a scene of its own: the process's memo holds nothing of it
    assert kept_route(scene) is None
    route = plan_bounds(scene, 0)[1]
    assert route is not None and route == pytest.approx(held_route(scene).route)
    assert len(_entries()) == 1 and kept_route(scene) == route
    # another scene's entry is not this one's
    assert kept_route(_barrier(0.68)) is None


def test_a_kept_route_is_read_as_it_was_written_and_forgotten_on_request(own_cache):
    scene = _barrier(0.7)
    keep_route(scene, 9.25)
    assert kept_route(scene) == 9.25
    forget_route(scene)
    assert kept_route(scene) is None and _entries() == []


@pytest.mark.parametrize("doc", [
    "not json",
    json.dumps({"format": "pivot-route/1", "key": "another", "route": 9.0}),
    json.dumps({"format": "pivot-route/1", "key": None, "route": float("nan")}),
    json.dumps({"format": "pivot-route/1", "key": None, "route": 1e9}),
    json.dumps({"format": "pivot-route/1", "key": None, "route": True}),
    json.dumps({"format": "pivot-bound/1", "key": None, "route": 9.0}),
])
def test_a_bad_entry_is_discarded_with_a_warning(own_cache, doc, caplog):
    scene = _barrier(0.7)
    keep_route(scene, 9.0)
    [path] = _entries()
    key = json.loads(path.read_text())["key"]
    path.write_text(doc.replace("null", json.dumps(key)))
    with caplog.at_level(logging.WARNING):
        assert kept_route(scene) is None
    assert "route cache entry" in caplog.text and not path.exists()


def test_no_disk_entry_when_the_bound_cache_is_off(own_cache, monkeypatch):
    monkeypatch.setenv("PIVOT_OMPL_BOUND_CACHE", "0")
    scene = _barrier(0.7)
    keep_route(scene, 9.0)
    assert _entries() == [] and kept_route(scene) is None

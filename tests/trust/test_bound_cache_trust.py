"""The bound cache never lies (issue 43, class 3).

An entry answers only the key it carries, passes the checks a fresh result passes, is read
as a small regular file of this user's without blocking; anything else is discarded with
one warning and computed again. A cache that cannot be written only costs time.
"""

from __future__ import annotations

import json
import logging
import math
import os
import shutil
import time

import pytest
from factories import make_scene, scene_file
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import bound_cache
from pivot_ompl.analysis.bound_cache import bound_problem, cache_dir, lower_bound, scene_key
from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.scene import load_scene

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty memory cache and disk cache folder."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(bound_cache, "_memory", bound_cache.BoundedCache(4))
    return tmp_path


def _forget_memory(monkeypatch):
    monkeypatch.setattr(bound_cache, "_memory", bound_cache.BoundedCache(4))


def _entry(scene):
    return cache_dir() / f"{scene_key(scene)}.json"


def _warnings(caplog):
    return [r for r in caplog.records if r.levelno >= logging.WARNING
            and r.name == bound_cache.__name__]


def test_an_entry_copied_under_another_scenes_key_is_not_used(fresh, monkeypatch, capsys,
                                                               caplog):
    enclosed, slot = load_scene(scene_file("enclosed")), load_scene(scene_file("slot"))
    assert lower_bound(enclosed).solvable is False
    _entry(slot).write_bytes(_entry(enclosed).read_bytes())
    _forget_memory(monkeypatch)
    assert main(["bound", str(scene_file("slot"))]) == 0
    out = capsys.readouterr().out
    assert "at least 1 regrasp" in out and "no plan exists" not in out
    assert len(_warnings(caplog)) == 1 and "another key" in caplog.text
    assert json.loads(_entry(slot).read_text())["key"] == scene_key(slot)  # replaced


def _forge(scene, **bound):
    fields = {"regrasps": 0, "solvable": True, "bins": 64, "pieces": 10, "seconds": 0.1,
              "shortest_route": 4.2, **bound}
    doc = {"format": bound_cache.ENTRY_FORMAT, "key": scene_key(scene), "bound": fields}
    path = _entry(scene)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc))
    path.chmod(0o600)
    return path


BAD_BOUNDS = {
    "huge route": {"regrasps": 7, "shortest_route": 1e308},
    "negative regrasps": {"regrasps": -1},
    "fractional regrasps": {"regrasps": 0.5},
    "text regrasps": {"regrasps": "0"},
    "bool regrasps": {"regrasps": True},
    "regrasps beyond pieces": {"regrasps": 11},
    "text solvable": {"solvable": "yes"},
    "unknown solvable": {"solvable": None, "regrasps": None},
    "nan route": {"shortest_route": float("nan")},
    "negative route": {"shortest_route": -1.0},
    "route below the straight line": {"shortest_route": 0.5},
    "list route": {"shortest_route": [4.0]},
    "zero bins": {"bins": 0},
    "unsolvable with regrasps": {"solvable": False, "regrasps": 2},
    "negative seconds": {"seconds": -1.0},
}


@pytest.mark.parametrize("case", sorted(BAD_BOUNDS))
def test_an_entry_out_of_range_is_discarded_and_recomputed(fresh, monkeypatch, caplog, case):
    scene = make_scene()
    truth = lower_bound(scene, use_cache=False)
    _forge(scene, **BAD_BOUNDS[case])
    _forget_memory(monkeypatch)
    got = lower_bound(scene)
    assert got.regrasps == truth.regrasps and got.shortest_route == truth.shortest_route
    assert len(_warnings(caplog)) == 1
    assert lower_bound(scene) == got and len(_warnings(caplog)) == 1  # once


@pytest.mark.parametrize("text", ["", "{not json", "[1, 2]", '{"format": 1}', "NaN",
                                  '{"format": "pivot-bound/1", "key": "x", "bound": 3}',
                                  "\xff\xfe"])
def test_an_entry_of_no_shape_is_discarded(fresh, monkeypatch, caplog, text):
    scene = make_scene()
    path = _forge(scene)
    path.write_text(text, errors="surrogateescape")
    _forget_memory(monkeypatch)
    assert lower_bound(scene).regrasps == 0
    assert len(_warnings(caplog)) == 1


def test_an_entry_of_an_old_format_is_discarded(fresh, monkeypatch):
    scene = make_scene()
    path = _forge(scene)
    path.write_text(json.dumps({"regrasps": 5, "solvable": True, "bins": 64, "pieces": 10,
                                "seconds": 0.1, "shortest_route": 4.0}))
    _forget_memory(monkeypatch)
    assert lower_bound(scene).regrasps == 0


def test_a_fifo_in_the_cache_neither_blocks_nor_is_used(fresh, monkeypatch, caplog):
    scene = make_scene()
    path = _entry(scene)
    path.parent.mkdir(parents=True)
    os.mkfifo(path)
    t0 = time.monotonic()
    assert lower_bound(scene).regrasps == 0
    assert time.monotonic() - t0 < 5.0
    assert "not a regular file" in caplog.text


def test_a_link_a_folder_or_a_large_file_is_not_read(fresh, monkeypatch, caplog):
    scene = make_scene()
    real = _forge(scene, regrasps=3)
    elsewhere = fresh / "elsewhere.json"
    shutil.move(real, elsewhere)
    real.symlink_to(elsewhere)
    assert lower_bound(scene).regrasps == 0
    _forget_memory(monkeypatch)
    real.unlink(missing_ok=True)
    real.mkdir()
    assert lower_bound(scene).regrasps == 0
    _forget_memory(monkeypatch)
    real.rmdir()
    _forge(scene).write_text(" " * (bound_cache.MAX_ENTRY_BYTES + 1) + "{}")
    assert lower_bound(scene).regrasps == 0


def test_an_entry_others_may_write_is_not_trusted(fresh, monkeypatch):
    scene = make_scene()
    _forge(scene, regrasps=3).chmod(0o666)
    assert lower_bound(scene).regrasps == 0


def test_an_unwritable_cache_only_costs_speed(fresh, monkeypatch):
    blocker = fresh / "file"
    blocker.write_text("x")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))  # a file where the folder should be
    assert lower_bound(make_scene()).regrasps == 0


def test_a_plan_refutes_a_forged_bound_it_beats(fresh, monkeypatch):
    from pivot_ompl.api import plan

    scene = make_scene()
    path = _forge(scene, regrasps=7, pieces=100, shortest_route=9.0)
    res = plan(scene, time_limit=20.0, seed=0)
    q = res.plan.extra["quality"]
    assert q["regrasps_lower_bound"] is None or q["regrasps_lower_bound"] <= q["regrasps"]
    assert q["shortest_route"] is None or q["shortest_route"] <= q["route_length"] + 1e-6
    assert not path.exists() or json.loads(path.read_text())["bound"]["regrasps"] == 0


def test_fresh_results_pass_the_same_checks():
    for name in ("slot", "enclosed", "open", "door"):
        scene = load_scene(scene_file(name))
        assert bound_problem(lower_bound(scene, use_cache=False), scene) is None


def test_lower_bound_refuses_a_scene_name():
    with pytest.raises(InputError, match="scene"):
        lower_bound("fig10")  # type: ignore[arg-type]


_JSON = st.recursive(st.none() | st.booleans() | st.integers(-10, 10**6)
                     | st.floats(allow_nan=False) | st.text(max_size=5),
                     lambda c: st.lists(c, max_size=3) | st.dictionaries(st.text(max_size=5),
                                                                          c, max_size=3),
                     max_leaves=6)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(field=st.sampled_from(["regrasps", "solvable", "bins", "pieces", "seconds",
                              "shortest_route", "key", "format", "extra"]), value=_JSON)
def test_any_mutated_entry_gives_a_checked_bound_and_no_crash(fresh, monkeypatch, field, value):
    scene = make_scene()
    path = _forge(scene)
    doc = json.loads(path.read_text())
    if field in ("key", "format"):
        doc[field] = value
    else:
        doc["bound"][field] = value
    path.write_text(json.dumps(doc))
    _forget_memory(monkeypatch)
    got = lower_bound(scene)
    assert bound_problem(got, scene) is None
    assert math.isfinite(got.shortest_route or 0.0)

"""The generality benchmark's helpers: a suite of generated scenes, success per family."""

from __future__ import annotations

import pytest

from pivot_ompl.bench.generality import family_rows, format_rows, generate_suite
from pivot_ompl.bench.summary import STATUS
from pivot_ompl.scene import load_scene


def _run(scene: str, planner: str, ok: bool, t: float) -> dict:
    status = STATUS["EXACT_SOLUTION"] if ok else STATUS["TIMEOUT"]
    return {"scene": scene, "planner": planner,
            "run": {"status ENUM": str(status), "time REAL": str(t)}}


def test_family_rows_counts_success_and_times():
    results = [_run("walls_0", "regrasp", True, 1.0), _run("walls_1", "regrasp", False, 30.0),
               _run("walls_2", "regrasp", True, 3.0), _run("fig10", "regrasp", True, 2.0)]
    rows = family_rows(results, {"walls_0": "walls", "walls_1": "walls", "walls_2": "walls"},
                       time_limit=30.0)
    by = {r.family: r for r in rows}
    assert by["walls"].runs == 3 and by["walls"].success == pytest.approx(2 / 3)
    assert by["walls"].median_time == 3.0 and by["walls"].p95_time == 30.0
    assert by["fig10"].success == 1.0
    assert "walls" in format_rows(rows)


def test_generate_suite_writes_scenes_and_witnesses(tmp_path):
    paths = generate_suite(["clutter"], count=2, out=tmp_path)
    assert sorted(p.name for p in paths) == ["clutter_0.yaml", "clutter_1.yaml"]
    assert set(paths.values()) == {"clutter"}
    for p in paths:
        assert load_scene(p).name == p.stem
        assert (tmp_path / f"{p.stem}.witness.json").exists()

"""``pivot-ompl steer`` and ``check`` on the paper's cases; the plan file contract."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest
from factories import scene_file

from pivot_ompl.errors import PlanFileError
from pivot_ompl.planfile import load_plan, plan_from_dict
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.plan_check import check_plan


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "pivot_ompl.cli.main", *args], capture_output=True,
                          text=True, timeout=120)


def test_steer_writes_valid_plan_and_figure(tmp_path):
    out, fig = tmp_path / "p.json", tmp_path / "p.png"
    r = run_cli("steer", "--start", "0", "0", "0", "--goal", "0.5", "3", "0", "--out", str(out),
                "--plot", str(fig))
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["format"] == "pivot-plan/1" and doc["status"] == "exact"
    for key in ("object_size", "robot_footprint", "standoff", "alpha_max"):
        assert key in doc
    steps = doc["phases"][0]["steps"]
    assert all(abs(s["angle"]) <= math.pi / 8 + 1e-12 for s in steps)
    assert steps[-1]["object"] == pytest.approx([0.5, 3.0, 0.0], abs=1e-12)
    assert fig.stat().st_size > 10_000
    r = run_cli("check", str(scene_file("open")), str(out))
    assert r.returncode == 0, r.stderr


def test_check_detects_tampering(tmp_path):
    out = tmp_path / "p.json"
    assert run_cli("steer", "--start", "0", "0", "0", "--goal", "3", "1.5", "0",
                   "--out", str(out)).returncode == 0
    doc = json.loads(out.read_text())
    doc["phases"][0]["steps"][3]["angle"] = 0.6  # over the bound and off the chain
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    rep = check_plan(load_plan(bad), load_scene(scene_file("open_fig7")))
    assert not rep.ok and any("alpha_max" in p for p in rep.problems)
    r = run_cli("check", str(scene_file("open_fig7")), str(bad))
    assert r.returncode == 1


@pytest.mark.parametrize("args, field", [
    (["--start", "0", "0", "nan", "--goal", "1", "1", "0"], "--start"),
    (["--start", "0", "0", "0", "--goal", "1", "1", "0", "--grasp", "7"], "--grasp"),
])
def test_steer_bad_input_exit_2(args, field):
    r = run_cli("steer", *args)
    assert r.returncode == 2 and field in r.stderr


def test_plan_file_errors_name_field():
    good = {"format": "pivot-plan/1", "scene": "x", "status": "exact", "object_size": [1, 1, 1],
            "robot_footprint": [0.4, 0.7], "standoff": 0.25, "alpha_max": 0.39,
            "start": [0, 0, 0], "phases": []}
    plan_from_dict(good)
    for key, val, field in (("format", "v2", "format"), ("status", "maybe", "status"),
                            ("object_size", [1, 1], "object_size"),
                            ("phases", [{"type": "fly"}], "phases[0].type")):
        with pytest.raises(PlanFileError) as e:
            plan_from_dict({**good, key: val})
        assert e.value.field == field
    del good["standoff"]
    with pytest.raises(PlanFileError) as e:
        plan_from_dict(good)
    assert e.value.field == "standoff"


def test_plan_round_trip(tmp_path):
    out = tmp_path / "p.json"
    assert run_cli("steer", "--start", "1", "2", "0.3", "--goal", "2", "4", "-1",
                   "--out", str(out)).returncode == 0
    p = load_plan(out)
    again = tmp_path / "q.json"
    p.to_json(again)
    assert json.loads(again.read_text()) == json.loads(out.read_text())

"""Plans carry their scene: its file (relative to the plan) and its digest, used by every verb."""

from __future__ import annotations

import argparse
import json
import shutil

import numpy as np
import pytest
from factories import scene_file

from pivot_ompl.cli.animate import plan_scene
from pivot_ompl.cli.main import main
from pivot_ompl.cli.scenes import SceneRecord, find_scene
from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import load_motion
from pivot_ompl.planfile import load_plan
from pivot_ompl.resources import shipped_scenes, urdf_path
from pivot_ompl.scene import load_scene, scene_digest
from pivot_ompl.viz.samples import write_urdf_motion


@pytest.fixture(scope="module")
def own_plan(tmp_path_factory):
    """A scene of one's own (not shipped) in ``work/scenes`` and its plan in ``work/plans``."""
    work = tmp_path_factory.mktemp("work")
    (work / "scenes").mkdir()
    (work / "plans").mkdir()
    mine = work / "scenes" / "mine.yaml"
    mine.write_text(scene_file("open").read_text().replace("name: open", "name: mine", 1))
    out = work / "plans" / "plan.json"
    assert main(["plan", str(mine), "--out", str(out), "--time", "10", "--no-bound"]) == 0
    return work


def _copy(own_plan, tmp_path):
    work = tmp_path / "copy"
    shutil.copytree(own_plan, work)
    return work


def test_the_plan_file_records_its_scene_relative_to_itself(own_plan, tmp_path):
    work = _copy(own_plan, tmp_path / "a" / "b")  # the folder moved: the plan still finds it
    doc = json.loads((work / "plans" / "plan.json").read_text())
    assert doc["scene_path"] == "../scenes/mine.yaml"
    mine = load_scene(work / "scenes" / "mine.yaml")
    assert doc["scene_sha256"] == scene_digest(mine)
    plan = load_plan(work / "plans" / "plan.json")
    assert plan.extra["scene_path"] == str((work / "scenes" / "mine.yaml").resolve())
    found = find_scene(SceneRecord.of(plan), None)
    assert found is not None and found.name == "mine"
    plan.to_json(work / "again.json")  # written elsewhere: relative to the new file
    assert json.loads((work / "again.json").read_text())["scene_path"] == "scenes/mine.yaml"


def test_a_plan_with_an_absolute_scene_path_still_reads(own_plan, tmp_path):
    work = _copy(own_plan, tmp_path)
    doc = json.loads((work / "plans" / "plan.json").read_text())
    doc["scene_path"] = str(work / "scenes" / "mine.yaml")
    (work / "old.json").write_text(json.dumps(doc))
    found = find_scene(SceneRecord.of(load_plan(work / "old.json")), None)
    assert found is not None and found.name == "mine"
    del doc["scene_path"], doc["scene_sha256"]  # a plan from before: name only
    (work / "older.json").write_text(json.dumps(doc))
    assert find_scene(SceneRecord.of(load_plan(work / "older.json")), None) is None


def test_every_verb_finds_the_plans_scene(own_plan, tmp_path, capsys):
    work = _copy(own_plan, tmp_path)
    plan_path = work / "plans" / "plan.json"
    assert main(["check", str(plan_path)]) == 0  # no SCENE: the plan's own
    html = tmp_path / "r.html"
    assert main(["replay", str(plan_path), "--html", str(html)]) == 0
    assert "showing no obstacles" not in capsys.readouterr().err
    args = argparse.Namespace(scene=None, no_check=False)
    assert plan_scene(args, SceneRecord.of(load_plan(plan_path))).name == "mine"  # animate
    motion = write_urdf_motion(tmp_path / "m", urdf_path(), duration=0.3)
    with np.load(motion) as d:
        arrays = {k: d[k] for k in d.files}
    n = len(arrays["t"])
    arrays.update(com=np.c_[arrays["q"][:, :2], np.full(n, 0.8)], support=np.zeros(n, int),
                  phase=np.zeros(n, int), scene=np.array("mine"),
                  scene_path=np.array("../scenes/mine.yaml"))
    arrays["zmp"] = arrays["com"][:, :2].copy()
    np.savez(work / "plans" / "m.npz", **arrays)
    assert load_motion(work / "plans" / "m.npz").scene_path == str(
        (work / "scenes" / "mine.yaml").resolve())
    capsys.readouterr()
    assert main(["check-motion", str(work / "plans" / "m.npz")]) in (0, 1)
    assert "(scene mine;" in capsys.readouterr().out


def test_a_scene_gone_is_named_with_the_shipped_ones(own_plan, tmp_path, capsys, caplog):
    work = _copy(own_plan, tmp_path)
    (work / "scenes" / "mine.yaml").unlink()
    plan_path = str(work / "plans" / "plan.json")
    assert main(["check", plan_path]) == 2
    err = capsys.readouterr().err
    assert "mine.yaml is gone" in err and "fig10" in err and "--scene" in err
    with pytest.raises(InputError, match="is gone"):
        plan_scene(argparse.Namespace(scene=None, no_check=False),
                  SceneRecord.of(load_plan(plan_path)))
    assert main(["replay", plan_path, "--html", str(tmp_path / "r.html")]) == 0
    assert "no obstacles drawn: the plan's scene 'mine': its file" in caplog.text


def test_another_scene_is_named_before_anything_else(own_plan, tmp_path, capsys):
    plan_path = str(own_plan / "plans" / "plan.json")
    assert main(["check", "cluttered_room", plan_path]) == 1
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("note: plan made for scene 'mine', given 'cluttered_room'")
    assert len(err) > 2  # the problems follow the note
    assert main(["check", str(own_plan / "scenes" / "mine.yaml"), plan_path]) == 0
    assert "note:" not in capsys.readouterr().err
    assert main(["replay", plan_path, "--scene", "slot", "--html",
                 str(tmp_path / "r.html")]) == 0
    assert capsys.readouterr().err.startswith("note: plan made for scene 'mine', given 'slot'")


def test_generated_witness_records_its_scene(tmp_path, capsys):
    assert main(["generate", "--family", "walls", "--seed", "1", "--out", str(tmp_path)]) == 0
    witness = next(tmp_path.glob("*.witness.json"))
    doc = json.loads(witness.read_text())
    assert doc["scene_path"] == witness.name.replace(".witness.json", ".yaml")
    capsys.readouterr()
    assert main(["check", str(witness)]) == 0
    assert "note:" not in capsys.readouterr().err
    assert "walls_1" not in shipped_scenes()


def test_python_dash_m_runs_the_command_line():
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "pivot_ompl", "plan", "--help"],
                         capture_output=True, text=True, check=False)
    assert out.returncode == 0 and "usage: pivot-ompl plan" in out.stdout

"""Plans carry their scene: its file and its digest, used by replay and check."""

from __future__ import annotations

from factories import scene_file

from pivot_ompl.cli.main import main
from pivot_ompl.cli.replay import find_scene
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene, scene_digest


def test_a_plan_of_ones_own_scene_finds_it_again(tmp_path, capsys):
    mine = tmp_path / "mine.yaml"
    mine.write_text(scene_file("open").read_text().replace("name: open", "name: mine", 1))
    out = tmp_path / "plan.json"
    assert main(["plan", str(mine), "--out", str(out), "--time", "10"]) == 0
    plan = load_plan(out)
    assert plan.extra["scene_path"] == str(mine.resolve())
    assert plan.extra["scene_sha256"] == scene_digest(load_scene(mine))
    found = find_scene(plan.scene, None, path=plan.extra["scene_path"])
    assert found is not None and found.name == "mine"
    mine.unlink()  # moved away: the name alone is not shipped, nothing to draw
    assert find_scene(plan.scene, None, path=plan.extra["scene_path"]) is None


def test_check_against_another_scene_says_so_first(tmp_path, capsys):
    out = tmp_path / "plan.json"
    assert main(["plan", str(scene_file("open")), "--out", str(out), "--time", "10"]) == 0
    capsys.readouterr()
    assert main(["check", str(scene_file("cluttered_room")), str(out)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("note: the plan was made for another scene")
    assert main(["check", str(scene_file("open")), str(out)]) == 0
    assert "another scene" not in capsys.readouterr().err

"""``pivot-ompl simulate``: exit codes, the report file, nothing replaced on bad input."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("mujoco")

from pivot_ompl.cli.main import main  # noqa: E402


def _scene_file(short_run, tmp_path):
    from pivot_ompl.generate.sceneio import scene_text

    path = tmp_path / "scene.yaml"
    path.write_text(scene_text(short_run[0]), encoding="utf-8")
    return str(path)


def test_done_exits_0_and_writes_the_report(short_run, tmp_path, capsys):
    scene = _scene_file(short_run, tmp_path)
    out = tmp_path / "report.json"
    rc = main(["simulate", str(short_run[1]), "--motion", str(short_run[2]), "--scene", scene,
               "--out", str(out), "--friction", "0.6", "--box-mass", "12"])
    assert rc == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("done: box error max")
    doc = json.loads(out.read_text())
    assert doc["reached_goal"] is True and doc["friction"] == 0.6 and doc["box_mass"] == 12.0


def test_goal_missed_exits_1(short_run, tmp_path, capsys):
    scene = _scene_file(short_run, tmp_path)
    out = tmp_path / "report.json"
    rc = main(["simulate", str(short_run[1]), "--motion", str(short_run[2]), "--scene", scene,
               "--out", str(out), "--perturb", "slip@0:0.08,0.02"])
    assert rc == 1
    assert json.loads(out.read_text())["status"] == "goal_missed"
    assert capsys.readouterr().out.startswith("goal_missed:")


@pytest.mark.parametrize("extra", [["--friction", "-1"], ["--perturb", "nonsense"],
                                   ["--box-mass", "1e9"], ["--seed", "x"],
                                   ["--motion", "missing.npz"]])
def test_bad_input_exits_2_and_keeps_the_old_report(short_run, tmp_path, extra):
    scene = _scene_file(short_run, tmp_path)
    out = tmp_path / "report.json"
    out.write_text("old", encoding="utf-8")
    argv = ["simulate", str(short_run[1]), "--motion", str(short_run[2]), "--scene", scene,
            "--out", str(out), *extra]
    with pytest.raises(SystemExit) as e:
        raise SystemExit(main(argv))
    assert e.value.code == 2
    assert out.read_text() == "old"


def test_html_replay_of_a_replanned_run(short_run, tmp_path, capsys):
    scene = _scene_file(short_run, tmp_path)
    out, html = tmp_path / "report.json", tmp_path / "run.html"
    rc = main(["simulate", str(short_run[1]), "--motion", str(short_run[2]), "--scene", scene,
               "--out", str(out), "--perturb", "slip@1:0.06,0", "--replan", "--html",
               str(html)])
    assert rc == 0
    text = html.read_text()
    replans = json.loads(out.read_text())["replans"]
    assert replans and "replan 1" in text and "the box as simulated" in text

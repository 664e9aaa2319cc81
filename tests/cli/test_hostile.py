"""Hostile command lines (issue 15): exit 2 with a short message naming the field, no
traceback, no lost file, bounded time. Run in-process through ``main(argv)``."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from factories import scene_file

from pivot_ompl.cli.main import main
from pivot_ompl.viz.samples import sample_plan, write_samples

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

OPEN = scene_file("open")
GOOD_SCENE = {"name": "t", "bounds": [0, 0, 8, 6], "object": {"size": [0.8, 0.6, 1.3]},
              "start": [1.5, 3.0, 0.0], "goal": [4.0, 3.0, 0.0]}


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    try:
        code = main([str(a) for a in argv])
    except SystemExit as e:  # argparse usage errors
        code = int(e.code or 0)
    out, err = capsys.readouterr()
    return code, out, err


def scene_with(tmp_path: Path, text: str | bytes | None = None, **overrides) -> Path:
    p = tmp_path / "scene.yaml"
    if text is None:
        text = yaml.safe_dump({**GOOD_SCENE, **overrides})
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text)
    return p


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    return write_samples(tmp_path_factory.mktemp("samples"), duration=1.0)


def bad_plan(tmp_path: Path, **changes) -> Path:
    doc = sample_plan().to_dict()
    doc["phases"][0].update(changes)
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(doc))
    return p


# --- class 6: bad input is exit 2, naming the field; no traceback ---------------------------

CASES = {
    "scene not UTF-8": lambda t: ["plan", scene_with(t, yaml.safe_dump(GOOD_SCENE).encode()
                                                     + b"# \xff\n")],
    "401-digit integer": lambda t: ["plan", scene_with(t, yaml.safe_dump(GOOD_SCENE).replace(
        "1.5", "1" * 401, 1))],
    "50,000 nested lists": lambda t: ["plan", scene_with(t, yaml.safe_dump(GOOD_SCENE).replace(
        "name: t", "name: " + "[" * 50_000 + "]" * 50_000))],
    "alpha_max 1e-9": lambda t: ["plan", scene_with(t, pivot={"alpha_max": 1e-9})],
    "coordinate 1e308": lambda t: ["plan", scene_with(t, goal=[1e308, 3.0, 0.0])],
    "seed >= 2^64 with OMPL": lambda t: ["plan", OPEN, "--planner", "rrtconnect",
                                         "--seed", str(2**64)],
    "--time nan": lambda t: ["plan", OPEN, "--time", "nan"],
    "--out a directory": lambda t: ["plan", OPEN, "--out", t],
    "--plot unknown extension": lambda t: ["plan", OPEN, "--plot", t / "fig.xyz"],
    "steer --plot unknown extension": lambda t: ["steer", "--start", "0", "0", "0", "--goal",
                                                 "1", "0", "0", "--plot", t / "f.xyz"],
    "steer coordinate 1e300": lambda t: ["steer", "--start", "1e300", "0", "0", "--goal",
                                         "1", "0", "0"],
    "steer --time -1": lambda t: ["steer", "--start", "0", "0", "0", "--goal", "1", "0", "0",
                                  "--time", "-1"],
    "plan not UTF-8": lambda t: ["check", OPEN, _bytes(t / "p.json", b'{"scene": "\xe9"}')],
    "rs_path not a list": lambda t: ["check", OPEN, bad_plan(t, rs_path=3)],
    "plan angle 1e300": lambda t: ["check", OPEN, bad_plan(t, steps=[{
        "pivot": [0, 0], "angle": 1e300, "object": [0, 0, 0], "robot": [0, 0, 0]}])],
    "truncated .npz": lambda t: ["check-motion", _truncated(t)],
    "empty .npz": lambda t: ["check-motion", _bytes(t / "m.npz", b"")],
    "--html a directory": lambda t: ["replay", sample_plan().to_json(t / "p.json"), "--html", t],
    "--fps nan": lambda t: ["replay", sample_plan().to_json(t / "p.json"), "--fps", "nan"],
    "bench on a garbage scene": lambda t: ["bench", _bytes(t / "g.yaml", b"\x00\xff garbage"),
                                           "--out", t / "res", "--no-progress"],
    "animate --out a directory": lambda t: ["animate", sample_plan().to_json(t / "p.json"),
                                            "--out", t],
}


#: What each message must name (the field, or what is wrong with the document).
NAMES = {"scene not UTF-8": "UTF-8", "401-digit integer": "start[0]",
         "50,000 nested lists": "nested too deeply", "alpha_max 1e-9": "pivot.alpha_max",
         "coordinate 1e308": "goal[0]", "seed >= 2^64 with OMPL": "--seed", "--time nan": "--time",
         "--out a directory": "--out", "--plot unknown extension": "--plot",
         "steer --plot unknown extension": "--plot", "steer coordinate 1e300": "--start[0]",
         "steer --time -1": "--time", "plan not UTF-8": "UTF-8",
         "rs_path not a list": "phases[0].rs_path", "plan angle 1e300": "steps[0].angle",
         "truncated .npz": "motion", "empty .npz": "motion", "--html a directory": "--html",
         "--fps nan": "--fps", "bench on a garbage scene": "UTF-8",
         "animate --out a directory": "--out"}


def _bytes(p: Path, data: bytes) -> Path:
    p.write_bytes(data)
    return p


def _truncated(t: Path) -> Path:
    from pivot_ompl.viz.samples import sample_motion_arrays

    p = t / "m.npz"
    np.savez(p, **sample_motion_arrays(duration=0.5))
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    return p


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input_exit_2_short_message(case, tmp_path, capsys):
    t0 = time.monotonic()
    code, _, err = cli(capsys, *CASES[case](tmp_path))
    assert code == 2, err
    assert "Traceback" not in err and 0 < len(err) < 1500
    assert NAMES[case] in err
    assert time.monotonic() - t0 < 20


# --- class 3: no lost file ------------------------------------------------------------------

def test_plan_refuses_to_overwrite_its_scene(tmp_path, capsys):
    scene = scene_with(tmp_path)
    before = scene.read_bytes()
    code, _, err = cli(capsys, "plan", scene, "--out", scene, "--time", "1")
    assert code == 2 and "--out" in err
    assert scene.read_bytes() == before


def test_plan_refuses_one_file_for_plan_and_figure(tmp_path, capsys):
    """--out and --plot naming one file: refused before planning (the figure would replace
    the plan), whichever way the path is written."""
    same = tmp_path / "x.png"
    same.write_bytes(b"keep")
    code, _, err = cli(capsys, "plan", scene_with(tmp_path), "--out", same,
                       "--plot", tmp_path / "." / "x.png", "--time", "1")
    assert code == 2 and "--plot" in err and "--out" in err
    assert same.read_bytes() == b"keep"


def test_failed_plan_keeps_the_existing_plan(tmp_path, capsys):
    out, fig = tmp_path / "plan.json", tmp_path / "plan.png"
    out.write_text("good plan")
    fig.write_bytes(b"good figure")
    code, _, err = cli(capsys, "plan", scene_file("enclosed"), "--time", "0.5", "--out", out,
                       "--plot", fig, "--no-bound")  # a search that times out
    assert code == 1, err
    assert out.read_text() == "good plan" and fig.read_bytes() == b"good figure"


def test_replay_refuses_to_overwrite_its_input(tmp_path, capsys):
    p = sample_plan().to_json(tmp_path / "p.json")
    before = p.read_bytes()
    code, _, err = cli(capsys, "replay", p, "--html", p)
    assert code == 2 and "--html" in err
    assert p.read_bytes() == before
    html_input = tmp_path / "x.html"  # default output <input>.html would be the input itself
    html_input.write_bytes(before)
    assert cli(capsys, "replay", html_input)[0] == 2
    assert html_input.read_bytes() == before


def test_animate_refuses_to_overwrite_its_plan(tmp_path, capsys):
    p = sample_plan().to_json(tmp_path / "p.npz")
    before = p.read_bytes()
    code, _, err = cli(capsys, "animate", p, "--out", p)
    assert code == 2 and "--out" in err and p.read_bytes() == before


def test_bench_rerun_into_same_folder(tmp_path, capsys):
    res = tmp_path / "res"
    res.mkdir()
    (res / "old_scene.log").write_text("stale")
    (res / "notes.txt").write_text("mine")
    argv = ["bench", OPEN, "--planners", "regrasp", "--runs", "1", "--time", "2", "--out", res,
            "--no-progress", "--no-plots", "--workers", "1"]
    code, _, err = cli(capsys, *argv)
    assert code == 2 and "--overwrite" in err
    assert sorted(p.name for p in res.iterdir()) == ["notes.txt", "old_scene.log"]
    code, _, err = cli(capsys, *argv, "--overwrite")
    assert code == 0, err
    names = sorted(p.name for p in res.iterdir())
    # no sweep wrote old_scene.log (no manifest lists it): it is the user's and stays
    assert "old_scene.log" in names and "open.log" in names and "notes.txt" in names
    assert not any(n.startswith(".partial") for n in names)


# --- classes 1 and 4: bounded time, a real limit for huge ones ------------------------------

def test_steer_honours_its_time_limit(capsys):
    t0 = time.monotonic()
    code, _, err = cli(capsys, "steer", "--start", "0", "0", "0", "--goal", "9000", "0", "0",
                       "--time", "0.2")
    assert code == 1 and "stopped" in err
    assert time.monotonic() - t0 < 5


@pytest.mark.parametrize("limit", ["1e10", "inf"])
def test_huge_time_limit_is_a_real_limit(limit, tmp_path, capsys):
    out = tmp_path / "p.json"
    code, text, err = cli(capsys, "plan", OPEN, "--planner", "rrtconnect", "--time", limit,
                          "--out", out)
    assert code == 0, err
    assert "EXACT_SOLUTION" in text and out.exists()


# --- a few real processes: exit codes and stderr as a shell sees them -----------------------

def run(*argv, timeout=60):
    return subprocess.run([sys.executable, "-m", "pivot_ompl.cli.main", *map(str, argv)],
                          capture_output=True, text=True, timeout=timeout)


def test_subprocess_alias_bomb_and_non_utf8(tmp_path):
    lines = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for i in range(1, 9):
        prev, cur = chr(ord("a") + i - 1), chr(ord("a") + i)
        lines.append(f"{cur}: &{cur} [{', '.join(['*' + prev] * 9)}]")
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text("\n".join(lines) + "\nname: *i\n")
    t0 = time.monotonic()
    r = run("plan", bomb)
    assert r.returncode == 2 and "Traceback" not in r.stderr and len(r.stderr) < 1000
    assert time.monotonic() - t0 < 30
    r = run("check", _bytes(tmp_path / "s.yaml", b"\xff\xfe"), tmp_path / "none.json")
    assert r.returncode == 2 and "UTF-8" in r.stderr and "Traceback" not in r.stderr


def test_subprocess_plan_ends_within_its_limit(tmp_path):
    """A plan that cannot succeed stops at its limit (110 % plus start-up)."""
    t0 = time.monotonic()
    r = run("plan", scene_file("enclosed"), "--time", "2", "--no-bound", timeout=120)
    wall = time.monotonic() - t0
    assert r.returncode == 1, r.stderr
    solve = float(r.stdout.split("solve ")[1].split(" s")[0])
    assert solve <= 2.2 + 0.3  # 110 % plus one poll of the termination condition
    assert wall < 2.2 + 30  # start-up (imports, OMPL) included


def test_ctrl_c_exits_130_and_keeps_outputs(tmp_path, capsys, monkeypatch):
    """An interrupted plan: exit 130, the existing plan untouched, no temporary file left."""
    import pivot_ompl.cli.plan as plan_verb

    out = tmp_path / "plan.json"
    out.write_text("good plan")

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(plan_verb, "plan", interrupted)
    code, _, err = cli(capsys, "plan", scene_file("open"), "--out", out, "--time", "1")
    assert code == 130 and "interrupted" in err
    assert out.read_text() == "good plan"
    assert [p.name for p in tmp_path.iterdir()] == ["plan.json"]


def test_a_fifo_as_input_is_refused_at_once(tmp_path):
    """A named pipe with no writer would block a reader forever: refused, exit 2, at once."""
    import os

    fifo = tmp_path / "scene.yaml"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "pivot_ompl.cli", "check", str(fifo), str(fifo)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "not a regular file" in r.stderr
    assert time.monotonic() - t0 < 30


def test_outputs_follow_the_umask(tmp_path, capsys):
    """Every verb's files get the umask's mode (generate's used to be 0600)."""
    import os
    import stat

    old = os.umask(0o022)
    try:
        code, _, _ = cli(capsys, "generate", "--family", "clutter", "--seed", "0",
                         "--out", tmp_path / "g")
        assert code == 0
        modes = {stat.S_IMODE(p.stat().st_mode) for p in (tmp_path / "g").iterdir()}
        assert modes == {0o644}
    finally:
        os.umask(old)


@pytest.mark.parametrize(("call", "field"), [
    (lambda: __import__("pivot_ompl").load_scene(3.5), "path"),
    (lambda: __import__("pivot_ompl").PivotSteering("2", 0.3), "turning_radius"),
    (lambda: __import__("pivot_ompl").PivotSteering(2.0, None), "alpha_max")])
def test_api_wrong_types_are_input_errors(call, field):
    from pivot_ompl.errors import InputError

    with pytest.raises(InputError) as e:
        call()
    assert e.value.field == field


@pytest.mark.parametrize("points", [[[0.0, 0.0, float("nan")]], [], "abc", [[1.0, 2.0]]])
def test_a_camera_never_becomes_nan(points):
    from pivot_ompl.errors import InputError
    from pivot_ompl.viz.camera import follow_pose

    with pytest.raises(InputError) as e:
        follow_pose(points)
    assert e.value.field == "points"


@pytest.mark.parametrize(("args", "flag"), [(["1.2", "1.0"], "--wide-doors"),
                                            (["1.0", "9"], "wide_doors")])
def test_generate_names_a_bad_wide_door_range(tmp_path, capsys, args, flag):
    code, _, err = cli(capsys, "generate", "--family", "building", "--wide-doors", *args,
                       "--out", tmp_path / "g")
    assert code == 2 and flag in err, err
    assert not (tmp_path / "g").exists()

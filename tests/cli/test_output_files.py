"""Every verb's files (issue 28, class 5): all or nothing, names checked before the work and
named as the user gave them, one file per output option, regular inputs only, the umask's mode."""

from __future__ import annotations

import errno
import os
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest
from factories import scene_file
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.fileio import MAX_NAME, atomic_outputs, check_output
from pivot_ompl.viz.samples import sample_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

STEER = ["steer", "--start", "0", "0", "0", "--goal", "1", "0", "0"]
PLAN = ["plan", str(scene_file("open")), "--planner", "rrtconnect", "--time", "10"]


def cli(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _disk_full(plan, path, *args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device", str(path))


@pytest.mark.parametrize("verb", [PLAN, STEER], ids=["plan", "steer"])
def test_one_file_for_two_outputs_is_refused(verb, tmp_path, capsys):
    same = tmp_path / "x.png"
    same.write_bytes(b"keep")
    code, _, err = cli(capsys, *verb, "--out", same, "--plot", tmp_path / "." / "x.png")
    assert code == 2 and "--plot" in err and "--out" in err, err
    assert same.read_bytes() == b"keep"


@pytest.mark.parametrize("verb", [PLAN, STEER], ids=["plan", "steer"])
def test_a_figure_that_cannot_be_written_keeps_the_plan_and_names_the_users_file(
        verb, tmp_path, capsys, monkeypatch):
    """Plan and figure are written together: a failed figure leaves the old plan, and the
    message names the figure as given, not its temporary file."""
    import pivot_ompl.viz.plan_figure as plan_figure

    out, fig = tmp_path / "p.json", tmp_path / "p.png"
    out.write_text("previous plan")
    monkeypatch.setattr(plan_figure, "plot_plan", _disk_full)
    code, _, err = cli(capsys, *verb, "--out", out, "--plot", fig)
    assert code == 2, err
    assert str(fig) in err and ".pivot-" not in err and ".tmp" not in err, err
    assert out.read_text() == "previous plan"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.json"]


def test_generate_count_is_all_or_nothing(tmp_path, capsys, monkeypatch):
    """A later seed that fails: none of the earlier seeds' files is written."""
    import pivot_ompl.cli.generate as verb

    real = verb.generate

    def second_fails(family, seed, **kw):
        if seed == 1:
            raise InputError("seed", seed, "no valid layout")
        return real(family, seed, **kw)

    monkeypatch.setattr(verb, "generate", second_fails)
    code, _, err = cli(capsys, "generate", "--family", "clutter", "--count", "2",
                       "--out", tmp_path / "g")
    assert code == 2, err
    assert not (tmp_path / "g").exists() or not list((tmp_path / "g").iterdir())


def test_a_folder_name_too_long_is_refused_before_the_work(tmp_path, capsys, monkeypatch):
    import pivot_ompl.cli.plan as verb

    monkeypatch.setattr(verb, "plan", lambda *a, **k: pytest.fail("planned"))
    code, _, err = cli(capsys, *PLAN, "--out", tmp_path / ("d" * 300) / "p.json")
    assert code == 2 and "--out" in err and "folder name longer than 255 bytes" in err, err
    code, _, err = cli(capsys, "generate", "--family", "clutter", "--out",
                       tmp_path / ("é" * 200))
    assert code == 2 and "--out" in err and "longer than 255 bytes" in err, err


def test_replay_html_at_the_name_limit(tmp_path, capsys):
    """A name of 255 bytes is written (the temporary name is short), 256 refused first."""
    plan = sample_plan().to_json(tmp_path / "p.json")
    ok = tmp_path / ("r" * (MAX_NAME - 5) + ".html")
    code, _, err = cli(capsys, "replay", plan, "--html", ok)
    assert code == 0, err
    assert ok.is_file() and sorted(p.name for p in tmp_path.iterdir()) == ["p.json", ok.name]
    code, _, err = cli(capsys, "replay", plan, "--html", tmp_path / ("r" * MAX_NAME + ".html"))
    assert code == 2 and "--html" in err


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(folder=st.text(st.sampled_from("aé€_"), min_size=1, max_size=140),
       name=st.text(st.sampled_from("bü𝄞-"), min_size=1, max_size=100))
def test_an_accepted_output_can_be_written(tmp_path, folder, name):
    """check_output accepts a path exactly when every name in it fits the file system; then
    the atomic writer creates it (no refusal after the work)."""
    path = tmp_path / folder / (name + ".json")
    fits = all(len(part.encode()) <= MAX_NAME for part in (folder, name + ".json"))
    try:
        check_output(path, field="--out")
    except InputError as e:
        assert not fits and "longer than" in e.reason
        return
    assert fits
    with atomic_outputs(path) as (tmp,):
        assert tmp is not None and len(tmp.name) < 64
        tmp.write_text("{}")
    assert path.read_text() == "{}"


@pytest.mark.parametrize("verb", ["check-motion", "replay"])
def test_a_fifo_input_is_refused_at_once(verb, tmp_path):
    fifo = tmp_path / "motion.npz"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "pivot_ompl.cli", verb, str(fifo)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "not a regular file" in r.stderr, r.stderr
    assert time.monotonic() - t0 < 30


def _modes(folder: Path) -> dict[str, int]:
    return {str(p.relative_to(folder)): stat.S_IMODE(p.stat().st_mode)
            for p in folder.rglob("*") if p.is_file()}


def test_every_verb_writes_with_the_umask(tmp_path, capsys):
    """One policy: every file written by every verb has mode 0666 & ~umask."""
    old = os.umask(0o027)
    try:
        plan = tmp_path / "p.json"
        runs = [[*PLAN, "--out", plan, "--plot", tmp_path / "p.png"],
                [*STEER, "--out", tmp_path / "s.json", "--plot", tmp_path / "s.png"],
                ["generate", "--family", "clutter", "--out", tmp_path / "g"],
                ["replay", sample_plan().to_json(tmp_path / "sample.json"),
                 "--html", tmp_path / "r.html"],
                ["bench", scene_file("open"), "--planners", "rrtconnect", "--runs", "1",
                 "--time", "2", "--out", tmp_path / "b", "--no-progress", "--workers", "1"]]
        for argv in runs:
            code, _, err = cli(capsys, *argv)
            assert code == 0, (argv, err)
        modes = _modes(tmp_path)
        mine = {k: v for k, v in modes.items() if k != "sample.json"}
        assert len(mine) >= 10 and set(mine.values()) == {0o640}, modes
    finally:
        os.umask(old)

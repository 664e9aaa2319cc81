"""Names and keys never reach a terminal, a log or a figure raw (issue 43, class 7)."""

from __future__ import annotations

import json
import subprocess
import sys
import unicodedata

import pytest
import yaml
from factories import scene_file
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError, printable
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene
from pivot_ompl.viz.plan_figure import plot_plan

HOSTILE = "x\nExperiment \x1b[31mred\x07\u202e $\\alpha$ $x^ \r"
RAW = ("\x1b", "\x07", "\u202e", "\r")


def _raw(text: str) -> bool:
    return any(c in text for c in RAW)


def _scene(tmp_path, name=HOSTILE, **extra):
    doc = yaml.safe_load(scene_file("open").read_text())
    doc.update(name=name, **extra)
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(doc))
    return p


@given(st.text())
def test_printable_leaves_no_control_character(text):
    out = printable(text)
    assert all(unicodedata.category(c)[0] != "C" and unicodedata.category(c) not in ("Zl", "Zp")
               for c in out)
    if text.isprintable():
        assert out == text


def test_an_error_naming_a_key_escapes_it(tmp_path, capsys):
    p = _scene(tmp_path, name="ok", **{"bad\x1b]0;title\x07key": 1})
    assert main(["check", str(p), "nothing.json"]) == 2
    err = capsys.readouterr().err
    assert not _raw(err) and "\\x1b" in err
    with pytest.raises(InputError) as e:
        load_scene(p)
    assert not _raw(str(e.value))


def test_bound_prints_the_name_escaped(tmp_path, capsys):
    assert main(["bound", str(_scene(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert not _raw(out) and "\\x1b[31mred\\x07" in out
    assert len(out.strip().splitlines()) == 1  # the newline in the name is shown, not obeyed


def test_every_log_line_is_escaped(tmp_path):
    p = _scene(tmp_path)
    run = subprocess.run([sys.executable, "-m", "pivot_ompl", "--log-level", "DEBUG", "plan",
                          str(p), "--time", "2", "--no-bound"], capture_output=True, text=True,
                         timeout=120, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    assert not _raw(run.stdout) and not _raw(run.stderr)
    assert "\\x1b" in run.stderr  # the name was logged, escaped


def test_a_dollar_name_draws_as_plain_text_and_the_plan_is_written(tmp_path, capsys):
    p = _scene(tmp_path)
    out, fig = tmp_path / "p.json", tmp_path / "p.png"
    assert main(["plan", str(p), "--out", str(out), "--plot", str(fig), "--time", "3",
                 "--no-bound"]) == 0
    assert out.is_file() and fig.is_file()
    plan = load_plan(out)
    assert plan.scene == HOSTILE  # the file keeps the name as it is
    plot_plan(plan, tmp_path / "again.png", title="$x^$ \x1b")


def test_a_newline_in_a_name_keeps_the_bench_log_readable(tmp_path, capsys):
    p = _scene(tmp_path)
    out = tmp_path / "out"
    assert main(["bench", str(p), "--planners", "regrasp", "--runs", "1", "--time", "2",
                 "--out", str(out), "--workers", "1", "--no-progress", "--no-plots"]) == 0
    text = capsys.readouterr()
    assert not _raw(text.out) and not _raw(text.err)
    assert (out / "benchmark.db").is_file()
    runs = json.loads((out / "runs.json").read_text())
    assert runs and all(r["scene"] == HOSTILE for r in runs)

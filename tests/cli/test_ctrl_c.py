"""Ctrl-C as a shell sends it (SIGINT to a real process): one line, exit 130, no traceback, no
partial or replaced file, whenever it comes (while the verbs load, while planning)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from factories import scene_file

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

#: Runs the command line after arranging a SIGINT to itself on the first import of ``numpy``
#: (deterministic: the moment the command line loads its verbs).
_INTERRUPT_ON_IMPORT = """
import builtins, os, signal, sys
real = builtins.__import__
def hook(name, *args, **kwargs):
    if name == "numpy" and "numpy" not in sys.modules:
        builtins.__import__ = real
        os.kill(os.getpid(), signal.SIGINT)
    return real(name, *args, **kwargs)
builtins.__import__ = hook
from pivot_ompl.cli.main import main
sys.exit(main())
"""


def _interrupted_cleanly(code: int, err: str, verb: str) -> None:
    assert code == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    lines = [line for line in err.replace("\r", "\n").splitlines()
             if line.strip() and not line.startswith("planning...")]
    assert lines == [f"pivot-ompl {verb}: interrupted"], err


@pytest.mark.parametrize("verb", ["plan", "generate"])
def test_ctrl_c_while_the_command_line_loads(verb, tmp_path):
    out = tmp_path / "kept.json"
    out.write_text("previous")
    argv = (["plan", str(scene_file("open")), "--out", str(out)] if verb == "plan"
            else ["generate", "--family", "walls", "--out", str(tmp_path)])
    r = subprocess.run([sys.executable, "-c", _INTERRUPT_ON_IMPORT, *argv],
                       capture_output=True, text=True, timeout=120)
    _interrupted_cleanly(r.returncode, r.stderr, verb)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.json"]
    assert out.read_text() == "previous"


def _interrupt_when(argv: list[str], ready: str, cwd: Path) -> tuple[int, str]:
    """Start ``pivot-ompl argv``, send SIGINT once stderr shows ``ready``; (code, stderr)."""
    p = subprocess.Popen([sys.executable, "-m", "pivot_ompl.cli", *argv], cwd=cwd,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    assert p.stderr is not None
    seen = b""
    deadline = time.monotonic() + 120
    try:
        os.set_blocking(p.stderr.fileno(), False)
        while ready.encode() not in seen and p.poll() is None and time.monotonic() < deadline:
            seen += p.stderr.read() or b""
            time.sleep(0.05)
        p.send_signal(signal.SIGINT)
        os.set_blocking(p.stderr.fileno(), True)
        seen += p.stderr.read()
        code = p.wait(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    return code, seen.decode(errors="replace")


def test_ctrl_c_while_planning_keeps_the_previous_plan(tmp_path):
    out, fig = tmp_path / "plan.json", tmp_path / "plan.png"
    out.write_text("previous plan")
    code, err = _interrupt_when(["plan", str(scene_file("enclosed")), "--time", "60", "--no-bound",
                                 "--out", str(out), "--plot", str(fig)], "planning...", tmp_path)
    _interrupted_cleanly(code, err, "plan")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.json"]
    assert out.read_text() == "previous plan"

"""``bench`` stopped by Ctrl-C or SIGTERM ends its jobs at once and leaves nothing behind
(issue 43, class 6)."""

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


def _jobs_of(marker: str) -> list[int]:
    """Processes whose command line holds ``marker`` (a folder of this test's own)."""
    pids = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            cmd = (d / "cmdline").read_bytes().decode(errors="replace")
        except OSError:
            continue
        if marker in cmd and "pivot_ompl.bench.worker" in cmd:
            pids.append(int(d.name))
    return pids


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_a_stopped_bench_ends_its_jobs_at_once_and_leaves_nothing(tmp_path, how):
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir()
    env = {**os.environ, "TMPDIR": str(tmp)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "pivot_ompl", "bench", str(scene_file("enclosed")),
         "--planners", "rrtconnect,regrasp", "--runs", "2", "--time", "60", "--workers", "2",
         "--out", str(out), "--no-progress", "--no-plots"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while len(_jobs_of(str(tmp))) < 2 and time.monotonic() < deadline:
            time.sleep(0.2)
        assert len(_jobs_of(str(tmp))) == 2, "the jobs did not start"
        time.sleep(2.0)  # the jobs are planning (in OMPL's C++ code)
        t0 = time.monotonic()
        if how == "ctrl-c":  # the terminal sends SIGINT to the foreground process group
            os.killpg(proc.pid, signal.SIGINT)
        else:
            proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
        took = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, err.decode()[-2000:]
    assert took < 5.0
    time.sleep(0.3)
    assert _jobs_of(str(tmp)) == []  # no job left running
    assert list(tmp.iterdir()) == []  # no temporary folder of a job
    assert not out.exists() or [p.name for p in out.iterdir()] == []  # no partial output
    assert b"Traceback" not in err

"""``bench --executor dask`` stopped by Ctrl-C or SIGTERM ends its jobs at once and leaves
nothing behind, as the default executor does (issue 43, class 6)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from factories import scene_file

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

pytest.importorskip("distributed")


def _processes_of(marker: str, what: str) -> list[int]:
    """Processes whose command line holds ``marker`` (a folder of this test's own) and
    ``what``."""
    pids = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            cmd = (d / "cmdline").read_bytes().decode(errors="replace")
            env = (d / "environ").read_bytes().decode(errors="replace")
        except OSError:
            continue
        if what in cmd and (marker in cmd or marker in env):
            pids.append(int(d.name))
    return pids


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_a_stopped_dask_bench_ends_its_jobs_at_once_and_leaves_nothing(tmp_path, how):
    tmp, out = tmp_path / "tmp", tmp_path / "out"
    tmp.mkdir()
    env = {**os.environ, "TMPDIR": str(tmp)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "pivot_ompl", "bench", str(scene_file("enclosed")),
         "--planners", "rrtconnect,regrasp", "--runs", "2", "--time", "60", "--workers", "2",
         "--executor", "dask", "--out", str(out), "--no-progress", "--no-plots"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        deadline = time.monotonic() + 90
        while (len(_processes_of(str(tmp), "pivot_ompl.bench.worker")) < 2
               and time.monotonic() < deadline):
            time.sleep(0.2)
        assert len(_processes_of(str(tmp), "pivot_ompl.bench.worker")) == 2, \
            "the jobs did not start"
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
    time.sleep(0.3)
    left = _processes_of(str(tmp), "python")
    names = {}
    for pid in left:
        with contextlib.suppress(OSError):
            names[pid] = Path(f"/proc/{pid}/cmdline").read_bytes()[:300]
    for pid in left:  # never leave this test's processes behind, whatever it found
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    assert proc.returncode == 130, err.decode()[-2000:]
    assert took < 5.0, took
    assert left == [], names  # no job, worker or nanny left running
    assert list(tmp.iterdir()) == []  # no temporary folder of a job or of the cluster
    assert not out.exists() or [p.name for p in out.iterdir()] == []  # no partial output
    assert b"Traceback" not in err

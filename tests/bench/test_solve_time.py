"""benchmarks/solve_time.py --first: the first plan of a fresh process, with an empty cache."""

from __future__ import annotations

import fcntl
import subprocess

import pytest
from factories import benchmark_script


def test_a_first_plan_runs_in_its_own_process_with_an_empty_cache(tmp_path, monkeypatch):
    st = benchmark_script("solve_time")
    cache = tmp_path / "user_cache"
    cache.mkdir()
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    row = st.run_first(st.ROOT, "door", 0, 15.0)
    assert row["solved"] and row["regrasps"] == 1 and row["seed"] == 0
    # the plan's own CPU seconds, within the whole process's (interpreter and imports too)
    assert 0.0 < row["cpu"] < row["proc"]
    assert row["solve"] > 0.0 and row["bound"] is not None
    assert 0.0 < row["search"] < row["cpu"]  # the regrasp search, within the plan
    # the late proof the search polls while it has no path, within the search
    assert 0.0 <= row["proof"] <= row["search"]
    # the lower bounds were computed, not read: the caller's cache folder stays untouched
    assert not any(cache.iterdir())


def _held_by_another(path) -> bool:
    """Whether a lock on ``path`` is held (another open file cannot take it at once)."""
    with open(path, "a") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        fcntl.flock(fh, fcntl.LOCK_UN)
        return False


@pytest.mark.parametrize("first", [True, False])
def test_every_worker_runs_holding_the_bench_lock(tmp_path, monkeypatch, first):
    st = benchmark_script("solve_time")
    lock = tmp_path / "bench.lock"
    monkeypatch.setenv("PIVOT_BENCH_LOCK", str(lock))
    held: list[bool] = []

    def worker(cmd, **kwargs):  # stands for the worker process: records the lock, answers
        held.append(_held_by_another(lock))
        lines = ['FIRST {"cpu": 1.0}'] + [f'ROW {{"seed": {k}, "cpu": 1.0}}' for k in range(2)]
        return subprocess.CompletedProcess(cmd, 0, "\n".join(lines[2:] if first else lines), "")

    monkeypatch.setattr(st.subprocess, "run", worker)
    if first:
        st.run_first(st.ROOT, "door", 1, 15.0)
    else:
        st.run(st.ROOT, "door", 2, 15.0)
    assert held == [True]
    assert not _held_by_another(lock)  # free again between the workers

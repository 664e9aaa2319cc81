"""benchmarks/solve_time.py --first: the first plan of a fresh process, with an empty cache."""

from __future__ import annotations

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

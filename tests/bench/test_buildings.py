"""benchmarks/buildings.py: every corpus map imports at its task, and the table reads runs."""

from __future__ import annotations

from pathlib import Path

import pytest
from factories import ROOT, benchmark_script


def _buildings():
    return benchmark_script("buildings")


def test_the_corpus_holds_at_least_six_maps_each_with_its_provenance():
    corpus = _buildings().CORPUS
    assert len({m.name for m in corpus}) == len(corpus) >= 6
    for m in corpus:
        text = (ROOT / m.map).parent.joinpath("PROVENANCE.md").read_text()
        assert "Source: https://github.com/" in text and "Licence:" in text


@pytest.mark.parametrize("name", [m.name for m in _buildings().CORPUS])
def test_every_corpus_map_imports_at_its_start_and_goal(tmp_path, name):
    mod = _buildings()
    m = next(m for m in mod.CORPUS if m.name == name)
    info = mod.import_corpus_map(m, tmp_path)
    assert info["boxes"] > 0 and Path(info["scene"]).is_file()


def test_a_row_counts_solved_runs_and_plans_at_their_bound():
    mod = _buildings()
    runs = [{"solved": True, "wall": 3.0, "solve": 1.0, "regrasps": 1, "bound": 1,
             "route_ratio": 1.2, "peak_mb": 300.0},
            {"solved": True, "wall": 5.0, "solve": 2.0, "regrasps": 2, "bound": 1,
             "route_ratio": 1.4, "peak_mb": 350.0},
            {"solved": False, "wall": 61.0, "peak_mb": 500.0, "outcome": "timeout"}]
    info = {"width": 10.0, "depth": 5.0, "resolution": 0.05, "boxes": 42}
    row = mod.summary_row(mod.CORPUS[0], info, runs)
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[3:] == ["42", "2/3", "4.0", "1.5", "2", "1/2 at bound 1", "1.30", "500",
                         "1 timeout (61.0 s)"]


def test_a_row_tells_proven_infeasible_runs_from_timeouts():
    mod = _buildings()
    runs = [{"solved": False, "wall": w, "peak_mb": 200.0, "outcome": o}
            for w, o in ((4.0, "infeasible"), (6.0, "infeasible"), (61.0, "timeout"))]
    info = {"width": 10.0, "depth": 5.0, "resolution": 0.05, "boxes": 42}
    row = mod.summary_row(mod.CORPUS[0], info, runs)
    assert row.rstrip(" |").endswith("2 infeasible (5.0 s), 1 timeout (61.0 s)")


@pytest.mark.parametrize(("code", "stdout", "expected"), [
    (0, "EXACT_SOLUTION: 12 pivots, 0 regrasps, solve 0.10 s\n", "solved"),
    (1, "INFEASIBLE: no plan: every way ... (proven in 3.10 s)\n", "infeasible"),
    (1, "TIMEOUT: no plan reaches the goal (solve 60.00 s of 60 s)\n", "timeout"),
    (1, "", "timeout"),
    (2, "", "error"),
    (-9, "INFEASIBLE: cut short\n", "error")])
def test_a_run_outcome_is_read_from_the_exit_code_and_the_status_word(code, stdout, expected):
    assert _buildings().outcome(code, stdout) == expected


def test_the_table_says_under_it_what_is_known_of_the_unsolved_tasks():
    mod = _buildings()
    info = {"width": 10.0, "depth": 5.0, "resolution": 0.05, "boxes": 42,
            "runs": [{"solved": False, "wall": 61.0, "peak_mb": 500.0}]}
    noted = [m for m in mod.CORPUS if m.note]
    assert noted  # the tasks without a known plan say so
    text = mod.table({m.name: info for m in mod.CORPUS}, "cmd")
    assert "Known of the tasks:" in text
    assert all(f"- {m.name}: {m.note}" in text for m in noted)
    plain = [m for m in mod.CORPUS if not m.note]
    assert "Known of the tasks" not in mod.table({plain[0].name: info}, "cmd")

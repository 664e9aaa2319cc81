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
            {"solved": False, "wall": 61.0, "peak_mb": 500.0}]
    info = {"width": 10.0, "depth": 5.0, "resolution": 0.05, "boxes": 42}
    row = mod.summary_row(mod.CORPUS[0], info, runs)
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[3:] == ["42", "2/3", "4.0", "1.5", "2", "1/2 at bound 1", "1.30", "500"]


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

"""benchmarks/figures.py turns each script's JSON into table rows."""

from __future__ import annotations

import subprocess

from factories import ROOT, benchmark_script


def _figures():
    return benchmark_script("figures")


def _method(median_s: float, ok: int, regrasps: int) -> dict:
    return {"ok": ok, "checked": ok, "median_s": median_s, "median_solve_s": median_s,
            "median_cost": 600.0, "median_regrasps": regrasps, "repaired": ok,
            "ratio": median_s / 0.7, "solve_ratio": median_s / 0.7}


def test_replanning_rows_read_the_three_way_table_with_slashes_in_event_names():
    table = {"fig10/drift 5cm/5deg": {"runs": 3, "warm": _method(0.03, 3, 1),
                                      "cli": _method(0.09, 3, 1), "fresh": _method(0.7, 3, 1)}}
    rows = _figures()._replanning_rows({"time_limit": 10.0, "rows": [], "table": table})
    ((what, measured),) = rows
    assert what == "replanning: fig10, drift 5cm/5deg"
    assert "warm 0.03 s (3/3 ok, 0.04 of fresh)" in measured
    assert "plan file solve 0.09 s (3/3, 0.13 of fresh)" in measured


def test_the_figures_page_holds_the_table_and_how_long_its_run_took():
    table = "| what | measured | command |\n|---|---|---|\n| a | b | `c` |\n"
    page = _figures().page(table, minutes=7.4, partial=False)
    assert page.startswith("# Figures\n") and page.endswith(table)
    assert "This run took 7 min." in page and "`--only`" not in page
    assert "`--only`" in _figures().page(table, minutes=1, partial=True)


def test_the_figures_page_says_when_and_from_which_commit_it_was_made(tmp_path):
    table = "| what | measured | command |\n|---|---|---|\n| a | b | `c` |\n"
    made = "2026-12-07 13:00 UTC from commit abc1234"
    page = _figures().page(table, minutes=7.4, partial=False, made=made)
    assert f"Made on {made}:" in page.split(table)[0]  # above the table
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                          capture_output=True, check=False).stdout.strip()
    if head:  # a clone: its commit, said to have changes when it has
        assert _figures().made_from(ROOT).startswith(f"commit {head}")
    assert _figures().made_from(tmp_path) == "a tree without git"


def _run(seed: int, solved: bool, wall: float, regrasps: int | None = None,
         bound: int | None = None, ratio: float | None = None) -> dict:
    return {"seed": seed, "solved": solved, "wall": wall, "peak_mb": 200.0 + seed,
            "regrasps": regrasps, "bound": bound, "route_ratio": ratio}


def test_buildings_rows_give_each_map_its_runs_bound_and_memory():
    maps = {"house": {"width": 18.75, "depth": 11.2, "boxes": 137,
                      "runs": [_run(0, True, 1.5, 0, 0, 1.1), _run(1, True, 3.5, 0, 0, 1.2),
                               _run(2, False, 61.0)]},
            "arena": {"width": 5.45, "depth": 5.1, "boxes": 157,
                      "runs": [_run(0, False, 61.2), _run(1, False, 61.1)]}}
    rows = dict(_figures()._buildings_rows({"seeds": 3, "time": 60.0, "maps": maps}))
    house = rows["real map: house, 18.8 × 11.2 m, 137 boxes"]
    assert house.startswith("solved 2/3; median 2.5 s") and "(= bound in 2/2)" in house
    assert "route 1.15 × the bound" in house and house.endswith("peak 202 MB")
    assert rows["real map: arena, 5.5 × 5.1 m, 157 boxes"] == "solved 0/2; peak 201 MB"


def test_the_buildings_step_reads_the_json_its_script_writes_in_its_folder():
    step = {s.name: s for s in _figures().STEPS}["buildings"]
    assert step.out_is_dir and step.result == "buildings.json"


def test_the_validation_step_times_the_worlds_queries_and_writes_its_figures(tmp_path):
    """The figures' validation step wraps the world's distance query to time coal: it must
    pass the query's arguments on, whatever they are (it broke when they grew)."""
    import json
    import subprocess
    import sys

    out = tmp_path / "validation.json"
    subprocess.run([sys.executable, str(ROOT / "benchmarks" / "validation.py"), "--n", "20",
                    "--out", str(out)], check=True, capture_output=True, timeout=300)
    res = json.loads(out.read_text())
    assert res["motion_checks_per_s"] > 0 and 0.0 <= res["motion_valid_fraction"] <= 1.0

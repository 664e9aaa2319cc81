"""benchmarks/figures.py turns each script's JSON into table rows."""

from __future__ import annotations

from factories import benchmark_script


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

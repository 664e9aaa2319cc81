"""benchmarks/plan_quality.py: its scene groups and the table of issue 42's four measures."""

from __future__ import annotations

from factories import benchmark_script


def _row(**over) -> dict:
    row = {"runs": 3, "success": 1.0, "regrasps_median": 0, "regrasps_range": [0, 1],
           "bound_median": 0.0, "at_bound": 2 / 3, "route_ratio_median": 1.21,
           "route_ratio_max": 1.4, "rate_over_ideal_median": 1.3, "cost_median": 1036.0,
           "cost_spread": 0.05, "solve_median": 2.5, "pivots_median": 400,
           "duration_median": 1000.0}
    row.update(over)
    return row


def test_layouts_and_maps_expand_to_every_layout_and_the_shipped_maps():
    pq = benchmark_script("plan_quality")
    names = pq.scene_names("layouts,fig10,maps")
    assert {"hall", "bugtrap"} <= set(names) and "fig10" in names
    assert [n for n in names if n.startswith("map:")] == [
        f"map:{m}" for m in pq.SHIPPED_MAPS]
    corpus = {m.name for m in benchmark_script("buildings").CORPUS}
    assert set(pq.SHIPPED_MAPS) <= corpus  # imported through the buildings script's helper


def test_the_markdown_table_shows_bound_route_rate_and_spread():
    pq = benchmark_script("plan_quality")
    md = pq.markdown({"hall/after": _row()}, "python benchmarks/plan_quality.py --seeds 3")
    header, _, row = md.splitlines()[:3]
    assert "route ratio" in header and "spread" in header and "pivot rate" in header
    assert row.startswith("| hall | after | 3 | 0 (0-1) | 0 | 67 % | 1.21 (1.40) | 1.30 |")
    assert "| 5.0 % |" in row
    assert "`python benchmarks/plan_quality.py --seeds 3`" in md


def test_the_figures_route_rows_carry_the_four_measures():
    rows = benchmark_script("figures")._route_rows({"table": {
        "map:aws_small_house/before": _row(), "map:aws_small_house/after": _row()}})
    ((what, measured),) = rows
    assert what == "route quality: map:aws_small_house (3 seeds)"
    for part in ("at it in 67 %", "1.21 × the bound (worst 1.40)", "pivot rate 1.30",
                 "cost spread 5 %"):
        assert part in measured


def test_corpus_expands_to_every_corpus_map_that_has_a_plan():
    corpus = benchmark_script("buildings").CORPUS  # puts the benchmarks folder on the path
    names = benchmark_script("plan_quality").scene_names("fig10,corpus")
    assert names[0] == "fig10"
    maps = [n.removeprefix("map:") for n in names[1:]]
    assert maps == [m.name for m in corpus if m.feasible]
    assert {"turtlebot3_world", "brsu_c069"}.isdisjoint(maps)  # proven: no plan exists
    assert {"aws_bookstore", "nav2_depot", "willow_garage_2010", "brsu_c069_room"} <= set(maps)

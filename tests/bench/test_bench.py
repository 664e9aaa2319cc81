"""Tests of pivot_ompl.bench: OMPL log format, database, crashes, executors, CLI."""

from __future__ import annotations

import io
import math
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from factories import ROOT, benchmark_script  # noqa: E402

from pivot_ompl.bench import (
    STATUS,
    DaskExecutor,
    LocalExecutor,
    build_database,
    make_executor,
    parse_log,
    run_columns,
    run_sweep,
    summarize,
)
from pivot_ompl.bench.ompl_log import ExperimentLog, PlannerResults, fmt_value
from pivot_ompl.bench.progress import Progress
from pivot_ompl.cli.main import main as cli_main
from pivot_ompl.errors import InputError

OPEN = ROOT / "scenes" / "open.yaml"
CORRIDOR = ROOT / "scenes" / "corridor.yaml"
TIME = 1.0
RUNS = 3
PLANNERS = ["regrasp", "rrtconnect"]
#: Run properties that do not depend on timing for these deterministic runs.
STABLE = ("status ENUM", "solved BOOLEAN", "solution length REAL", "pivots INTEGER",
          "regrasps INTEGER", "graph states INTEGER", "seed INTEGER")


def _db_rows(db: Path, sql: str) -> list[tuple]:
    conn = sqlite3.connect(db)
    try:
        return conn.execute(sql).fetchall()
    finally:
        conn.close()


@pytest.fixture(scope="module")
def local_sweep(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("bench_local")
    res = run_sweep([OPEN], PLANNERS, runs=RUNS, time_limit=TIME, out=out,
                    executor=LocalExecutor(2), progress=False)
    return res, out


# --- the OMPL log format -------------------------------------------------------------------

GENUINE = textwrap.dedent("""
    import sys
    from ompl import tools as ot, util as ou
    from pivot_ompl.scene import load_scene
    from pivot_ompl.base.problem import make_setup
    from pivot_ompl.planners import make_planner

    def main():
        ou.RNG.setSeed(7)
        problem = make_setup(load_scene(sys.argv[1]), seed=0)
        ss = problem.setup
        planners = [make_planner("rrtconnect", problem), make_planner("regrasp", problem, seed=0)]
        b = ot.Benchmark(ss, "open")
        for p in planners:
            b.addPlanner(p)
        b.benchmark(ot.Request(1.0, 4096.0, 2, 0.05, False, False, False))
        b.saveResultsToFile(sys.argv[2])
        return b, problem, planners

    r = main()
""")


def test_writer_is_byte_compatible_with_ompl(tmp_path: Path) -> None:
    log_path = tmp_path / "genuine.log"
    subprocess.run([sys.executable, "-c", GENUINE, str(OPEN), str(log_path)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=60)
    text = log_path.read_text()
    log = parse_log(text)
    assert [p.name for p in log.planners] == ["geometric_RRTConnect", "geometric_RegraspPlanner"]
    assert [len(p.runs) for p in log.planners] == [2, 2]
    assert log.format() == text  # our writer reproduces OMPL's bytes


def test_writer_missing_values_and_types() -> None:
    p = PlannerResults("geometric_X", ["range = 1"],
                       [{"time REAL": "0.5", "solved BOOLEAN": "1"}, {"time REAL": "2"}])
    log = ExperimentLog("e", host="h", start="2026-01-01 00:00:00", setup="s\n", cpuinfo="c",
                        time_limit=2.0, runs_per_planner=2, planners=[p])
    text = log.format()
    assert "2 properties for each run\nsolved BOOLEAN\ntime REAL\n2 runs\n1; 0.5; \n; 2; \n.\n" \
        in text
    again = parse_log(text)
    assert again.planners[0].runs == p.runs
    assert again.format() == text
    assert [fmt_value(v) for v in (True, 3, 0.1234567, 1e-7, 30.0)] == \
        ["1", "3", "0.123457", "1e-07", "30"]


# --- a short benchmark -> ompl_benchmark_statistics database --------------------------------

def test_short_benchmark_database(local_sweep, tmp_path: Path) -> None:
    res, out = local_sweep
    log_path = out / "open.log"
    assert res.logs == {"open": log_path}
    # the tool shipped in the ompl wheel parses the log
    db = tmp_path / "tool.db"
    subprocess.run([sys.executable, "-m", "ompl.ompl_benchmark_statistics", "-d", str(db),
                    str(log_path)], check=True, stdout=subprocess.DEVNULL, timeout=60)
    for path in (db, res.database):
        names = _db_rows(path, "SELECT p.name, COUNT(*) FROM runs r JOIN plannerConfigs p "
                               "ON r.plannerid = p.id GROUP BY p.name ORDER BY p.name")
        assert names == [("geometric_RRTConnect", RUNS), ("geometric_RegraspPlanner", RUNS)]
        cols = set(run_columns(path))
        assert {"time", "solved", "status", "memory", "graph_states", "solution_length",
                "seed", "pivots", "regrasps", "planner_guards",
                "planner_critical_configurations", "planner_manipulation_nodes"} <= cols
        assert _db_rows(path, "SELECT runcount, timelimit, name FROM experiments") == \
            [(RUNS, TIME, "open")]
        assert ("status", STATUS["CRASH"], "Crash") in _db_rows(path, "SELECT * FROM enums")
        assert _db_rows(path, "SELECT COUNT(*) FROM bestPlannerConfigs")[0][0] == 2
        seeds = _db_rows(path, "SELECT seed FROM runs ORDER BY plannerid, seed")
        assert [s for (s,) in seeds] == [0, 1, 2, 0, 1, 2]
    # both planners solve the open scene; the table and the plots are there
    rows = {r.planner: r for r in res.rows}
    assert rows["regrasp"].success == 1.0 and rows["rrtconnect"].success == 1.0
    assert rows["regrasp"].regrasps == 0 and rows["regrasp"].pivots > 0
    assert "success" in (out / "summary.txt").read_text()
    for png in res.plots:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(res.plots) == 2


def test_same_seeds_same_results(local_sweep, tmp_path: Path) -> None:
    res, _ = local_sweep
    again = run_sweep([OPEN], PLANNERS, runs=1, time_limit=TIME, out=tmp_path, seed0=2,
                      executor=LocalExecutor(2), progress=False, plots=False)
    first = {(r["planner"], r["seed"]): r["run"] for r in res.results}
    for r in again.results:
        assert r["seed"] == 2
        assert {k: r["run"].get(k) for k in STABLE} == \
            {k: first[(r["planner"], 2)].get(k) for k in STABLE}


# --- crashes are recorded, not fatal --------------------------------------------------------

FAILING = textwrap.dedent('''
    import os
    import signal

    from ompl import base as ob


    class Raising(ob.Planner):
        def __init__(self, si):
            super().__init__(si, "Raising")

        def solve(self, ptc):
            raise RuntimeError("deliberate failure")


    class Segfault(ob.Planner):
        def __init__(self, si):
            super().__init__(si, "Segfault")

        def solve(self, ptc):
            os.kill(os.getpid(), signal.SIGSEGV)


    def raising(si, seed):
        return Raising(si)


    def segfault(si, seed):
        return Segfault(si)
''')


def test_planner_exception_is_a_crash_run(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "failing_planners.py").write_text(FAILING)
    monkeypatch.syspath_prepend(str(tmp_path))  # for the input check here
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))  # for the job processes
    planners = ["failing_planners:raising", "failing_planners:segfault", "rrtconnect"]
    res = run_sweep([OPEN], planners, runs=2, time_limit=TIME, out=tmp_path / "out",
                    executor=LocalExecutor(2), progress=False, plots=False)
    by = {}
    for r in res.results:
        by.setdefault(r["planner"], []).append(r)
    assert sorted(by) == ["raising", "rrtconnect", "segfault"]
    for name in ("raising", "segfault"):
        assert [r["run"]["status ENUM"] for r in by[name]] == [str(STATUS["CRASH"])] * 2
        assert all(r["error"] for r in by[name])
    assert "deliberate failure" in by["raising"][0]["error"]
    assert by["raising"][0]["planner_name"] == "geometric_Raising"  # OMPL saw the planner
    assert [r["run"]["status ENUM"] for r in by["rrtconnect"]] == \
        [str(STATUS["EXACT_SOLUTION"])] * 2
    assert res.crashed == 4
    rows = _db_rows(res.database, "SELECT p.name, r.status, COUNT(*) FROM runs r JOIN "
                                  "plannerConfigs p ON r.plannerid = p.id "
                                  "GROUP BY p.name, r.status ORDER BY p.name")
    assert rows == [("geometric_RRTConnect", STATUS["EXACT_SOLUTION"], 2),
                    ("geometric_Raising", STATUS["CRASH"], 2),
                    ("geometric_segfault", STATUS["CRASH"], 2)]


# --- Dask ----------------------------------------------------------------------------------

def test_dask_local_cluster_matches_local(local_sweep, tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    res, _ = local_sweep
    dres = run_sweep([OPEN], PLANNERS, runs=RUNS, time_limit=TIME, out=tmp_path,
                     executor=DaskExecutor(workers=2), progress=False, plots=False)

    def key(results):
        return {(r["planner"], r["seed"]): {k: r["run"].get(k) for k in STABLE}
                for r in results}

    assert key(dres.results) == key(res.results)
    assert len(dres.results) == len(PLANNERS) * RUNS
    # the same log structure: only times, memory and the like differ
    a, b = parse_log(res.logs["open"].read_text()), parse_log(dres.logs["open"].read_text())
    assert [(p.name, p.common, p.properties()) for p in a.planners] == \
        [(p.name, p.common, p.properties()) for p in b.planners]


def test_dask_missing_is_a_clear_input_error(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(InputError, match="distributed"):
        make_executor("dask")


# --- CLI, table, progress ------------------------------------------------------------------

def test_cli_bench(tmp_path: Path, capsys) -> None:
    out = tmp_path / "res"
    code = cli_main(["bench", str(OPEN), str(CORRIDOR), "--planners", "regrasp",
                     "--runs", "1", "--time", "2", "--out", str(out), "--workers", "2",
                     "--no-progress", "--no-plots"])
    assert code == 0
    text = capsys.readouterr().out
    assert "open" in text and "corridor" in text and "regrasp" in text
    assert (out / "open.log").exists() and (out / "corridor.log").exists()
    assert _db_rows(out / "benchmark.db", "SELECT COUNT(*) FROM experiments") == [(2,)]


@pytest.mark.parametrize("argv", [
    ["--planners", "nosuch"], ["--runs", "0"], ["--time", "-1"], ["--workers", "0"],
    ["--scheduler", "tcp://127.0.0.1:1"], ["--seed0", "-3"], ["--executor", "ray"]])
def test_cli_bad_input_exit_2(argv: list[str], tmp_path: Path) -> None:
    with pytest.raises(SystemExit) as e:
        raise SystemExit(cli_main(["bench", str(OPEN), "--out", str(tmp_path), *argv]))
    assert e.value.code == 2


def test_cli_missing_scene_exit_2(tmp_path: Path) -> None:
    assert cli_main(["bench", str(tmp_path / "none.yaml"), "--out", str(tmp_path)]) == 2


def test_build_database_append(local_sweep, tmp_path: Path) -> None:
    res, _ = local_sweep
    db = build_database(tmp_path / "a.db", [res.logs["open"]])
    build_database(db, [res.logs["open"]], append=True)
    assert _db_rows(db, "SELECT COUNT(*) FROM runs") == [(2 * 2 * RUNS,)]


def test_summary_rows() -> None:
    def r(planner, status, t, piv=None):
        run = {"status ENUM": str(STATUS[status]), "time REAL": str(t)}
        if piv is not None:
            run["pivots INTEGER"] = str(piv)
        return {"scene": "s", "planner": planner, "seed": 0, "run": run}

    rows = summarize([r("a", "EXACT_SOLUTION", 1.0, 10), r("a", "TIMEOUT", 3.0),
                      r("a", "CRASH", 0.5), r("a", "EXACT_SOLUTION", 2.0, 20)])
    (row,) = rows
    assert (row.runs, row.solved, row.crashed, row.success) == (4, 2, 1, 0.5)
    assert row.median_time == 1.5 and row.pivots == 15 and math.isnan(row.length)


def test_progress_eta() -> None:
    buf = io.StringIO()
    p = Progress(4, stream=buf, period=0.0, width=8)
    p.update(1, "x")
    p.update(1, "y")
    line = buf.getvalue().splitlines()[-1]
    assert "2/4" in line and "50%" in line and "ETA" in line and "[####....]" in line


def test_recipe_under_ompl_benchmark(tmp_path: Path) -> None:
    out = tmp_path / "recipe"
    subprocess.run([sys.executable, str(ROOT / "benchmarks" / "ompl_benchmark.py"), str(OPEN),
                    "--planners", "regrasp,visprm,rrtconnect,kpiece1", "--runs", "2",
                    "--time", "1", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120)
    db = out / "open.db"
    rows = _db_rows(db, "SELECT p.name, COUNT(*), SUM(r.solved) FROM runs r JOIN "
                        "plannerConfigs p ON r.plannerid = p.id GROUP BY p.name ORDER BY p.name")
    assert rows == [("geometric_KPIECE1", 2, 2), ("geometric_RRTConnect", 2, 2),
                    ("geometric_RegraspPlanner", 2, 2), ("geometric_VisibilityPRM", 2, 2)]
    assert {"pivots", "regrasps", "seed", "planner_guards"} <= set(run_columns(db))
    seeds = _db_rows(db, "SELECT r.seed FROM runs r JOIN plannerConfigs p ON r.plannerid = p.id "
                         "WHERE p.name = 'geometric_VisibilityPRM' ORDER BY r.id")
    assert seeds == [(1,), (2,)]


def test_invalid_start_is_recorded_as_ompl_status(tmp_path: Path) -> None:
    from pivot_ompl.bench import Job, run_job

    text = OPEN.read_text().replace("name: open", "name: blocked") + (
        "obstacles:\n  - {type: box, center: [0.0, 0.0], size: [1.0, 1.0], yaw: 0.0, "
        "height: 2.0}\n")
    res = run_job(Job("blocked", text, "regrasp", 0, TIME))
    assert res["run"]["status ENUM"] == str(STATUS["INVALID_START"])
    assert "INVALID_START" in res["error"]


def _paper_table(text: str) -> list[dict[str, str]]:
    section = text.split("## 3. Paper comparison", 1)[1].split("\n## ", 1)[0]
    lines = [ln for ln in section.splitlines() if ln.startswith("|")]
    head = [c.strip() for c in lines[0].strip("|").split("|")]
    return [dict(zip(head, (c.strip() for c in ln.strip("|").split("|")), strict=True))
            for ln in lines[2:]]


def test_readme_paper_comparison_is_consistent_with_the_benchmark_script() -> None:
    """The paper's row carries the script's figures; our rows are well-formed measurements."""
    script = benchmark_script("regrasp")
    rows = _paper_table((ROOT / "benchmarks" / "README.md").read_text())
    (paper,) = [r for r in rows if r["planner"].startswith("regrasp paper")]
    assert float(paper["mean time (s)"]) == script.PAPER["mean_time"]
    assert float(paper["failures"].rstrip(" %")) == 100 * script.PAPER["failure_rate"]
    ours = [r for r in rows if "(ours)" in r["planner"]]
    assert ours
    for r in ours:
        runs = int(r["runs"])
        success, failures = (float(r[k].rstrip(" %")) for k in ("success", "failures"))
        assert success + failures == 100 and runs >= 20
        median, p95 = float(r["median time (s)"]), float(r["p95 time (s)"])
        assert 0 < median <= p95 and float(r["mean time (s)"]) > 0


def test_readme_paper_comparison_command_parses() -> None:
    import shlex

    from pivot_ompl.cli.main import build_parser

    text = (ROOT / "benchmarks" / "README.md").read_text()
    section = text.split("## 3. Paper comparison", 1)[1].split("\n## ", 1)[0]
    cmd = section.split("```sh\n", 1)[1].split("\n#", 1)[0].replace("\\\n", " ")
    argv = shlex.split(cmd)
    assert argv[:2] == ["pivot-ompl", "bench"]
    args = build_parser().parse_args(argv[1:])
    assert [Path(s).name for s in args.scenes] == ["fig10.yaml"]
    assert (ROOT / args.scenes[0]).exists()
    assert (args.runs, args.time) == (100, 30.0)


def test_param_sweeps_give_one_named_configuration_per_value():
    from pivot_ompl.cli.bench import expand_params

    got = expand_params(["regrasp", "rrtconnect"], ["search.weight=1.5,2", "search.turns=false"],
                        regrasp_cost=60.0)
    assert got == ["regrasp[search.weight=1.5;search.turns=false;cost.regrasp=60]",
                   "regrasp[search.weight=2;search.turns=false;cost.regrasp=60]", "rrtconnect"]
    with pytest.raises(InputError):
        expand_params(["rrtconnect"], ["search.weight=1.5"])
    with pytest.raises(InputError):
        expand_params(["regrasp"], ["search.weight"])


def test_a_configured_planner_runs_under_its_own_name_with_its_parameters(tmp_path):
    from pivot_ompl.bench.job import Job, execute

    text = (Path(__file__).resolve().parents[2] / "scenes" / "slot.yaml").read_text()
    res = execute(Job("slot", text, "regrasp[search.weight=1.5]", 0, 10.0))
    assert res["planner_name"] == "geometric_RegraspPlanner[search.weight=1.5]"
    assert "search.weight = 1.5" in res["common"]
    assert res["run"]["solved BOOLEAN"] == "1"


def test_cli_bench_time_inf_is_the_plan_limit(tmp_path: Path) -> None:
    """``--time inf`` means "until solved", as for ``plan`` (the 1e6 s limit), not an error."""
    out = tmp_path / "res"
    code = cli_main(["bench", str(OPEN), "--planners", "regrasp", "--runs", "1", "--time", "inf",
                     "--out", str(out), "--workers", "1", "--no-progress", "--no-plots"])
    assert code == 0
    assert "1e+06 seconds per run" in (out / "open.log").read_text()

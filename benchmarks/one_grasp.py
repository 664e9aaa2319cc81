"""Where one grasp suffices: our planner against OMPL's RRT-Connect, side by side.

For each map of ``--maps`` (names of :data:`buildings.CORPUS`, imported at their corpus start
and goal) and each version (``--before DIR``, a package tree put on ``PYTHONPATH``, e.g. an
export of an older commit, repeatable; then this checkout), runs
``pivot-ompl bench SCENE --planners P --runs N --time T --workers 1 --no-plots`` (a fresh
process per run: OMPL's ``Benchmark`` times ``solve``, cold caches every run) and prints per
map, version and planner the median solve time, the median pivots, the median regrasps, the
median execution estimate of the plan (``quality duration estimate``, s: what the robot then
spends carrying it out) and the ratios to RRT-Connect's (time ours / theirs; pivots theirs /
ours). Maps and versions take
turns, one ``bench`` at a time (set ``PIVOT_BENCH_LOCK`` to hold that lock during each).

``--cpu``: instead of ``bench``, one fresh process per (planner, seed) that sets the problem and
the planner up as ``bench`` does and times ``solve`` in CPU seconds (``time.process_time``:
other load on a shared machine counts less than in OMPL's wall-clock ``time``); the columns
are the same.

    PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock python benchmarks/one_grasp.py \
        [--before /tmp/base] [--maps aws_small_house,nav2_depot] \
        [--planners 'regrasp,regrasp[optimiser.routes=false],rrtconnect'] [--runs 5]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from buildings import CORPUS, ROOT, import_corpus_map  # noqa: E402
from common import machine_lock  # noqa: E402

MAPS = ("aws_small_house", "aws_small_warehouse", "nav2_depot", "aws_hospital")
REFERENCE = "rrtconnect"


def bench(scene: str, version: Path, planners: str, runs: int, limit: float,
          out: Path) -> list[dict[str, Any]]:
    """One ``pivot-ompl bench`` of ``scene`` with the package at ``version``: its runs."""
    env = dict(os.environ, PYTHONPATH=str(version))
    cmd = [sys.executable, "-m", "pivot_ompl", "bench", scene, "--planners", planners,
           "--runs", str(runs), "--time", str(limit), "--workers", "1", "--no-plots",
           "--no-progress", "--out", str(out)]
    with machine_lock():
        subprocess.run(cmd, env=env, check=False, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
    path = out / "runs.json"
    return json.loads(path.read_text()) if path.exists() else []


def cpu_run(scene: str, planner: str, seed: int, limit: float) -> dict[str, str]:
    """One ``solve`` in this process, as ``bench`` sets it up: CPU seconds and the plan's."""
    import time

    import yaml
    from ompl import util as ou

    from pivot_ompl.base.problem import make_setup
    from pivot_ompl.bench.job import allocator, run_extras
    from pivot_ompl.scene import scene_from_dict

    ou.setLogLevel(ou.LogLevel.LOG_ERROR)
    ou.RNG.setSeed(seed + 1)
    loaded = scene_from_dict(yaml.safe_load(Path(scene).read_text()), source=scene)
    problem = make_setup(loaded, seed=seed)
    chosen = allocator(planner)(problem, seed)
    problem.setup.setPlanner(chosen)
    problem.setup.setup()  # as Benchmark does before its clock starts
    t0 = time.process_time()
    solved = bool(problem.setup.solve(limit)) and problem.setup.haveExactSolutionPath()
    run = {"time REAL": str(time.process_time() - t0), "solved BOOLEAN": "1" if solved else "0"}
    run.update(run_extras(loaded, problem, chosen, seed))
    return run


def cpu_bench(scene: str, version: Path, planners: str, runs: int,
              limit: float) -> list[dict[str, Any]]:
    """:func:`cpu_run` per planner and seed ``0 .. runs-1``, each in a fresh process."""
    env = dict(os.environ, PYTHONPATH=str(version))
    out = []
    for seed in range(runs):
        for planner in planners.split(","):
            cmd = [sys.executable, str(Path(__file__).resolve()), "--cpu-run", scene, planner,
                   str(seed), str(limit)]
            with machine_lock():
                proc = subprocess.run(cmd, env=env, check=False, capture_output=True, text=True)
            lines = proc.stdout.strip().splitlines()
            run = json.loads(lines[-1]) if proc.returncode == 0 and lines else \
                {"time REAL": "nan", "solved BOOLEAN": "0"}
            out.append({"planner": planner, "run": run})
    return out


def medians(runs: list[dict[str, Any]]) -> dict[str, dict[str, float]]:
    """Per planner: runs, solved, median time (s), pivots, regrasps, execution (s) if solved."""
    out: dict[str, dict[str, float]] = {}
    for name in dict.fromkeys(r["planner"] for r in runs):
        mine = [r["run"] for r in runs if r["planner"] == name]
        solved = [r for r in mine if r.get("solved BOOLEAN") == "1"]

        def med(key: str, rows: list[dict[str, str]]) -> float:
            vals = [float(r[key]) for r in rows if key in r]
            return statistics.median(vals) if vals else float("nan")

        out[name] = {"runs": len(mine), "solved": len(solved), "time": med("time REAL", mine),
                     "pivots": med("pivots INTEGER", solved),
                     "regrasps": med("regrasps INTEGER", solved),
                     "execution": med("quality duration estimate REAL", solved)}
    return out


def table(results: list[dict[str, Any]]) -> str:
    """The Markdown table of :func:`main`'s results."""
    lines = ["| map | version | planner | solved | median time (s) | median pivots | "
             "regrasps | execution (s) | time / RRT-Connect's | RRT-Connect's pivots / ours |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for res in results:
        ref = res["planners"].get(REFERENCE, {})
        for name, m in res["planners"].items():
            ratio = pivots = "-"
            if name != REFERENCE and ref:
                ratio = f"{m['time'] / ref['time']:.2f}"
                pivots = f"{ref['pivots'] / m['pivots']:.1f}"
            lines.append(f"| {res['map']} | {res['version']} | {name} | "
                         f"{m['solved']}/{m['runs']} | {m['time']:.3f} | {m['pivots']:.0f} | "
                         f"{m['regrasps']:.0f} | {m['execution']:.0f} | {ratio} | {pivots} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Import the maps, bench each version on each, print the table (and ``--out``)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to bench before this checkout (repeatable)")
    ap.add_argument("--maps", default=",".join(MAPS), help="corpus map names, comma-separated")
    ap.add_argument("--planners", default=f"regrasp,{REFERENCE}",
                    help=f"bench's --planners (include {REFERENCE} for the ratios)")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--out", type=Path, default=None, help="write the results as JSON too")
    ap.add_argument("--cpu", action="store_true",
                    help="CPU seconds of solve, a fresh process per run, instead of bench")
    ap.add_argument("--cpu-run", nargs=4, metavar=("SCENE", "PLANNER", "SEED", "TIME"),
                    help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.cpu_run:
        scene, planner, seed, limit = a.cpu_run
        print(json.dumps(cpu_run(scene, planner, int(seed), float(limit))))
        return 0
    names = [n for n in a.maps.split(",") if n]
    corpus = {m.name: m for m in CORPUS}
    unknown = [n for n in names if n not in corpus]
    if unknown:
        print(f"--maps: unknown {unknown} (known: {sorted(corpus)})", file=sys.stderr)
        return 2
    versions = [*a.before, ROOT]
    results: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory(prefix="one-grasp-") as tmp:
        work = Path(tmp)
        for name in names:
            scene = import_corpus_map(corpus[name], work)["scene"]
            for k, version in enumerate(versions):
                label = "this" if version == ROOT else version.name
                runs = cpu_bench(scene, version, a.planners, a.runs, a.time) if a.cpu else \
                    bench(scene, version, a.planners, a.runs, a.time, work / f"{name}.{k}")
                results.append({"map": name, "version": label, "planners": medians(runs)})
                print(table(results[-1:]).splitlines()[-1], flush=True)
    print(table(results))
    if a.out is not None:
        tmp_out = a.out.with_suffix(a.out.suffix + ".tmp")
        tmp_out.write_text(json.dumps(results, indent=1))
        tmp_out.replace(a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Our planners beside OMPL's under OMPL's own ``ompl.tools.Benchmark`` (the recipe).

Usage::

    python benchmarks/ompl_benchmark.py [SCENE] [--planners regrasp,visprm,rrtconnect,kpiece1]
        [--runs 10] [--time 5] [--seed 1] [--out results/recipe]

Writes ``<out>/<scene>.log`` (``Benchmark.saveResultsToFile``) and ``<out>/<scene>.db`` (what
``ompl_benchmark_statistics -d <scene>.db <scene>.log`` builds; open it in Planner Arena).
Our figures (``seed``, ``pivots``, ``regrasps``, ``plan valid``, the planners' ``planner ...``
roadmap figures such as ``planner critical configurations``, the checker's counters) are
added to every run record before saving, so they are columns of the ``runs`` table.

The rules that keep ``Benchmark`` alive over many runs:
* everything the Benchmark points to (SimpleSetup, Python validators, planners, the
  projection) stays referenced until the log is saved: all of it lives in ``main``'s frame;
* OMPL's seed is set first (``ou.RNG.setSeed`` works only before the first random number);
  our planners take their seed per run from the pre-run event (else every run is the same);
* a Python planner's exception aborts ``benchmark()``: ours catch and return ``CRASH``;
* PRM is not in the default list: in this build its roadmap thread calls the Python validity
  checker without the GIL and deadlocks (``pivot-ompl bench`` runs it anyway, each run in its
  own process, and records ``Crash`` when the process is killed);
* the KPIECE family needs a default projection, which the compound space lacks: we register
  OMPL's ``SubspaceProjectionEvaluator`` on the Reeds-Shepp component.

``pivot-ompl bench`` does the same with one fresh process per run (seeded, parallel or on a
Dask cluster) and writes the same log format.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ompl import tools as ot
from ompl import util as ou

from pivot_ompl.base.problem import make_setup
from pivot_ompl.bench import build_database, run_extras
from pivot_ompl.planners import make_planner
from pivot_ompl.scene import load_scene


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?", default="corridor")
    ap.add_argument("--planners", default="regrasp,visprm,rrtconnect,kpiece1")
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--time", type=float, default=5.0)
    ap.add_argument("--seed", type=int, default=1, help="OMPL's seed (> 0) and our first seed")
    ap.add_argument("--out", default="results/recipe")
    args = ap.parse_args(argv)

    ou.RNG.setSeed(max(args.seed, 1))  # before anything draws a random number
    ou.setLogLevel(ou.LogLevel.LOG_WARN)
    scene = load_scene(args.scene)
    problem = make_setup(scene, seed=args.seed)  # owns ss, validators and the projection
    ss = problem.setup
    planners = [make_planner(n.strip(), problem, seed=args.seed)
                for n in args.planners.split(",") if n.strip()]

    bench = ot.Benchmark(ss, scene.name)
    for p in planners:
        bench.addPlanner(p)
    extras: dict[str, list[dict[str, str]]] = {}  # planner name -> one dict per run

    def pre_run(planner) -> None:
        # our planners are deterministic for a seed: give run i the seed args.seed + i
        i = len(extras.get(planner.getName(), []))
        if hasattr(planner, "seed"):
            planner.seed = args.seed + i

    def post_run(planner, run) -> None:
        mine = extras.setdefault(planner.getName(), [])
        seed = args.seed + len(mine)
        try:
            mine.append(run_extras(scene, problem, planner, seed))
        except Exception as e:  # noqa: BLE001 - an exception here would abort the benchmark
            print(f"post-run event: {e}", file=sys.stderr)
            mine.append({"seed INTEGER": str(seed)})

    bench.setPreRunEvent(pre_run)
    bench.setPostRunEvent(post_run)
    # maxTime, maxMem (MB), runCount, timeBetweenUpdates, displayProgress, saveConsoleOutput
    # (off: it writes ompl_<host>_<date>.console into the cwd), simplify (off: a simplified
    # path is not the planner's plan)
    request = ot.Request(args.time, 4096.0, args.runs, 0.05, True, False, False)
    bench.benchmark(request)

    # add our columns: getRecordedExperimentData() is the Benchmark's own record
    exp = bench.getRecordedExperimentData()
    for planner_exp in exp.planners:  # named "geometric_<planner name>"
        mine = extras.get(planner_exp.name.split("_", 1)[1], [])
        for run, values in zip(planner_exp.runs, mine, strict=False):
            for key, value in values.items():
                run[key] = value
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    log_path = out / f"{scene.name}.log"
    bench.saveResultsToFile(str(log_path))
    db = build_database(out / f"{scene.name}.db", [log_path])  # = ompl_benchmark_statistics
    print(f"log: {log_path}\ndatabase: {db}")
    bench = None  # the Benchmark goes first; the problem and planners after it
    return 0


if __name__ == "__main__":
    sys.exit(main())

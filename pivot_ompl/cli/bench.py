"""``pivot-ompl bench SCENE... --planners regrasp,rrtconnect --runs 50 --time 30 --out results/``.

Writes an OMPL benchmark log per scene, the ``ompl_benchmark_statistics`` database, the
summary table (also printed) and PNG plots into ``--out``. Exit codes: 0 every run went
through, 1 some run crashed (the outputs are still written), 2 bad input.
"""

from __future__ import annotations

import argparse
import logging
import sys

from pivot_ompl.cli.args import positive
from pivot_ompl.errors import InputError

log = logging.getLogger(__name__)

#: Ours and OMPL's that run on our space (``prm`` deadlocks with Python validators in this
#: build: give it explicitly to record its crashes).
DEFAULT_PLANNERS = "regrasp,visprm,rrtconnect,kpiece1"


def _count(name: str, minimum: int) -> object:
    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: not an integer") from None
        if v < minimum:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be >= {minimum}")
        return v

    return conv


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``bench`` verb."""
    p = sub.add_parser(
        "bench", help="benchmark planners on scenes (OMPL log, database, table, plots)",
        description="Benchmark planners on scenes: an OMPL log per scene, the "
                    "ompl_benchmark_statistics database, a summary table and PNG plots.")
    p.add_argument("scenes", nargs="+", metavar="SCENE", help="scene YAML files")
    p.add_argument("--planners", default=DEFAULT_PLANNERS,
                   help="comma-separated planner names (or module:factory) "
                        f"[default: {DEFAULT_PLANNERS}]")
    p.add_argument("--runs", type=_count("--runs", 1), default=50, help="runs per planner")
    p.add_argument("--time", type=positive("--time"), default=30.0,
                   help="time limit per run (s)")
    p.add_argument("--out", default="results",
                   help="output directory, new or empty unless --overwrite [default: results]")
    p.add_argument("--overwrite", action="store_true",
                   help="replace a previous sweep's outputs in --out (after the new one ends)")
    p.add_argument("--executor", choices=["local", "dask"], default="local",
                   help="local processes, or a Dask cluster [default: local]")
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address (tcp://host:8786); without it, a LocalCluster")
    p.add_argument("--workers", type=_count("--workers", 1), default=None,
                   help="parallel jobs (local) or LocalCluster workers [default: the cores]")
    p.add_argument("--seed0", type=_count("--seed0", 0), default=0,
                   help="seed of the first run (run i uses seed0 + i)")
    p.add_argument("--memory", type=positive("--memory"), default=4096.0,
                   help="OMPL's memory limit per run (MB)")
    p.add_argument("--simplify", action="store_true",
                   help="let OMPL's Benchmark simplify solutions (adds its columns)")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the sweep; print the table and where the outputs are."""
    from pivot_ompl.bench.executors import make_executor
    from pivot_ompl.bench.sweep import run_sweep

    planners = [p.strip() for p in args.planners.split(",") if p.strip()]
    if not planners:
        raise InputError("--planners", args.planners, "give at least one planner")
    if args.scheduler and args.executor != "dask":
        raise InputError("--scheduler", args.scheduler, "needs --executor dask")
    from pivot_ompl.bench.sweep import check_out_folder

    check_out_folder(args.out, overwrite=args.overwrite)  # before starting a Dask cluster
    executor = make_executor(args.executor, scheduler=args.scheduler, workers=args.workers)
    if not log.isEnabledFor(logging.DEBUG):  # Dask's INFO chatter would bury the progress bar
        logging.getLogger("distributed").setLevel(logging.WARNING)
    res = run_sweep(args.scenes, planners, runs=args.runs, time_limit=args.time, out=args.out,
                    executor=executor, seed0=args.seed0, memory_limit=args.memory,
                    simplify=args.simplify, progress=not args.no_progress,
                    plots=not args.no_plots, overwrite=args.overwrite)
    sys.stdout.write(res.table)
    print(f"{len(res.results)} runs in {res.wall:.1f} s; logs: "
          + ", ".join(str(p) for p in res.logs.values()))
    print(f"database: {res.database}   (Planner Arena: plannerarena.org)")
    if res.plots:
        print("plots: " + ", ".join(str(p) for p in res.plots))
    if res.crashed:
        print(f"pivot-ompl bench: {res.crashed} run(s) crashed (status Crash in the log)",
              file=sys.stderr)
        return 1
    return 0

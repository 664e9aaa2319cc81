"""``pivot-ompl bench SCENE [...] --planners regrasp,rrtconnect --runs 50 --time 30 --out DIR``.

Writes an OMPL benchmark log per scene, the ``ompl_benchmark_statistics`` database, the
summary table (also printed) and PNG plots into ``--out``. Exit codes: 0 every run went
through, 1 some run crashed (the outputs are still written), 2 bad input.
"""

from __future__ import annotations

import argparse
import logging
import sys

from pivot_ompl.cli.args import non_negative, positive, time_limit
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


def _split_specs(text: str) -> list[str]:
    """Comma-separated planner specs (commas inside brackets belong to a spec)."""
    out, depth, cur = [], 0, ""
    for ch in text:
        depth += {"[": 1, "]": -1}.get(ch, 0)
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    return [*out, cur]


def expand_params(planners: list[str], params: list[str], *,
                  regrasp_cost: float | None = None) -> list[str]:
    """The planner specs with every combination of the ``--param`` values.

    Only the configurable planners (the regrasp planner) take parameters; the others are
    kept as given.

    Raises:
        InputError: a malformed ``--param``, or parameters and no planner to take them.
    """
    import itertools

    from pivot_ompl.planners import parse_spec, planner_spec
    from pivot_ompl.planners.registry import CONFIGURABLE

    grid: list[list[tuple[str, str]]] = []
    for item in params:
        name, eq, text = item.partition("=")
        vals = [v.strip() for v in text.split(",") if v.strip()]
        if not eq or not name.strip() or not vals:
            raise InputError("--param", item, "write NAME=V1,V2 (e.g. search.weight=1.5,2)")
        grid.append([(name.strip(), v) for v in vals])
    if regrasp_cost is not None:
        grid.append([("cost.regrasp", f"{regrasp_cost:g}")])
    if not grid:
        return planners
    if not any(parse_spec(p)[0] in CONFIGURABLE for p in planners if ":" not in p):
        raise InputError("--param", ",".join(params) or "--regrasp-cost",
                         f"none of the planners takes parameters (only {sorted(CONFIGURABLE)})")
    out = []
    for p in planners:
        if ":" in p:
            out.append(p)
            continue
        base, given = parse_spec(p)
        if base not in CONFIGURABLE:
            out.append(p)
            continue
        for combo in itertools.product(*grid):
            out.append(planner_spec(base, {**given, **dict(combo)}))
    return out


def parameter_table(width: int = 100) -> str:
    """``--param help``: every sweepable parameter with its default and range, and what it is."""
    import textwrap

    from pivot_ompl.cli.main import plain
    from pivot_ompl.planners.config import parameters

    params = parameters()
    name_w = max(len(p.name) for p in params)
    default_w = max(len(_shown(p.default)) for p in params)
    lines = ["Parameters of the regrasp planner: --param NAME=V1,V2 sweeps NAME over the "
             "values (a tuple: V1 V2 in one value; a flag: true or false).",
             f"{'NAME':<{name_w}}  {'DEFAULT':<{default_w}}  RANGE"]
    for p in params:
        rng = "true or false" if isinstance(p.default, bool) else \
            "grasp indices 0 1 2 3" if p.range is None else str(p.range)
        lines.append(f"{p.name:<{name_w}}  {_shown(p.default):<{default_w}}  {rng}")
        if p.doc:
            lines.extend(textwrap.wrap(plain(p.doc), width, initial_indent=" " * 4,
                                       subsequent_indent=" " * 4))
    return "\n".join(lines) + "\n"


def _shown(value: object) -> str:
    """A default as ``--param`` takes it (a tuple's items space-separated)."""
    if isinstance(value, tuple):
        return " ".join(_shown(v) for v in value)
    if isinstance(value, bool):
        return str(value).lower()
    return f"{value:g}" if isinstance(value, float) else str(value)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``bench`` verb."""
    p = sub.add_parser(
        "bench", help="benchmark planners on scenes (OMPL log, database, table, plots)",
        description="Benchmark planners on scenes: an OMPL log per scene, the "
                    "ompl_benchmark_statistics database, a summary table and PNG plots.")
    p.add_argument("scenes", nargs="*", metavar="SCENE",
                   help="scene files or shipped scenes' names (at least one)")
    p.add_argument("--planners", default=DEFAULT_PLANNERS,
                   help="comma-separated planner names (or module:factory) "
                        f"[default: {DEFAULT_PLANNERS}]")
    p.add_argument("--param", action="append", default=[], metavar="NAME=V1,V2",
                   help="sweep a parameter of the regrasp planner (a dotted name of "
                        "RegraspConfig, e.g. search.weight=1.5,2): one planner "
                        "configuration per value, each under its own name; repeat for a "
                        "grid of configurations; --param help lists the parameters with "
                        "their defaults and ranges")
    p.add_argument("--regrasp-cost", type=non_negative("--regrasp-cost"), default=None,
                   metavar="S", help="price of one regrasp (s) for the regrasp planner")
    p.add_argument("--runs", type=_count("--runs", 1), default=50, help="runs per planner")
    p.add_argument("--time", type=time_limit("--time"), default=30.0,
                   help="time limit per run (s; inf or above 1e6 s: 1e6 s, as for plan)")
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
    """Run the sweep; print the table and where the outputs are (``--param help``: list)."""
    from pivot_ompl.bench.executors import make_executor
    from pivot_ompl.bench.processes import terminate_as_interrupt
    from pivot_ompl.bench.sweep import run_sweep

    if "help" in (p.strip() for p in args.param):
        sys.stdout.write(parameter_table())
        return 0
    if not args.scenes:
        raise InputError("SCENE", [], "give at least one scene file or shipped scene's name")

    planners = [p.strip() for p in _split_specs(args.planners) if p.strip()]
    if not planners:
        raise InputError("--planners", args.planners, "give at least one planner")
    planners = expand_params(planners, args.param, regrasp_cost=args.regrasp_cost)
    if args.scheduler and args.executor != "dask":
        raise InputError("--scheduler", args.scheduler, "needs --executor dask")
    from pivot_ompl.bench.sweep import check_out_folder

    check_out_folder(args.out, overwrite=args.overwrite)  # before starting a Dask cluster
    executor = make_executor(args.executor, scheduler=args.scheduler, workers=args.workers)
    if not log.isEnabledFor(logging.DEBUG):  # Dask's INFO chatter would bury the progress bar
        logging.getLogger("distributed").setLevel(logging.WARNING)
    with terminate_as_interrupt():  # SIGTERM cleans up as Ctrl-C does
        res = run_sweep(args.scenes, planners, runs=args.runs,
                        time_limit=args.time, out=args.out,
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

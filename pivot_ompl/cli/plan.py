"""``pivot-ompl plan SCENE``: plan with our planners or OMPL's.

Exit status: 0 found, 1 none, 2 bad input. ``--out`` and ``--plot`` are checked before planning
(not a directory, not the scene file, a known figure extension) and written only when a plan is
found, each through a temporary file: a failed run leaves existing files as they were. One
exception: when no plan exists (``INFEASIBLE``, proven by the relaxation), ``--plot`` draws the
scene with the passage that blocks every plan marked.
"""

from __future__ import annotations

import argparse
import logging
import sys
import threading
import time

from pivot_ompl.api import MAX_SEED, PlanResult, plan
from pivot_ompl.cli.args import integer, non_negative, output_files, time_limit
from pivot_ompl.cli.terminal import control_stream
from pivot_ompl.cost import REGRASP_COST
from pivot_ompl.errors import InputError, PlanningError, counted
from pivot_ompl.fileio import atomic_outputs
from pivot_ompl.planners import PLANNERS
from pivot_ompl.planners.explain import explain_lines
from pivot_ompl.planners.registry import parse_spec, planner_spec
from pivot_ompl.scene import scene_path

log = logging.getLogger(__name__)

#: The largest ``--quality-share`` (the search keeps a twentieth of the checks at least).
MAX_QUALITY_SHARE = 0.95


def share_of_checks(text: str) -> float:
    """An argparse type for ``--quality-share``: a number in 0..0.95."""
    v = non_negative("--quality-share")(text)
    if v > MAX_QUALITY_SHARE:
        raise argparse.ArgumentTypeError(f"--quality-share = {text}: must be <= "
                                         f"{MAX_QUALITY_SHARE:g}")
    return v


def planner_with_share(planner: str, share: float | None) -> str:
    """``planner`` with ``optimiser.quality_share`` set when ``share`` is given.

    Raises:
        InputError: a share for a planner other than the regrasp planner.
    """
    if share is None:
        return planner
    name, values = parse_spec(planner)
    if name != "regrasp":
        raise InputError("--quality-share", share, f"applies to the regrasp planner only, "
                         f"not {name!r}")
    return planner_spec(name, {**values, "optimiser.quality_share": share})


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``plan`` verb."""
    p = sub.add_parser("plan", help="plan a pivoting path with regrasps for a scene")
    p.add_argument("scene", help="scene file (YAML) or shipped scene's name, e.g. fig10")
    p.add_argument("--planner", default="regrasp",
                   help=f"planner: one of {', '.join(sorted(PLANNERS))}, "
                        "or the regrasp planner with parameters, e.g. "
                        "'regrasp[search.weight=1.5]'")
    p.add_argument("--regrasp-cost", type=non_negative("--regrasp-cost"), default=None,
                   metavar="S", help="price of one regrasp on top of its execution seconds "
                                     f"(s, >= 0; default {REGRASP_COST:g})")
    p.add_argument("--time", type=time_limit("--time"), default=30.0,
                   help="time limit (s) of loading, setup and search; inf: until solved")
    p.add_argument("--seed", type=integer("--seed", 0, MAX_SEED), default=0,
                   help=f"seed (0..{MAX_SEED})")
    p.add_argument("--quality-share", type=share_of_checks, default=None,
                   help="share (0..0.95) of the time limit that improving the path found "
                        "may take, and the scale of its budgets of motion checks (default "
                        "0.6; the regrasp planner's optimiser.quality_share, see "
                        "docs/quality.md)")
    p.add_argument("--no-bound", action="store_true",
                   help="skip the scene's lower bounds on regrasps and route and the proof "
                        "that no plan exists (computed once per scene within --time, then "
                        "cached)")
    proving = p.add_mutually_exclusive_group()
    proving.add_argument("--prove", action="store_true", default=None,
                         help="when the plan regrasps more often than the quick bounds "
                              "prove, refine the bound where its best path passes narrow "
                              "places until --time ends, even where its estimate does not "
                              "fit (as 'bound --guided'; cached for later plans). By "
                              "default it runs when its estimate fits what --time leaves")
    proving.add_argument("--no-prove", action="store_false", dest="prove",
                         help="never refine the bound inside the plan (the quick bounds "
                              "only, at most 10 s; a refined bound is still read from the "
                              "cache)")
    beside = p.add_mutually_exclusive_group()
    beside.add_argument("--parallel", action="store_true", default=None,
                        help="prove 'no plan' and the lower bounds in a second process "
                             "beside the search, from its start. By default on 2 cores or "
                             "more, with --time 5 s or more, where they are estimated at a "
                             "second or more (a real building's floor)")
    beside.add_argument("--no-parallel", action="store_false", dest="parallel",
                        help="prove in the search's own process, in windows of --time")
    p.add_argument("--out", help="write the pivot-plan/1 JSON here")
    p.add_argument("--plot", help="write the plan figure here (.png, .svg, .pdf...)")
    p.set_defaults(func=run, prove=None, parallel=None)


def _progress(stop: threading.Event, limit: float) -> None:
    t0 = time.monotonic()
    while not stop.wait(1.0):
        print(f"\rplanning... {time.monotonic() - t0:5.1f} s / {limit:.4g} s", end="",
              file=control_stream(sys.stderr), flush=True)


def regrasps_text(regrasps: int, bound: int | None) -> str:
    """``"2 regrasps (proven minimum)"``, ``"3 regrasps (at least 2)"`` or ``"3 regrasps"``.

    A bound of 0 under a plan with regrasps proves nothing and is not shown.
    """
    text = counted(regrasps, "regrasp")
    if bound is None or bound <= 0 < regrasps:  # "at least 0" says nothing
        return text
    return f"{text} (proven minimum)" if bound >= regrasps else f"{text} (at least {bound})"


def result_line(res: PlanResult) -> str:
    """``EXACT_SOLUTION: 221 pivots, 1 regrasp, solve 0.82 s`` or what was not found."""
    solve = f"solve {res.timings['solve']:.2f} s"
    if res.solved:
        return (f"{res.status}: {counted(res.pivots, 'pivot')}, "
                f"{counted(res.regrasps, 'regrasp')}, {solve}")
    if getattr(res, "infeasible_reason", None):
        took = sum(res.timings.values())
        return f"{res.status}: {res.infeasible_reason} (proven in {took:.2f} s)"
    if res.status == "APPROXIMATE_SOLUTION":
        return (f"{res.status}: the planner's closest path does not reach the goal, "
                f"no plan ({solve} of {res.time_limit:g} s)")
    return f"{res.status}: no plan reaches the goal ({solve} of {res.time_limit:g} s)"


def quality_line(q: dict) -> str:
    """One line of a plan's quality block, its optimality report included."""
    ratio = q.get("route_ratio")
    route = f"route {q['route_length']:.1f} m" + (
        "" if ratio is None else f" ({ratio:.2f} x the shortest bound)")
    return (f"quality: {regrasps_text(q['regrasps'], q['regrasps_lower_bound'])}, "
            f"{counted(q['pivots'], 'pivot')} ({q['pivots_per_m']:.1f}/m, ideal "
            f"{q['ideal_pivots_per_m']:.1f}), {route}, walking {q['walking_length']:.1f} m, "
            f"whole body ~{q['duration_estimate']:.0f} s")


def run(args: argparse.Namespace) -> int:
    """Plan, write the plan and the figure (``--time`` covers reading the scene too)."""
    source = scene_path(args.scene)
    out, fig = output_files([source], figures=["plot"], out=args.out, plot=args.plot)
    stop = threading.Event()
    th = threading.Thread(target=_progress, args=(stop, args.time), daemon=True)
    th.start()
    try:
        res = plan(source, planner=planner_with_share(args.planner, args.quality_share),
                   time_limit=args.time, seed=args.seed, regrasp_cost=args.regrasp_cost,
                   bound=not args.no_bound, prove=args.prove, parallel=args.parallel)
    except PlanningError as e:
        stop.set()
        print(f"\npivot-ompl plan: {e}", file=sys.stderr)
        return 2
    finally:
        stop.set()
        th.join()
        print(file=sys.stderr)
    print(result_line(res))
    q = res.plan.extra.get("quality")
    if q:
        print(quality_line(q))
        for line in explain_lines(q):
            print(line)
    if not res.solved:
        if fig and res.status == "INFEASIBLE":  # the figure shows why: the passage marked
            with atomic_outputs(fig) as (tmp_fig,):
                from pivot_ompl.viz.plan_figure import plot_plan
                plot_plan(res.plan, tmp_fig or fig, scene=res.scene)
            print(f"no plan exists: nothing written to --out; figure written to {fig}",
                  file=sys.stderr)
        elif out or fig:
            why = "no plan exists" if res.status == "INFEASIBLE" else "no plan found"
            print(f"{why}: nothing written", file=sys.stderr)
        return 1
    with atomic_outputs(out, fig) as (tmp_out, tmp_fig):  # both or neither
        if tmp_out and out:
            tmp_out.write_text(res.plan.to_text(folder=out.parent), encoding="utf-8")
        if tmp_fig:
            from pivot_ompl.viz.plan_figure import plot_plan
            plot_plan(res.plan, tmp_fig, scene=res.scene, search=res.search)
    if out:
        print(f"plan written to {out}")
    if fig:
        print(f"figure written to {fig}")
    return 0

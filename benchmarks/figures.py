"""The table of current figures, docs/figures.md, made by one command (``make figures``).

Runs the benchmark scripts one after another (one planning process at a time, sized for the
project's 2-core machine; the page says how long its run took), each writing its JSON into
``--out``, then prints one Markdown table, each row naming the script and arguments that
produced it, and writes the page ``--page`` (the table under a short introduction). Usage::

    python benchmarks/figures.py [--out results/figures] [--page docs/figures.md]
                                 [--only plan_quality,scaling,...] [--reuse]

Set ``PIVOT_BENCH_LOCK`` to a file to hold it (``flock``) while the table is made, so that two
measuring runs never share the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import machine_lock  # noqa: E402

TREE = Path(__file__).resolve().parent
PAGE = TREE.parent / "docs" / "figures.md"
PY = sys.executable

#: Scenes of the plan-quality rows: fig10, two copies of it, the other shipped scenes.
QUALITY_SCENES = "fig10,rot30,mirror,slot,door,t_junction,corridor,cluttered_room"
#: Scenes of the route-quality rows: the public layouts and the shipped real maps.
ROUTE_SCENES = "layouts,maps"


@dataclass(frozen=True)
class Step:
    """One benchmark script run and how its JSON becomes rows ``(what, measured)``."""

    name: str
    script: str
    args: tuple[str, ...]
    rows: Callable[[Any], list[tuple[str, str]]]
    out_is_dir: bool = False
    #: the JSON a step writing a folder leaves in it
    result: str = "regrasp_table.json"


def _pct(x: float) -> str:
    return f"{100 * x:.0f} %"


def _quality_rows(d: dict) -> list[tuple[str, str]]:
    out = []
    for key, r in d["table"].items():
        scene = key.split("/")[0]
        out.append((f"plan quality: {scene}",
                    f"{_pct(r['success'])} solved; regrasps {r['regrasps_median']} "
                    f"(bound {r['bound_median']}, at the bound in {_pct(r['at_bound'])}); "
                    f"{r['pivots_median']} pivots; route {r['route_ratio_median']:.2f} × "
                    f"the bound; solve {r['solve_median']:.2f} s; whole body "
                    f"~{r['duration_median']:.0f} s"))
    return out


def _route_rows(d: dict) -> list[tuple[str, str]]:
    out = []
    for key, r in d["table"].items():
        scene, version = key.rsplit("/", 1)
        if version != "after":  # a run with --before: this checkout's rows only
            continue
        out.append((f"route quality: {scene} ({r['runs']} seeds)",
                    f"{_pct(r['success'])} solved; regrasps {r['regrasps_median']} (bound "
                    f"{r['bound_median']}, at it in {_pct(r['at_bound'])}); route "
                    f"{r['route_ratio_median']:.2f} × the bound (worst "
                    f"{r['route_ratio_max']:.2f}); pivot rate {r['rate_over_ideal_median']:.2f} "
                    f"× the ideal; cost spread {_pct(r['cost_spread'])}; solve "
                    f"{r['solve_median']:.2f} s"))
    return out


def _scaling_rows(d: dict) -> list[tuple[str, str]]:
    out = []
    for key, r in d["table"].items():
        cls, param = key.split("/")
        rooms = param.replace("rooms=", "")
        if cls == "building":
            what = f"scaling: {rooms} room{'' if rooms == '1' else 's'} in a row"
        elif cls == "doors":
            what = f"doors: 6 rooms, every wall a {param.replace('width=', '')} m door"
        else:
            what = f"tight slots: {param.replace('clearance=', '')} m a side"
        out.append((what, f"solved {r['solved']}/{r['runs']}; median {r['solve_median']:.2f} s, "
                          f"p95 {r['solve_p95']:.2f} s"))
    return out


def _count(x: float | None) -> str:
    """A median count as read: ``2``, ``1.5``, ``–`` when no run solved."""
    return "–" if x is None else f"{x:g}"


def _replanning_rows(d: dict) -> list[tuple[str, str]]:
    """One row per (scene, event): the warm session and the plan file against a fresh plan."""
    out = []
    for key, r in d["table"].items():
        scene, event = key.split("/", 1)  # events such as "drift 5cm/5deg" hold a slash
        w, c, f = r["warm"], r["cli"], r["fresh"]
        out.append((f"replanning: {scene}, {event}",
                    f"warm {w['median_s']:.2f} s ({w['ok']}/{r['runs']} ok, "
                    f"{w['ratio']:.2f} of fresh); plan file solve {c['median_solve_s']:.2f} s "
                    f"({c['ok']}/{r['runs']}, {c['solve_ratio']:.2f} of fresh); fresh "
                    f"{f['median_s']:.2f} s ({f['ok']}/{r['runs']}); regrasps "
                    + " / ".join(_count(m["median_regrasps"]) for m in (w, c, f))))
    return out


def _time_limit_rows(d: dict) -> list[tuple[str, str]]:
    worst = max((r["max_ratio"] for r in d["rows"] if r["max_ratio"] is not None), default=0.0)
    outs = sum(r["timeouts"] for r in d["rows"])
    return [(f"time limit {d['time_limit']:g} s, shipped scenes, {d['seeds']} seeds",
             f"wall time at most {worst:.2f} × the limit; {outs} runs ended as TIMEOUT")]


def _steering_rows(d: dict) -> list[tuple[str, str]]:
    push = ", ".join(f"l = {k} m {v:.1f} (ideal {d['ideal_per_m'][k]:.1f})"
                     for k, v in d["straight_push_per_m"].items())
    return [(f"Reeds–Shepp to pivots, {d['pairs']} pairs 0.1–6 m",
             f"median {d['median_ms']:.2f} ms, p95 {d['p95_ms']:.2f} ms; "
             f"{d['rotations_per_m']:.1f} rotations/m"),
            ("straight 8 m push, rotations per metre", push)]


def _validation_rows(d: dict) -> list[tuple[str, str]]:
    return [(f"{d['scene']} state and motion checks",
             f"{d['state_checks_per_s'] / 1000:.0f} k states/s; "
             f"{d['motion_checks_per_s']:.0f} motions/s ({_pct(d['coal_fraction'])} in coal)")]


def _walking_rows(d: dict) -> list[tuple[str, str]]:
    out = [(f"transit query: {r['scene']}",
            f"median {r['median_ms']:.1f} ms, p95 {r['p95_ms']:.1f} ms, {r['queries']} queries")
           for r in d["transit"]]
    return out


def _versus_ompl_rows(d: dict) -> list[tuple[str, str]]:
    cells = [f"{r['planner']} {_pct(r['success'])} solved, median {r['median_time']:.2f} s"
             for r in d["rows"]]
    return [(f"{Path(d['scene']).stem}, {d['runs']} runs of {d['time_limit']:g} s: ours and "
             "OMPL's on the same space", "; ".join(cells)
             + " (OMPL's planners cannot change grasp)")]


def _wholebody_rows(d: dict) -> list[tuple[str, str]]:
    return [(f"whole-body motion of the fig10 plan ({d['motion_duration_s']:.0f} s)",
             f"{d['real_time_factor']:.1f}× real time; ZMP margin "
             f"{1000 * d['worst_zmp_margin_m']:.0f} mm; hand error "
             f"{1000 * d['max_hand_error_m']:.2f} mm; checks "
             f"{'pass' if d['checks_passed'] else 'FAIL'}")]


def _buildings_rows(d: dict) -> list[tuple[str, str]]:
    out = []
    for name, m in d["maps"].items():
        runs = m["runs"]
        ok = [r for r in runs if r["solved"]]
        what = (f"real map: {name}, {m['width']:.1f} × {m['depth']:.1f} m, "
                f"{m['boxes']} boxes")
        text = f"solved {len(ok)}/{len(runs)}"
        if ok:
            bounds = [r for r in ok if r.get("bound") is not None]
            ratios = [r["route_ratio"] for r in ok if r.get("route_ratio") is not None]
            text += (f"; median {statistics.median(r['wall'] for r in ok):.1f} s (whole "
                     "process); regrasps "
                     f"{max(r['regrasps'] for r in ok)}")
            text += (f" (= bound in {sum(r['regrasps'] == r['bound'] for r in bounds)}"
                     f"/{len(bounds)})" if bounds else " (no bound proven)")
            if ratios:
                text += f"; route {statistics.median(ratios):.2f} × the bound"
        out.append((what, text + f"; peak {max(r['peak_mb'] for r in runs):.0f} MB"))
    return out


STEPS = (
    Step("plan_quality", "plan_quality.py",
         ("--seeds", "5", "--time", "30", "--scenes", QUALITY_SCENES), _quality_rows),
    Step("route_quality", "plan_quality.py",
         ("--seeds", "3", "--time", "30", "--scenes", ROUTE_SCENES), _route_rows),
    Step("scaling", "scaling.py", ("--rooms", "1,4,8,16,32", "--clearances", "0.1,0.05,0.03",
                                   "--doors", "0.95,1.3", "--seeds", "2", "--time", "60",
                                   "--no-bound"),
         _scaling_rows),
    Step("replanning", "replanning.py", ("--points", "3", "--time", "10",
                                         "--scenes", "fig10,slot"), _replanning_rows),
    Step("time_limit", "time_limit.py", ("--seeds", "3"), _time_limit_rows),
    Step("steering", "steering.py", ("--pairs", "300"), _steering_rows),
    Step("validation", "validation.py", ("--n", "500"), _validation_rows),
    Step("walking", "walking.py", ("--poses", "10", "--runs", "0",
                                   "--walk-scenes", "door,t_junction,fig10"), _walking_rows),
    Step("versus_ompl", "regrasp.py", ("--planners", "regrasp,rrtconnect,kpiece1", "--runs",
                                       "3", "--time", "10", "--workers", "1"),
         _versus_ompl_rows, out_is_dir=True),
    Step("wholebody", "wholebody.py", ("{fig10_plan}",), _wholebody_rows),
    Step("buildings", "buildings.py", ("--seeds", "2", "--time", "60"), _buildings_rows,
         out_is_dir=True, result="buildings.json"),
)


def _fig10_plan(out: Path) -> Path:
    plan = out / "fig10_plan.json"
    subprocess.run([PY, "-m", "pivot_ompl", "plan", "fig10", "--time", "60", "--seed", "0",
                    "--out", str(plan)], check=True, stdout=subprocess.DEVNULL)
    return plan


def run(out: Path, only: set[str] | None, *, reuse: bool = False) -> str:
    """Run the steps, return the Markdown table (``reuse``: read a step's JSON left in
    ``out`` by an earlier run instead of running it again)."""
    out.mkdir(parents=True, exist_ok=True)
    lines = ["| what | measured | command |", "|---|---|---|"]
    plan: Path | None = None
    for step in STEPS:
        if only and step.name not in only:
            continue
        target = out / (step.name if step.out_is_dir else f"{step.name}.json")
        args = step.args
        if "{fig10_plan}" in args:
            plan = plan or _fig10_plan(out)
            args = tuple(str(plan) if a == "{fig10_plan}" else a for a in args)
        cmd = [PY, str(TREE / step.script), *args, "--out", str(target)]
        result = (target / step.result) if step.out_is_dir else target
        if reuse and result.is_file():
            print(f"[{step.name}] reused {result}", flush=True)
        else:
            t0 = time.perf_counter()
            print(f"[{step.name}] {' '.join(cmd[1:])}", flush=True)
            # the lock is held here for the whole run: a script taking it per run must not wait
            env = {k: v for k, v in os.environ.items() if k != "PIVOT_BENCH_LOCK"}
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
            print(f"[{step.name}] {time.perf_counter() - t0:.0f} s", flush=True)
        data = json.loads(result.read_text())
        shown = " ".join(a if a != str(plan) else "PLAN" for a in args)
        for what, measured in step.rows(data):
            lines.append(f"| {what} | {measured} | `python benchmarks/{step.script} {shown}` |")
    return "\n".join(lines) + "\n"


def made_from(tree: Path = TREE.parent) -> str:
    """The commit ``tree`` is at (short hash), with " and changes not committed" if any.

    ``"a tree without git"`` where ``git`` cannot tell (an export, no ``git`` installed).
    """
    def git(*args: str) -> str | None:
        try:
            out = subprocess.run(["git", *args], cwd=tree, capture_output=True, text=True,
                                 check=False, timeout=30)
        except (OSError, subprocess.SubprocessError):
            return None
        return out.stdout.strip() if out.returncode == 0 else None

    rev = git("rev-parse", "--short", "HEAD")
    if not rev:
        return "a tree without git"
    dirty = git("status", "--porcelain", "--untracked-files=no")
    return f"commit {rev}" + (" and changes not committed" if dirty else "")


def page(table: str, *, minutes: float, partial: bool,
         load: tuple[float, float] | None = None, made: str | None = None) -> str:
    """The figures page: what the table is, when and from what it was made, how long ``make
    figures`` took, the table.

    ``load``: the machine's 1-minute load average at the run's start and end (a figure well
    above the cores' number means other work shared the machine and slowed the timings).
    ``made``: when and from what the run was made (``"2026-12-07 13:00 UTC from commit
    abc1234"``: :func:`made_from`), stated at the page's top.
    """
    took = (f"This run took {minutes:.0f} min" + (" (some steps only: `--only`)" if partial
                                                  else "") + ".")
    if made is not None:
        took = (f"Made on {made}: figures of that code, not of a later one (a change since "
                f"is not measured here until `make figures` runs again). {took}")
    if load is not None:
        took += (f" The 1-minute load average was {load[0]:.1f} at its start and {load[1]:.1f}"
                 f" at its end, on {os.cpu_count()} cores.")
    return f"""# Figures

Measured on a 2-core machine of this project's CI kind. `make figures` wrote this page
(`benchmarks/figures.py`: the benchmark scripts one after another, one planning process at a
time; their JSON in `results/figures/`). Each row names the script and arguments that
measured it; what each script measures, the targets and the longer runs (20 seeds, 32 rooms,
the whole body of every shipped scene) are in `benchmarks/README.md`. For comparison, the
regrasp paper's planner (Centrino Duo 2.16 GHz) solved its Fig. 10 in 90 % of runs, in
263.7 s on average, with two regrasps.
{took}

{table}"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("results/figures"),
                    help="folder of the scripts' JSON")
    ap.add_argument("--page", type=Path, default=PAGE,
                    help="the Markdown page written (default docs/figures.md)")
    ap.add_argument("--only", default="", help="comma-separated step names: "
                    + ",".join(s.name for s in STEPS))
    ap.add_argument("--reuse", action="store_true",
                    help="read the JSON a step left in --out instead of running it again")
    args = ap.parse_args()
    only = {s for s in args.only.split(",") if s} or None
    t0 = time.perf_counter()
    made = f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from {made_from()}"
    with machine_lock():
        load0 = os.getloadavg()[0]
        table = run(args.out, only, reuse=args.reuse)
        load1 = os.getloadavg()[0]
    took = time.perf_counter() - t0
    text = page(table, minutes=took / 60, partial=only is not None, load=(load0, load1),
                made=made)
    args.page.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.page.with_name(args.page.name + ".part")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(args.page)  # a failed run never leaves a half-written page
    print(table)
    print(f"{took:.0f} s; written {args.page}")


if __name__ == "__main__":
    main()

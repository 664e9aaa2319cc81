"""Plan quality before/after, side by side: regrasps against the proven bound, route, pivots.

Plans the public-style layouts of ``benchmarks/layouts`` (``hall``: a 15.7 x 10.2 m hall of
staggered barriers with 1.4-2.0 m gaps, one grasp suffices; ``bugtrap``: the classic bug trap,
start inside the cup), fig10 and rotated / mirrored copies of it (``rot30``: turned by 30
degrees about the room's centre, the old bounds kept as walls; ``mirror``: reflected in the
line at 0.3 rad through the centre; both made by ``pivot_ompl.generate``), any shipped scene
by name, generated scenes (``gen:FAMILY:SEED[:NAME=VALUE...]``, e.g. ``gen:walls:1:walls=2``,
``gen:building:0:rooms=3``; the values are ``GeneratorParams`` fields) and the real-map corpus
(``map:NAME``, a map of ``benchmarks/buildings.py``'s ``CORPUS`` imported by its
``import_corpus_map`` at the corpus's start and goal; ``maps`` names the one-grasp maps shipped
in ``scenes/maps``, ``corpus`` every corpus map whose task has a plan (the shipped ones, the
Nav2 depot and warehouse, the hospital, the Willow Garage office and the lab's lower room),
``layouts`` every layout of ``benchmarks/layouts``) with
``RegraspPlanner`` over seeds, with two versions of the package in turn: one worker process
per version (``--before DIR``, e.g. an export of ``main``, and this checkout), fed the same
(scene, seed) jobs alternately, so both see the same machine (``--fresh``: a new process per
plan, so that no seed reuses the checks, fields and bounds an earlier seed's plan left in the
process; the bound cache on disk, ``XDG_CACHE_HOME``, is still shared). Prints medians per scene and
version: pivots, regrasps, pivots per metre of transfer, walking length, planning time, the
optimiser's share of it, the estimated whole-body duration, whether every plan passes the
independent plan check, runs that raised an error, and the quality block's lower bound on
regrasps with its computing time (versions that write it), the share of runs whose regrasps
equal the bound, and the median route ratio (box route over the proven shortest route).
Targets: fig10 and its copies median regrasps = bound = 2, <= 250 pivots; walls, corridor and
shipped scenes at the bound in >= 90 % of runs; one-grasp scenes 0 regrasps in 100 %; route
ratio median <= 1.3; pivot rate (pivots per metre over the ideal rate) <= 1.5 median; cost
spread across seeds (max / min - 1) <= 10 %.

    python benchmarks/plan_quality.py [--before DIR] [--seeds 20] [--time 30] [--fresh]
        [--scenes layouts,fig10,rot30,mirror,slot,gen:walls:1:walls=2,maps,corpus]
        [--out results/plan_quality.json] [--markdown results/plan_quality.md]

Run timing figures under ``flock /tmp/pivot-bench.lock``.

``mirror:SPEC`` plans any of these scenes reflected as ``mirror`` is (``mirror:door``,
``mirror:gen:walls:1``, ``mirror:map:aws_small_house``): a scene and its reflection side by
side. ``rot:ANGLE:SPEC`` plans any of them turned by ``ANGLE`` rad about its floor's centre
(``rot:0.6:fig10``, ``rot:0.6:mirror:door``), the old floor kept as walls as ``rot30`` is.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parents[1]
#: the public-style layouts, by name (``NAME.yaml`` in this folder)
LAYOUTS = HERE.parent / "layouts"
#: the corpus maps shipped in ``scenes/maps`` (one grasp solves each of their tasks)
SHIPPED_MAPS = ("aws_small_house", "aws_bookstore", "aws_small_warehouse")
#: where ``map:NAME`` scenes are imported to
MAP_SCENES = ROOT / "results" / "plan_quality_maps"
#: the line (rad, through the floor's centre) ``mirror`` and ``mirror:SPEC`` reflect in
MIRROR_AXIS = 0.3


def scene_names(spec: str) -> list[str]:
    """``--scenes``' names, with ``layouts``, ``maps`` and ``corpus`` expanded."""
    out: list[str] = []
    for name in filter(None, spec.split(",")):
        if name == "layouts":
            out += sorted(p.stem for p in LAYOUTS.glob("*.yaml"))
        elif name == "maps":
            out += [f"map:{m}" for m in SHIPPED_MAPS]
        elif name == "corpus":
            out += [f"map:{m}" for m in corpus_maps()]
        else:
            out.append(name)
    return out


def corpus_maps() -> list[str]:
    """The corpus maps of ``benchmarks/buildings.py`` whose task has a plan, in its order."""
    from buildings import CORPUS

    return [m.name for m in CORPUS if m.feasible]


def map_scene(name: str):  # noqa: ANN201 (a Scene of whichever package version runs)
    """The corpus map ``name`` imported as ``benchmarks/buildings.py`` does (its helper)."""
    from buildings import CORPUS, import_corpus_map

    from pivot_ompl.scene import load_scene

    by_name = {m.name: m for m in CORPUS}
    if name not in by_name:
        raise SystemExit(f"map:{name}: not in the corpus (known: {sorted(by_name)})")
    MAP_SCENES.mkdir(parents=True, exist_ok=True)
    return load_scene(import_corpus_map(by_name[name], MAP_SCENES)["scene"])


# -- scenes ------------------------------------------------------------------------------

def variant(name: str):  # noqa: ANN201 (a Scene of whichever package version runs)
    """fig10 as is, turned by 30 degrees (``rot30``) or mirrored (``mirror``); any spec.

    The copies are :mod:`pivot_ompl.generate`'s: the old floor kept as walls round it,
    ``mirror`` reflected in the line at :data:`MIRROR_AXIS` through the room's centre, and
    ``mirror:SPEC`` any scene of the other specs reflected alike (``mirror:door``,
    ``mirror:gen:walls:1``, ``mirror:map:aws_small_house``), ``rot:ANGLE:SPEC`` turned by
    ``ANGLE`` rad about its floor's centre (``rot:0.6:fig10``).
    """
    from common import scene_from_spec

    from pivot_ompl.generate import mirror_scene, rotate_scene
    from pivot_ompl.scene import load_scene

    if name.startswith("mirror:"):  # any scene of these specs, reflected as ``mirror`` is
        inner = variant(name[7:])
        return mirror_scene(inner, MIRROR_AXIS, name=f"{inner.name}_mirror")
    if name.startswith("rot:"):  # rot:ANGLE:SPEC, any scene turned by ANGLE rad
        _, angle, rest = name.split(":", 2)
        inner = variant(rest)
        return rotate_scene(inner, float(angle), name=f"{inner.name}_rot{angle}")
    if (LAYOUTS / f"{name}.yaml").is_file():
        return load_scene(LAYOUTS / f"{name}.yaml")
    if name.startswith("map:"):
        return map_scene(name[4:])
    if name not in ("fig10", "rot30", "mirror"):
        return scene_from_spec(name)  # a shipped or generated scene
    base = load_scene("fig10")
    if name == "fig10":
        return base
    if name == "rot30":
        return rotate_scene(base, math.radians(30.0), name="fig10_rot30")
    return mirror_scene(base, MIRROR_AXIS, name="fig10_mirror")


# -- worker: plans jobs read from stdin with whichever package is on its path ------------

def worker() -> None:
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.errors import PivotError
    from pivot_ompl.scene import load_scene
    from pivot_ompl.validity.plan_check import check_plan

    ou.setLogLevel(ou.LOG_WARN)
    scenes: dict[str, Any] = {}
    for line in sys.stdin:
        name, seed_s, limit_s, spec, path = line.split()
        if name not in scenes:  # the file the parent wrote: one scene for every version
            scenes[name] = load_scene(path)
        scene = scenes[name]
        try:
            res = plan(scene, planner=spec,
                       time_limit=float(limit_s), seed=int(seed_s))
        except PivotError as e:  # e.g. a path the conversion refuses: counted, not fatal
            print(json.dumps({"scene": name, "seed": int(seed_s), "solved": False,
                              "solve": 0.0, "optimise": 0.0, "error": str(e)}), flush=True)
            continue
        row: dict[str, Any] = {"scene": name, "seed": int(seed_s), "solved": res.solved,
                               "solve": res.timings["solve"],
                               "optimise": float(res.roadmap.get("time_optimise", 0.0))}
        if res.solved:
            p = res.plan
            q = p.extra.get("quality") or {}
            row.update(pivots=p.pivots, regrasps=p.regrasps,
                       walking=sum(ph.length for ph in p.phases if ph.type == "transit"),
                       bound=q.get("regrasps_lower_bound"), bound_s=res.timings.get("bound"),
                       route_ratio=q.get("route_ratio"),
                       check=check_plan(p, scene).ok, plan=p.to_dict())
        print(json.dumps(row), flush=True)


# -- parent ------------------------------------------------------------------------------

def _start(path: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(path))
    return subprocess.Popen([sys.executable, str(HERE), "--worker"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env=env, cwd=str(path))


def _close(proc: subprocess.Popen) -> None:
    assert proc.stdin is not None
    proc.stdin.close()
    proc.wait()


def _ask(proc: subprocess.Popen, job: str) -> dict[str, Any]:
    assert proc.stdin is not None and proc.stdout is not None
    proc.stdin.write(job + "\n")
    proc.stdin.flush()
    while True:  # OMPL's C++ log lines share the worker's stdout
        line = proc.stdout.readline()
        if not line:
            raise SystemExit(f"worker for {job!r} died")
        if line.startswith("{"):
            return json.loads(line)


def _summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    from pivot_ompl.planfile import plan_from_dict
    from pivot_ompl.quality import plan_quality

    ok = [r for r in rows if r["solved"]]

    def med(key: str) -> float:
        vals = [r[key] for r in ok]
        return statistics.median(vals) if vals else math.nan

    quality = [plan_quality(plan_from_dict(r["plan"])) for r in ok]
    costs = [q["cost"] for q in quality]
    rates = [q["pivots_per_m"] / q["ideal_pivots_per_m"] for q in quality
             if q["ideal_pivots_per_m"] > 0]
    share = [r["optimise"] / r["solve"] for r in ok if r["solve"] > 0]
    return {"runs": len(rows), "success": len(ok) / len(rows) if rows else math.nan,
            "pivots_median": med("pivots"),
            "pivots_range": [min(r["pivots"] for r in ok), max(r["pivots"] for r in ok)]
            if ok else None,
            "regrasps_median": med("regrasps"),
            "regrasps_range": [min(r["regrasps"] for r in ok), max(r["regrasps"] for r in ok)]
            if ok else None,
            "walking_median": med("walking"), "solve_median": med("solve"),
            "optimise_share_median": statistics.median(share) if share else math.nan,
            "optimise_share_max": max(share) if share else math.nan,
            "pivots_per_m_median": statistics.median(q["pivots_per_m"] for q in quality)
            if quality else math.nan,
            "duration_median": statistics.median(q["duration_estimate"] for q in quality)
            if quality else math.nan,
            "checked_ok": sum(bool(r.get("check")) for r in ok),
            "errors": sum("error" in r for r in rows),
            "bound_median": _median([r["bound"] for r in ok if r.get("bound") is not None]),
            "bound_s_median": _median([r["bound_s"] for r in ok if r.get("bound_s") is not None]),
            "at_bound": _share([r["regrasps"] == r["bound"] for r in ok
                                if r.get("bound") is not None]),
            "route_ratio_median": _median([r["route_ratio"] for r in ok
                                           if r.get("route_ratio") is not None]),
            "route_ratio_max": max((r["route_ratio"] for r in ok
                                    if r.get("route_ratio") is not None), default=math.nan),
            "rate_over_ideal_median": _median(rates),
            "cost_median": _median(costs),
            "cost_spread": max(costs) / min(costs) - 1.0 if costs and min(costs) > 0
            else math.nan}


def markdown(table: dict[str, dict[str, Any]], command: str) -> str:
    """The quality table: per scene and version, the four measures of issue 42's targets."""
    lines = ["| scene | version | runs | regrasps (range) | bound | at bound | route ratio "
             "(max) | pivot rate / ideal | cost s | spread | solve s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for key, t in table.items():
        scene, ver = key.rsplit("/", 1)
        rr = t["regrasps_range"] or ["-", "-"]
        lines.append(
            f"| {scene} | {ver} | {t['runs']} | {t['regrasps_median']:g} ({rr[0]}-{rr[1]}) "
            f"| {t['bound_median']:g} | {100 * t['at_bound']:.0f} % "
            f"| {t['route_ratio_median']:.2f} ({t['route_ratio_max']:.2f}) "
            f"| {t['rate_over_ideal_median']:.2f} | {t['cost_median']:.0f} "
            f"| {100 * t['cost_spread']:.1f} % | {t['solve_median']:.2f} |")
    return "\n".join(lines) + f"\n\n`{command}`; medians over the seeds, spread = max / " \
        "min cost - 1.\n"


def _share(flags: list[bool]) -> float:
    return sum(flags) / len(flags) if flags else math.nan


def _median(vals: list[float]) -> float:
    return statistics.median(vals) if vals else math.nan


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--before", help="package tree of the 'before' version (e.g. main)")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--seeds-variants", type=int, default=None,
                    help="seeds on the rotated/mirrored copies (default: --seeds)")
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--scenes", default="fig10,rot30,mirror")
    ap.add_argument("--out", default="results/plan_quality.json")
    ap.add_argument("--markdown", help="also write the quality table (Markdown) here")
    ap.add_argument("--fresh", action="store_true",
                    help="a new worker process per plan (cold, as one `pivot-ompl plan` is: "
                         "nothing kept from the seeds before but the bound cache on disk)")
    ap.add_argument("--after-planner", default="regrasp",
                    help="the planner of this checkout, e.g. "
                         "'regrasp[optimiser.choose_grasps=true]' (no spaces)")
    args = ap.parse_args()
    if args.worker:
        worker()
        return
    sys.path.insert(0, str(HERE.parent))
    from common import this_checkout, write_json, written_scene

    this_checkout()  # the scenes are made by this checkout's package

    versions = {"after": ROOT}
    if args.before:
        versions = {"before": Path(args.before).resolve(), "after": ROOT}
    procs = {} if args.fresh else {k: _start(v) for k, v in versions.items()}
    rows: dict[tuple[str, str], list[dict[str, Any]]] = {}
    files = Path(tempfile.mkdtemp(prefix="plan_quality_"))
    try:
        for i, name in enumerate(scene_names(args.scenes)):
            # made once by this checkout, one file for both versions (common.written_scene)
            scene_file = written_scene(variant(name), files, str(i))
            n = args.seeds if name == "fig10" else (args.seeds_variants or args.seeds)
            if name.startswith("gen:") or name not in ("fig10", "rot30", "mirror"):
                n = args.seeds
            for seed in range(n):
                for ver, path in versions.items():  # alternately: the same load for both
                    spec = args.after_planner if ver == "after" else "regrasp"
                    proc = procs.get(ver) or _start(path)
                    try:
                        r = _ask(proc, f"{name} {seed} {args.time} {spec} {scene_file}")
                    finally:
                        if args.fresh:
                            _close(proc)
                    rows.setdefault((name, ver), []).append(r)
                    print(f"{name:7s} seed {seed:3d} {ver:6s} solved={r['solved']} "
                          f"pivots={r.get('pivots')} regrasps={r.get('regrasps')} "
                          f"bound={r.get('bound')} solve={r['solve']:.2f}s "
                          f"opt={r['optimise']:.2f}s", flush=True)
    finally:
        for proc in procs.values():
            _close(proc)
        shutil.rmtree(files, ignore_errors=True)
    table = {f"{name}/{ver}": _summary(rs) for (name, ver), rs in rows.items()}
    print(f"\n{'scene/version':18s} {'runs':>4} {'ok':>5} {'pivots':>7} {'range':>10} "
          f"{'regr':>5} {'range':>6} {'piv/m':>6} {'walk m':>7} {'solve s':>8} "
          f"{'opt %':>6} {'max %':>6} {'body s':>7} {'checked':>7} {'errors':>6} {'bound':>5} "
          f"{'bound s':>7} {'at bd':>6} {'route':>6} {'rt max':>6} {'rate':>5} {'cost':>6} "
          f"{'spread':>6}")
    for key, t in table.items():
        pr, rr = t["pivots_range"] or [0, 0], t["regrasps_range"] or [0, 0]
        print(f"{key[-18:]:18s} {t['runs']:4d} {100 * t['success']:4.0f}% "
              f"{t['pivots_median']:7.0f} "
              f"{f'{pr[0]}-{pr[1]}':>10} {t['regrasps_median']:5.1f} "
              f"{f'{rr[0]}-{rr[1]}':>6} {t['pivots_per_m_median']:6.1f} "
              f"{t['walking_median']:7.1f} {t['solve_median']:8.2f} "
              f"{100 * t['optimise_share_median']:6.1f} {100 * t['optimise_share_max']:6.1f} "
              f"{t['duration_median']:7.0f} {t['checked_ok']:7d} {t['errors']:6d} "
              f"{t['bound_median']:5.1f} {t['bound_s_median']:7.2f} "
              f"{100 * t['at_bound']:5.0f}% {t['route_ratio_median']:6.2f} "
              f"{t['route_ratio_max']:6.2f} {t['rate_over_ideal_median']:5.2f} "
              f"{t['cost_median']:6.0f} {100 * t['cost_spread']:5.1f}%")
    print("targets: fig10 and copies: regrasps = bound = 2, <= 250 pivots; walls, corridor, "
          "shipped: at the bound in >= 90 % of runs; one-grasp scenes 0 regrasps; route ratio "
          "median <= 1.3 (max 1.5); rate (pivots/m over ideal) median <= 1.5; cost spread "
          "<= 10 %")
    if args.markdown:
        md = markdown(table, " ".join(["python benchmarks/plan_quality.py", *sys.argv[1:]]))
        Path(args.markdown).write_text(md)
        print(md)
    write_json({"seeds": args.seeds, "time_limit": args.time, "versions":
                {k: str(v) for k, v in versions.items()}, "table": table}, args.out)


if __name__ == "__main__":
    main()

"""Plan quality before/after, side by side: pivots, regrasps, walking, optimisation time.

Plans fig10 and rotated / mirrored copies of it (``rot30``: turned by 30 degrees about the
room's centre, the old bounds kept as walls; ``mirror``: reflected in y) with
``RegraspPlanner`` over seeds, with two versions of the package in turn: one worker process
per version (``--before DIR``, e.g. an export of ``main``, and this checkout), fed the same
(scene, seed) jobs alternately, so both see the same machine. Prints medians per scene and
version: pivots, regrasps, pivots per metre of transfer, walking length, planning time, the
optimiser's share of it, the estimated whole-body duration, and whether every plan passes the
independent plan check. Targets (issue 14): fig10 median <= 250 pivots, median regrasps 2,
optimisation <= 20 % of planning time.

    python benchmarks/plan_quality.py --before /tmp/base [--seeds 100] [--time 30]
        [--scenes fig10,rot30,mirror] [--out results/plan_quality.json]

Run timing figures under ``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parents[1]


# -- scenes ------------------------------------------------------------------------------

def _xf(doc: dict[str, Any], fn, yaw_fn) -> dict[str, Any]:  # noqa: ANN001
    """A copy of a scene dict with every point mapped by ``fn`` and yaw by ``yaw_fn``."""
    out = json.loads(json.dumps(doc))
    out["start"] = [*fn(doc["start"][:2]), yaw_fn(doc["start"][2])]
    out["goal"] = [*fn(doc["goal"][:2]), yaw_fn(doc["goal"][2])]
    obs = []
    for o in doc.get("obstacles", []):
        o = dict(o)
        if o["type"] == "polygon":
            o["points"] = [list(fn(p)) for p in o["points"]]
        else:
            o["center"] = list(fn(o["center"]))
            if o["type"] == "box":
                o["yaw"] = yaw_fn(o.get("yaw", 0.0))
        obs.append(o)
    out["obstacles"] = obs
    return out


def variant(doc: dict[str, Any], name: str) -> dict[str, Any]:
    """fig10 (``doc``) as is, turned by 30 degrees (``rot30``) or mirrored (``mirror``)."""
    x0, y0, x1, y1 = doc["bounds"]
    if name == "fig10":
        return doc
    if name == "mirror":
        out = _xf(doc, lambda p: (p[0], y0 + y1 - p[1]), lambda a: -a)
        out["name"] = "fig10_mirror"
        return out
    if name == "rot30":
        th = math.radians(30.0)
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        c, s = math.cos(th), math.sin(th)

        def fn(p):  # noqa: ANN001, ANN202
            dx, dy = p[0] - cx, p[1] - cy
            return (cx + c * dx - s * dy, cy + s * dx + c * dy)

        out = _xf(doc, fn, lambda a: a + th)
        corners = [fn(p) for p in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
        walls = []
        for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
            walls.append({"type": "box", "center": [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
                          "size": [math.dist(a, b) + 0.2, 0.2],
                          "yaw": math.atan2(b[1] - a[1], b[0] - a[0]), "height": 2.0})
        # the old bounds become walls; the new bounds hold them with a margin
        xs, ys = [p[0] for p in corners], [p[1] for p in corners]
        out["bounds"] = [min(xs) - 0.3, min(ys) - 0.3, max(xs) + 0.3, max(ys) + 0.3]
        out["obstacles"] = out["obstacles"] + walls
        out["name"] = "fig10_rot30"
        return out
    raise SystemExit(f"unknown scene variant {name!r}")


# -- worker: plans jobs read from stdin with whichever package is on its path ------------

def worker() -> None:
    import yaml
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.resources import data_root
    from pivot_ompl.scene import scene_from_dict
    from pivot_ompl.validity.plan_check import check_plan

    ou.setLogLevel(ou.LOG_WARN)
    base = yaml.safe_load((data_root() / "scenes" / "fig10.yaml").read_text())
    scenes: dict[str, Any] = {}
    for line in sys.stdin:
        name, seed_s, limit_s = line.split()
        if name not in scenes:
            scenes[name] = scene_from_dict(variant(base, name), source=name)
        scene = scenes[name]
        res = plan(scene, planner="regrasp", time_limit=float(limit_s), seed=int(seed_s))
        row: dict[str, Any] = {"scene": name, "seed": int(seed_s), "solved": res.solved,
                               "solve": res.timings["solve"],
                               "optimise": float(res.roadmap.get("time_optimise", 0.0))}
        if res.solved:
            p = res.plan
            row.update(pivots=p.pivots, regrasps=p.regrasps,
                       walking=sum(ph.length for ph in p.phases if ph.type == "transit"),
                       check=check_plan(p, scene).ok, plan=p.to_dict())
        print(json.dumps(row), flush=True)


# -- parent ------------------------------------------------------------------------------

def _start(path: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(path))
    return subprocess.Popen([sys.executable, str(HERE), "--worker"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env=env, cwd=str(path))


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
    from pivot_ompl.planfile import plan_from_dict, plan_quality

    ok = [r for r in rows if r["solved"]]

    def med(key: str) -> float:
        vals = [r[key] for r in ok]
        return statistics.median(vals) if vals else math.nan

    quality = [plan_quality(plan_from_dict(r["plan"])) for r in ok]
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
            "checked_ok": sum(bool(r.get("check")) for r in ok)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--before", help="package tree of the 'before' version (e.g. main)")
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--seeds-variants", type=int, default=None,
                    help="seeds on the rotated/mirrored copies (default: --seeds)")
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--scenes", default="fig10,rot30,mirror")
    ap.add_argument("--out", default="results/plan_quality.json")
    args = ap.parse_args()
    if args.worker:
        worker()
        return
    sys.path[:0] = [str(HERE.parent), str(ROOT)]  # this checkout's package and common.py
    from common import write_json

    versions = {"after": ROOT}
    if args.before:
        versions = {"before": Path(args.before).resolve(), "after": ROOT}
    procs = {k: _start(v) for k, v in versions.items()}
    rows: dict[tuple[str, str], list[dict[str, Any]]] = {}
    try:
        for name in args.scenes.split(","):
            n = args.seeds if name == "fig10" else (args.seeds_variants or args.seeds)
            for seed in range(n):
                for ver, proc in procs.items():  # alternately: the same load for both
                    r = _ask(proc, f"{name} {seed} {args.time}")
                    rows.setdefault((name, ver), []).append(r)
                    print(f"{name:7s} seed {seed:3d} {ver:6s} solved={r['solved']} "
                          f"pivots={r.get('pivots')} regrasps={r.get('regrasps')} "
                          f"solve={r['solve']:.2f}s opt={r['optimise']:.2f}s", flush=True)
    finally:
        for proc in procs.values():
            assert proc.stdin is not None
            proc.stdin.close()
            proc.wait()
    table = {f"{name}/{ver}": _summary(rs) for (name, ver), rs in rows.items()}
    print(f"\n{'scene/version':18s} {'runs':>4} {'ok':>5} {'pivots':>7} {'range':>10} "
          f"{'regr':>5} {'range':>6} {'piv/m':>6} {'walk m':>7} {'solve s':>8} "
          f"{'opt %':>6} {'max %':>6} {'body s':>7} {'checked':>7}")
    for key, t in table.items():
        pr, rr = t["pivots_range"] or [0, 0], t["regrasps_range"] or [0, 0]
        print(f"{key:18s} {t['runs']:4d} {100 * t['success']:4.0f}% {t['pivots_median']:7.0f} "
              f"{f'{pr[0]}-{pr[1]}':>10} {t['regrasps_median']:5.1f} "
              f"{f'{rr[0]}-{rr[1]}':>6} {t['pivots_per_m_median']:6.1f} "
              f"{t['walking_median']:7.1f} {t['solve_median']:8.2f} "
              f"{100 * t['optimise_share_median']:6.1f} {100 * t['optimise_share_max']:6.1f} "
              f"{t['duration_median']:7.0f} {t['checked_ok']:7d}")
    print("targets: fig10 median <= 250 pivots, median regrasps 2, optimisation <= 20 % of "
          "planning time")
    write_json({"seeds": args.seeds, "time_limit": args.time, "versions":
                {k: str(v) for k, v in versions.items()}, "table": table}, args.out)


if __name__ == "__main__":
    main()

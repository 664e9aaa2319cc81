"""Free-walking benchmark (issue: free walking): transit queries and regrasp planning.

1. Walk planning time per transit query (the robot alone, from one grasp of a resting box to
   another): random valid box poses of each scene (seeded), every pair of valid grasps, one
   fresh ``PivotChecker`` per scene (its per-scene caches fill as the queries go, as in a
   planner run): median and p95 time, share of queries answered with a walk.
2. The regrasp planner on the free-walking scenes (``door``, ``t_junction``): one run per seed,
   in this process one after the other: success (exact and valid under ``check``), median and
   p95 planning time, regrasps. Targets: >= 95 % success within 60 s (aim 100 % within 10 s);
   transit query median <= 20 ms.

    python benchmarks/walking.py [--poses 40] [--runs 20] [--time 60] [--inflation 1,3]
                                 [--scenes door,t_junction] [--walk-scenes door,t_junction,fig10]
                                 [--out results/walking.json]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
from common import write_json

import pivot_ompl
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.plan_check import check_plan


def _p95(xs: list[float]) -> float:
    return float(np.percentile(xs, 95)) if xs else math.nan


def transit_queries(name: str, poses: int, seed: int, inflation: float | None = None) -> dict:
    """Time transit queries at random valid box poses of scene ``name``."""
    scene = load_scene(name)
    ck = PivotChecker(scene)
    if inflation is not None:  # both guides: the floor distance, then the lattice cost-to-go
        ck.walker.floor_inflation = inflation
        ck.walker.inflation = inflation
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = scene.bounds
    times, found, tried = [], 0, 0
    while tried < poses:
        obj = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
               float(rng.uniform(-math.pi, math.pi)))
        grasps = [g for g in range(4) if ck.state_valid(obj, g)]
        if len(grasps) < 2:
            continue
        tried += 1
        for g1 in grasps:
            for g2 in grasps:
                if g1 == g2:
                    continue
                t = time.perf_counter()
                w = ck.transit(obj, g1, g2)
                times.append(time.perf_counter() - t)
                found += w.valid
    return {"scene": name, "inflation": ck.walker.floor_inflation,
            "lattice_inflation": ck.walker.inflation, "poses": poses,
            "queries": len(times), "expansions": ck.walker.expansions,
            "with_walk": found / len(times), "median_ms": 1e3 * statistics.median(times),
            "p95_ms": 1e3 * _p95(times), "mean_ms": 1e3 * statistics.fmean(times)}


def regrasp_runs(name: str, runs: int, time_limit: float) -> dict:
    """The regrasp planner on scene ``name``, seeds 0 .. runs-1."""
    scene = load_scene(name)
    times, ok, regrasps = [], 0, []
    for seed in range(runs):
        t = time.perf_counter()
        res = pivot_ompl.plan(scene, planner="regrasp", time_limit=time_limit, seed=seed)
        dt = time.perf_counter() - t
        valid = res.solved and check_plan(res.plan, scene).ok
        print(f"  {name} seed {seed}: {res.status} {dt:.2f} s valid={valid}", flush=True)
        times.append(dt)
        if valid:
            ok += 1
            regrasps.append(res.regrasps)
    return {"scene": name, "runs": runs, "time_limit": time_limit, "success": ok / runs,
            "median_s": statistics.median(times), "p95_s": _p95(times),
            "max_s": max(times), "regrasps_median": statistics.median(regrasps) if regrasps
            else math.nan}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=40)
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--time", type=float, default=60.0)
    ap.add_argument("--scenes", default="door,t_junction")
    ap.add_argument("--walk-scenes", default="door,t_junction,fig10")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--inflation", default="",
                    help="A* heuristic weights to compare, e.g. 1,3, each set on both guides "
                         "(the floor distance, then the lattice cost-to-go past "
                         "quick_expansions); default: the planner's, 3 and 1.5")
    ap.add_argument("--out", default="results/walking.json")
    args = ap.parse_args()
    weights = [float(w) for w in args.inflation.split(",") if w] or [None]
    walks = [transit_queries(s, args.poses, args.seed, w)
             for s in args.walk_scenes.split(",") if s for w in weights]
    print(f"{'scene':<12} {'weight':>6} {'queries':>7} {'walk found':>10} {'median ms':>9} "
          f"{'p95 ms':>8} {'expansions':>10}")
    for w in walks:
        print(f"{w['scene']:<12} {w['inflation']:6.1f} {w['queries']:7d} "
              f"{100 * w['with_walk']:9.0f}% {w['median_ms']:9.1f} {w['p95_ms']:8.1f} "
              f"{w['expansions']:10d}")
    plans = [regrasp_runs(s, args.runs, args.time) for s in args.scenes.split(",")
             if s and args.runs > 0]
    print(f"{'scene':<12} {'runs':>5} {'success':>8} {'median s':>9} {'p95 s':>8} {'max s':>7} "
          f"{'regrasps':>8}")
    for p in plans:
        print(f"{p['scene']:<12} {p['runs']:5d} {100 * p['success']:7.0f}% "
              f"{p['median_s']:9.2f} {p['p95_s']:8.2f} {p['max_s']:7.2f} "
              f"{p['regrasps_median']:8.1f}")
    write_json({"transit": walks, "regrasp": plans}, args.out)


if __name__ == "__main__":
    main()

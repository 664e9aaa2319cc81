"""Whole-body obstacle clearance of planned motions on shipped scenes, and what checking costs.

Usage::

    python benchmarks/clearance.py --scenes fig10,slot --seeds 0,1,2 --time 60 --out r.json

For every scene and seed: plan (``regrasp``), generate the HRP-2 whole-body motion, then
measure every link's and the box's obstacle clearance
(:func:`pivot_ompl.wholebody.clearance.obstacle_clearance`). Prints, per scene, the smallest
clearance and the link, the share of motions keeping every link and the box >= 1 cm from the
obstacles (target 100 %), and the obstacle check's time as a share of the motion's generation
time (target <= 10 %).
"""

from __future__ import annotations

import argparse
import logging
import statistics
import time

from common import write_json

from pivot_ompl.api import plan as plan_scene
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.scene import load_scene
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.clearance import obstacle_clearance

TARGET_CLEARANCE = 0.01
TARGET_SHARE = 0.10


def main() -> None:
    """Run the measurement and print the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default=",".join(sorted(shipped_scenes())))
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--time", type=float, default=60.0, help="planning time limit (s)")
    ap.add_argument("--out", default="results/clearance.json")
    ap.add_argument("--keep", default=None, help="folder to write each plan and motion to")
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    runs = []
    for name in args.scenes.split(","):
        scene = load_scene(name)
        for seed in (int(s) for s in args.seeds.split(",")):
            res = plan_scene(scene, planner="regrasp", time_limit=args.time, seed=seed)
            if not res.solved:
                print(f"{name} seed {seed}: no plan ({res.status})")
                runs.append({"scene": name, "seed": seed, "status": res.status})
                continue
            plan = res.plan
            t0 = time.perf_counter()
            motion, stats = generate_motion(plan, walk=scene.walk)
            gen = time.perf_counter() - t0
            rep = obstacle_clearance(motion, scene)
            if args.keep:
                plan.to_json(f"{args.keep}/{name}_{seed}_plan.json")
                motion.save(f"{args.keep}/{name}_{seed}_motion.npz")
            w = rep.worst
            assert w is not None
            run = {"scene": name, "seed": seed, "status": "exact", "duration": motion.duration,
                   "generate_s": gen, "check_s": rep.seconds, "share": rep.seconds / gen,
                   "queries": rep.queries, "samples": rep.samples,
                   "min_clearance": w.clearance, "link": w.link, "time": w.time,
                   "obstacle": w.obstacle,
                   "per_link": {k: v.clearance for k, v in rep.per_link().items()}}
            runs.append(run)
            print(f"{name:15s} seed {seed}: min {1000 * w.clearance:7.1f} mm {w.link:12s} "
                  f"t {w.time:8.2f} s {w.obstacle:22s} check {rep.seconds:6.2f} s = "
                  f"{100 * rep.seconds / gen:4.1f} % of generation {gen:7.1f} s")
    done = [r for r in runs if r["status"] == "exact"]
    ok = [r for r in done if r["min_clearance"] >= TARGET_CLEARANCE]
    shares = [r["share"] for r in done]
    summary = {"motions": len(done), "planned": f"{len(done)}/{len(runs)}",
               "clear_1cm": len(ok) / len(done) if done else 0.0,
               "median_share": statistics.median(shares) if shares else None,
               "max_share": max(shares) if shares else None}
    print(f"every link and the box >= 1 cm: {len(ok)}/{len(done)} motions "
          f"(target 100 %); obstacle check / generation: median "
          f"{100 * (summary['median_share'] or 0):.1f} %, max "
          f"{100 * (summary['max_share'] or 0):.1f} % (target <= 10 %)")
    write_json({"summary": summary, "runs": runs}, args.out)


if __name__ == "__main__":
    main()

"""Physics in the loop: tracking error per shipped scene, closed-loop success under slips.

Tracking (``--scenes``, default every shipped scene): each scene planned (regrasp planner,
``--time`` s, seed 0), its whole-body motion generated, then simulated in MuJoCo with
friction ``--friction`` and a ``--box-mass`` box: the largest and final box error against the
plan, the largest heading error, the largest median friction ratio of a pivot corner, the
rotations whose corner slid more than 5 mm, the hands' peak force and the simulation speed.

Closed loop (``--loop-scenes``, default fig10): ``--runs`` runs with ``--perturb slip``
(three slips at random pivots, 2 to 5 cm and up to 2 deg each) and ``--replan``, seeds
0..runs-1: the share that reached the goal within 3 cm and 3 deg, the replans per run, the
median replan time against the scene's fresh plan time.

    python benchmarks/physics.py [--scenes open,slot] [--loop-scenes fig10] [--runs 20]
        [--time 30] [--friction 0.5] [--box-mass 10] [--out results/physics.json]

Run timing figures under ``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parent))

from common import scene_from_spec, write_json  # noqa: E402


def _shipped() -> list[str]:
    return sorted(p.stem for p in (HERE.parents[1] / "scenes").glob("*.yaml"))


def _prepare(name: str, time_limit: float) -> tuple[Any, Any, Any, float]:
    from pivot_ompl import plan
    from pivot_ompl.wholebody import generate_motion

    scene = scene_from_spec(name)
    t0 = time.perf_counter()
    res = plan(scene, time_limit=time_limit, seed=0)
    plan_time = time.perf_counter() - t0
    if not res.solved:
        return scene, None, None, plan_time
    motion, _ = generate_motion(res.plan, walk=scene.walk)
    return scene, res.plan, motion, plan_time


def tracking(names: list[str], args: argparse.Namespace) -> list[dict[str, Any]]:
    from pivot_ompl.physics import simulate

    rows = []
    for name in names:
        scene, p, motion, plan_time = _prepare(name, args.time)
        if p is None:
            rows.append({"scene": name, "solved": False})
            print(f"{name:16s} no plan in {args.time:g} s", flush=True)
            continue
        r = simulate(p, motion, scene=scene, friction=args.friction, box_mass=args.box_mass)
        row = {"scene": name, "solved": True, "pivots": len(r.pivots),
               "regrasps": p.regrasps, "motion_s": r.simulated_s,
               "error_max_cm": 100 * r.box_error_max_m,
               "yaw_max_deg": math.degrees(r.box_yaw_error_max_rad),
               "error_final_cm": 100 * r.box_error_final_m,
               "goal_cm": 100 * r.goal_error_m, "reached": r.reached_goal,
               "friction_needed": r.friction_needed_max,
               "pivots_at_limit": r.pivots_at_limit, "slipped": r.slipping_pivots,
               "hand_peak_n": max(r.hand_force_peak_n),
               "obstacle_contacts": len(r.obstacle_contacts),
               "speed_x": r.real_time_factor}
        rows.append(row)
        print(f"{name:16s} {row['pivots']:4d} piv {row['regrasps']:2d} rg "
              f"{row['motion_s']:6.0f} s  err max {row['error_max_cm']:5.2f} cm "
              f"{row['yaw_max_deg']:5.2f} deg  final {row['error_final_cm']:5.2f} cm  "
              f"mu needed {row['friction_needed']:.2f}  at limit {row['pivots_at_limit']:3d}  "
              f"slipped {row['slipped']:3d}  hands {row['hand_peak_n']:4.0f} N  "
              f"obst {row['obstacle_contacts']}  {row['speed_x']:4.0f}x", flush=True)
    return rows


def closed_loop(names: list[str], args: argparse.Namespace) -> list[dict[str, Any]]:
    from pivot_ompl.physics import LoopSettings, simulate

    rows = []
    for name in names:
        scene, p, motion, plan_time = _prepare(name, args.time)
        if p is None:
            rows.append({"scene": name, "solved": False})
            continue
        runs = []
        for seed in range(args.runs):
            r = simulate(p, motion, scene=scene, friction=args.friction,
                         box_mass=args.box_mass, perturb=["slip"], replan=True, seed=seed,
                         settings=LoopSettings(replan_time=args.time))
            runs.append({"seed": seed, "status": r.status, "reached": r.reached_goal,
                         "goal_cm": 100 * r.goal_error_m, "replans": len(r.replans),
                         "replan_s": [x.plan_time_s for x in r.replans],
                         "motion_s": [x.motion_time_s for x in r.replans],
                         "error_max_cm": 100 * r.box_error_max_m})
            print(f"{name:16s} seed {seed:3d} {r.status:18s} goal {100 * r.goal_error_m:5.2f} cm"
                  f"  replans {len(r.replans)}", flush=True)
        times = [t for run in runs for t in run["replan_s"]]
        med = statistics.median(times) if times else math.nan
        row = {"scene": name, "runs": len(runs),
               "success": sum(r["reached"] for r in runs) / max(1, len(runs)),
               "replans_per_run": statistics.mean(r["replans"] for r in runs),
               "replan_s_median": med, "fresh_plan_s": plan_time,
               "replan_share": med / plan_time if plan_time > 0 else math.nan,
               "runs_detail": runs}
        rows.append(row)
        print(f"{name:16s} success {100 * row['success']:5.1f} % of {len(runs)}  "
              f"replans/run {row['replans_per_run']:.2f}  replan median {med:.3f} s vs fresh "
              f"{plan_time:.2f} s ({100 * row['replan_share']:.0f} %)", flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default=",".join(_shipped()),
                    help="scenes to track (comma separated; empty: none)")
    ap.add_argument("--loop-scenes", default="fig10",
                    help="scenes of the closed-loop runs (comma separated; empty: none)")
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--time", type=float, default=30.0, help="planning time limit (s)")
    ap.add_argument("--friction", type=float, default=0.5)
    ap.add_argument("--box-mass", type=float, default=10.0)
    ap.add_argument("--out", default="results/physics.json")
    args = ap.parse_args()
    split = [s for s in args.scenes.split(",") if s]
    loop = [s for s in args.loop_scenes.split(",") if s]
    res = {"friction": args.friction, "box_mass": args.box_mass,
           "tracking": tracking(split, args), "closed_loop": closed_loop(loop, args)}
    write_json(res, args.out)


if __name__ == "__main__":
    main()

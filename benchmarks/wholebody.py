"""Benchmark of the HRP-2 whole-body generator on a plan file.

Usage::

    python benchmarks/wholebody.py PLAN.json --out result.json [--motion motion.npz] [--repeat N]
    python benchmarks/wholebody.py --synthetic --out result.json   # no plan at hand

``--synthetic`` builds a stand-in plan with the fig10 box (0.8 x 0.4 x 1.0 m): a turning
push at grasp 0 (17 pivots), a transit to grasp 1 and a backward pull (5 pivots).

Prints and writes (JSON) the real-time factor of generation (seconds of motion per second of
compute; target >= 5), the worst ZMP margin and the largest hand-to-grip error, together with
every check of the motion; and where the motion's seconds go (per pivot step, transfer
remainder, transit; :mod:`pivot_ompl.wholebody.durations`) with the
``cost.DurationModel`` fitted to them, beside the plan's ``duration_estimate``.
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import platform
import sys
import time
from pathlib import Path

from common import write_json

from pivot_ompl.planfile import load_plan
from pivot_ompl.quality import plan_quality
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.durations import duration_breakdown, fit_duration_model
from pivot_ompl.wholebody.motion_checks import check_motion

TARGET_RTF = 5.0


def synthetic_plan():
    """A fig10-box stand-in plan: push with a turn, transit to grasp 1, pull back."""
    from pivot_ompl.grasp import BoxGraspModel
    from pivot_ompl.pivoting.steering import PivotSteering
    from pivot_ompl.pivoting.transfer import transfer_phase
    from pivot_ompl.planfile import Plan, TransitPhase

    size = (0.8, 0.4, 1.0)
    model = BoxGraspModel(size)
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    push = transfer_phase(model, steering, [(0.0, 0.0, 0.0), (1.0, 0.5, 0.5)], 0)
    end = push.object_end
    r0, r1 = model.robot_pose(end, 0), model.robot_pose(end, 1)
    h = r0[2]
    back = (r0[0] - 0.15 * math.cos(h), r0[1] - 0.15 * math.sin(h), h)
    side = (back[0] + 0.6 * math.sin(h), back[1] - 0.6 * math.cos(h), r1[2])
    transit = TransitPhase(0, 1, (r0, back, side, r1), end)
    hd = end[2] + math.pi / 2
    pulled = (end[0] - 0.5 * math.cos(hd), end[1] - 0.5 * math.sin(hd), end[2])
    pull = transfer_phase(model, steering, [end, pulled], 1)
    return Plan("synthetic-fig10-box", "exact", size, (0.40, 0.70), 0.25, math.pi / 8,
                (0.0, 0.0, 0.0), [push, transit, pull])


def run(plan_path: Path | None, *, repeat: int, motion_out: Path | None) -> dict:
    plan = load_plan(plan_path) if plan_path is not None else synthetic_plan()
    runs = []
    motion = None
    for _ in range(repeat):
        motion, stats = generate_motion(plan)
        runs.append({"duration_s": stats.duration, "compute_s": stats.compute,
                     "real_time_factor": stats.real_time_factor, "ticks": stats.ticks,
                     "samples": stats.samples,
                     "max_hand_error_m": stats.max_hand_error})
    assert motion is not None
    t0 = time.perf_counter()
    report = check_motion(motion, plan)
    t_check = time.perf_counter() - t0
    if motion_out is not None:
        motion.save(motion_out)
    best = max(runs, key=lambda r: r["real_time_factor"])
    split = duration_breakdown(motion, plan)
    fitted = fit_duration_model(split)
    return {
        "benchmark": "wholebody", "plan": str(plan_path) if plan_path else "synthetic",
        "scene": plan.scene,
        "pivots": plan.pivots, "regrasps": plan.regrasps, "phases": len(plan.phases),
        "motion_duration_s": best["duration_s"],
        "real_time_factor": best["real_time_factor"],
        "real_time_factor_all": [r["real_time_factor"] for r in runs],
        "target_real_time_factor": TARGET_RTF,
        "meets_target": best["real_time_factor"] >= TARGET_RTF,
        "worst_zmp_margin_m": report["zmp"].value,
        "max_hand_error_m": report["hands"].value,
        "checks_passed": report.passed,
        "checks": {r.name: {"passed": r.passed, "value": r.value, "limit": r.limit,
                            "unit": r.unit, "detail": r.detail} for r in report.results},
        "check_time_s": t_check, "runs": runs,
        "seconds": {"pivot_mean": split.per_pivot_mean,
                    "pivots": sum(s for _, s in split.pivots),
                    "transfer_rest": sum(split.transfer_rest),
                    "transits": sum(s for _, s in split.transits)},
        "duration_estimate_s": plan_quality(plan)["duration_estimate"],
        "fitted_duration_model": {k: getattr(fitted, k) for k in (
            "per_transfer", "per_pivot", "per_radian", "per_transit", "per_walk_m")},
        "machine": {"python": platform.python_version(), "cpus": os.cpu_count(),
                    "platform": platform.platform()},
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("plan", type=Path, nargs="?", default=None,
                    help="pivot-plan/1 file (e.g. the fig10 plan)")
    ap.add_argument("--synthetic", action="store_true",
                    help="use the built-in fig10-box stand-in plan instead of a file")
    ap.add_argument("--out", type=Path, required=True, help="JSON result file")
    ap.add_argument("--motion", type=Path, default=None, help="also write the motion (.npz)")
    ap.add_argument("--repeat", type=int, default=1, help="generations (best RTF is kept)")
    args = ap.parse_args(argv)
    if (args.plan is None) == (not args.synthetic):
        ap.error("give either a plan file or --synthetic")
    logging.basicConfig(level=logging.WARNING)
    res = run(args.plan, repeat=max(1, args.repeat), motion_out=args.motion)
    print(f"plan {res['plan']}: {res['pivots']} pivots, {res['regrasps']} regrasps")
    print(f"motion {res['motion_duration_s']:.1f} s, real-time factor "
          f"{res['real_time_factor']:.1f}x (target >= {TARGET_RTF:.0f}x: "
          f"{'met' if res['meets_target'] else 'NOT met'})")
    print(f"worst ZMP margin {1000 * res['worst_zmp_margin_m']:.1f} mm, "
          f"max hand error {1000 * res['max_hand_error_m']:.2f} mm, "
          f"checks {'PASS' if res['checks_passed'] else 'FAIL'}")
    sec = res["seconds"]
    print(f"seconds: pivots {sec['pivots']:.1f} ({sec['pivot_mean']:.2f} a pivot), transfer "
          f"rest {sec['transfer_rest']:.1f}, transits {sec['transits']:.1f}; the plan's "
          f"duration_estimate {res['duration_estimate_s']:.1f} s")
    print("fitted DurationModel: " + ", ".join(
        f"{k} {v:.2f}" for k, v in res["fitted_duration_model"].items()))
    write_json(res, args.out)
    return 0 if res["checks_passed"] else 1


if __name__ == "__main__":
    sys.exit(main())

"""The shipped scenes with every humanoid profile: plan, whole body, checks.

For each shipped scene and each robot model (``robot.model`` replaced; a footprint the scene
gives is kept where larger than the model's own, :mod:`pivot_ompl.scene`): the regrasp planner
(one seeded run), the plan checked against its scene, the proven regrasp bound; then the
whole-body motion (PlaCo) and every ``check-motion`` check with the robot's own limits.
Reports success, regrasps against the bound, planning time, motion duration, the peak joint
acceleration (share of its limit), the worst ZMP margin, the smallest link-to-obstacle
clearance and the generation speed (seconds of motion per second of compute: wall clock, and
per CPU second of this process, which a machine shared with other jobs does not change).

    python benchmarks/robots.py [--scenes open,fig10] [--robots hrp2,talos] [--time 60]
                                [--seed 0] [--no-motion] [--out results/robots.json]

Writes the JSON and a Markdown table beside it (``.md``).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time
from pathlib import Path
from typing import Any

from common import write_json

from pivot_ompl import plan as plan_scene
from pivot_ompl.fileio import load_yaml
from pivot_ompl.humanoids import PROFILES
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.scene import Scene, scene_from_dict
from pivot_ompl.validity.plan_check import check_plan


def scene_for(path: Path, robot: str) -> Scene:
    """The shipped scene at ``path`` with its robot model replaced by ``robot``."""
    doc = load_yaml(path)
    doc["robot"] = {**(doc.get("robot") or {}), "model": robot}
    doc["name"] = f"{doc['name']}_{robot}"
    return scene_from_dict(doc, source=str(path))


def run_one(scene: Scene, *, time_limit: float, seed: int, motion: bool) -> dict[str, Any]:
    """Plan ``scene``, check the plan, and (``motion``) generate and check the whole body."""
    row: dict[str, Any] = {"scene": scene.name, "robot": scene.robot_model}
    t0 = time.perf_counter()
    res = plan_scene(scene, planner="regrasp", time_limit=time_limit, seed=seed)
    row["plan_time_s"] = time.perf_counter() - t0
    plan = res.plan
    quality = plan.extra.get("quality") or {}
    row["regrasps_lower_bound"] = quality.get("regrasps_lower_bound")
    row["status"] = plan.status
    if not res.solved:
        row["success"] = False
        return row
    report = check_plan(plan, scene)
    row.update(plan_valid=report.ok, regrasps=plan.regrasps, pivots=plan.pivots)
    if not report.ok or not motion:
        row["success"] = report.ok
        return row
    from pivot_ompl.wholebody import generate_motion
    from pivot_ompl.wholebody.motion_checks import check_motion

    cpu = time.process_time()
    try:
        m, stats = generate_motion(plan, walk=scene.walk)
        cpu = time.process_time() - cpu
    except Exception as e:  # noqa: BLE001 - a failed generation is a row, not a crash
        row.update(success=False, motion_error=str(e))
        return row
    checks = check_motion(m, plan, scene=scene)
    peaks = checks.peaks
    worst = peaks.worst_accel() if peaks is not None else None
    clearance = next((r.value for r in checks.results if r.name == "obstacles"), math.inf)
    row.update(
        motion_duration_s=stats.duration, generation_s=stats.compute,
        real_time_factor=stats.real_time_factor, generation_cpu_s=cpu,
        cpu_real_time_factor=stats.duration / cpu if cpu > 0 else math.inf,
        zmp_margin_m=checks["zmp"].value, min_obstacle_clearance_m=clearance,
        peak_accel_joint=worst.joint if worst else None,
        peak_accel=worst.accel if worst else None,
        peak_accel_ratio=worst.accel / worst.accel_limit if worst else None,
        checks_passed=checks.passed,
        failed_checks=[r.name for r in checks.results if not r.passed],
        success=checks.passed)
    return row


def table(rows: list[dict[str, Any]]) -> str:
    """The rows as a Markdown table."""
    head = ("| scene | robot | success | regrasps (bound) | plan s | motion s | gen. speed "
            "(wall / CPU) | ZMP margin mm | min clearance mm | peak accel (share of limit) |")
    out = [head, "|" + "---|" * 10]
    for r in rows:
        def f(key: str, scale: float = 1.0, fmt: str = ".1f", r: dict = r) -> str:
            v = r.get(key)
            return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) \
                else format(scale * v, fmt)
        peak = ("-" if r.get("peak_accel") is None else
                f"{r['peak_accel_joint']} {r['peak_accel']:.1f} ({r['peak_accel_ratio']:.2f})")
        out.append(
            f"| {r['scene']} | {r['robot']} | {'yes' if r.get('success') else 'NO'} | "
            f"{r.get('regrasps', '-')} ({r.get('regrasps_lower_bound', '-')}) | "
            f"{f('plan_time_s', fmt='.2f')} | {f('motion_duration_s')} | "
            f"{f('real_time_factor')}x / {f('cpu_real_time_factor')}x | "
            f"{f('zmp_margin_m', 1000)} | "
            f"{f('min_obstacle_clearance_m', 1000)} | {peak} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default=",".join(shipped_scenes()),
                    help="shipped scene names, comma-separated (default: all)")
    ap.add_argument("--robots", default=",".join(PROFILES), help="robot models (default: all)")
    ap.add_argument("--time", type=float, default=60.0, help="planning time limit (s)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-motion", action="store_true", help="plan and check the plans only")
    ap.add_argument("--out", type=Path, default=Path("results/robots.json"))
    args = ap.parse_args(argv)
    files = shipped_scenes()
    rows = []
    for name in args.scenes.split(","):
        for robot in args.robots.split(","):
            scene = scene_for(files[name], robot)
            row = run_one(scene, time_limit=args.time, seed=args.seed,
                          motion=not args.no_motion)
            print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()},
                  flush=True)
            rows.append(row)
    text = table(rows)
    print(text)
    write_json({"benchmark": "robots", "time_limit_s": args.time, "seed": args.seed,
                "rows": rows, "machine": {"python": platform.python_version(),
                                          "cpus": os.cpu_count(),
                                          "platform": platform.platform()}}, args.out)
    args.out.with_suffix(".md").write_text(text + "\n")
    return 0 if all(r.get("success") for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())

"""Least clearance of planned walks, searched far more finely than the planner samples them.

Usage::

    python benchmarks/walk_clearance.py --scenes fig10,door,mirror:door,gen:walls:1 \\
        --seeds 0,1,2,3 --time 10 [--finer 64] [--out results/walk_clearance.json]

For every scene (the specs of ``benchmarks/plan_quality.py``: shipped names,
``gen:FAMILY:SEED``, ``mirror:SPEC``, ...) and seed: plan (``regrasp``), check the plan
(:func:`~pivot_ompl.validity.plan_check.check_plan`, and again with a tolerance ``--finer``
times smaller), then search every walk segment's least clearance beyond the margins the
planner keeps (1 cm from the obstacles, the walk planner's ``box_margin`` from the resting
box, none from the floor's edge) down to ``2 * tolerance / finer`` of motion: a segment's
clearance is Lipschitz in its parameter with the walk's sweep bound, so an interval whose
ends' clearances leave no room for a smaller value is not sampled further (branch and bound).
Prints per scene the least clearance found at a sample, the plans checked and the plans'
median cost and walking length; a negative clearance is a walk dipping into the kept margin
between the planner's samples.
"""

from __future__ import annotations

import argparse
import inspect
import logging
import math
import statistics
import sys
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def least(f: Any, lipschitz: float, step: float) -> float:  # noqa: ANN401 - f(s) -> m
    """Least ``f`` over [0, 1] at samples, refined to ``step`` of motion (branch and bound)."""
    d0, d1 = f(0.0), f(1.0)
    best = min(d0, d1)
    stack = [(0.0, d0, 1.0, d1)]
    while stack:
        a, da, b, db = stack.pop()
        span = lipschitz * (b - a)
        if span <= step or 0.5 * (da + db - span) >= best:
            continue  # nothing lower than ``best`` can hide between these two samples
        m = 0.5 * (a + b)
        dm = f(m)
        best = min(best, dm)
        stack.append((m, dm, b, db))
        stack.append((a, da, m, dm))
    return best


def walk_clearances(plan: Any, scene: Any, step: float, box_margin: float  # noqa: ANN401
                    ) -> tuple[float, float, int]:
    """Least clearance of the plan's walks: (obstacles and bounds, the box), segments."""
    from pivot_ompl.se2 import wrap_angle
    from pivot_ompl.validity.collision import CollisionWorld

    world = CollisionWorld.from_scene(scene)
    model = scene.model
    radius = model.robot_radius()
    static, boxed, segments = math.inf, math.inf, 0
    for ph in plan.phases:
        if ph.type != "transit":
            continue
        obj = ph.object_pose
        for a, b in zip(ph.robot_path, ph.robot_path[1:], strict=False):
            segments += 1
            dyaw = wrap_angle(b[2] - a[2])
            lip = math.hypot(b[0] - a[0], b[1] - a[1]) + radius * abs(dyaw)

            def pose(s: float, a: Any = a, b: Any = b, dyaw: float = dyaw) -> Any:  # noqa: ANN401
                return (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw)

            def to_static(s: float, pose: Any = pose) -> float:  # noqa: ANN401
                p = pose(s)
                return min(world.bounds_margin(model.robot_corners(p)), world.robot_distance(p))

            def to_box(s: float, pose: Any = pose, obj: Any = obj) -> float:  # noqa: ANN401
                return world.robot_box_distance(pose(s), obj) - box_margin

            static = min(static, least(to_static, max(lip, 1e-12), step))
            boxed = min(boxed, least(to_box, max(lip, 1e-12), step))
    return static, boxed, segments


def _median(values: list[Any]) -> float:  # noqa: ANN401
    known = [v for v in values if v is not None]
    return statistics.median(known) if known else math.nan


def main() -> None:
    """Plan, search the walks' clearances, print the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default="fig10,door,t_junction,slot")
    ap.add_argument("--seeds", default="0,1,2,3")
    ap.add_argument("--time", type=float, default=10.0, help="planning time limit (s)")
    ap.add_argument("--finer", type=float, default=64.0,
                    help="times finer than the planner's sweep tolerance")
    ap.add_argument("--out", default="results/walk_clearance.json")
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    from common import write_json
    from ompl import util as ou
    from plan_quality import scene_names, variant

    from pivot_ompl.api import plan as plan_scene
    from pivot_ompl.errors import PivotError
    from pivot_ompl.transit.planner import WalkPlanner
    from pivot_ompl.validity.certify import SWEEP_TOLERANCE
    from pivot_ompl.validity.plan_check import check_plan

    ou.setLogLevel(ou.LOG_WARN)
    box_margin = inspect.signature(WalkPlanner).parameters["box_margin"].default
    step = 2.0 * SWEEP_TOLERANCE / args.finer
    rows: list[dict[str, Any]] = []
    print(f"{'scene':28s} {'plans':>5s} {'segs':>5s} {'obstacles (mm)':>15s} "
          f"{'box (mm)':>9s} {'check':>6s} {'finer':>6s} {'cost s':>8s} {'walk m':>7s}")
    for name in scene_names(args.scenes):
        scene = variant(name)
        got = []
        for seed in (int(s) for s in args.seeds.split(",")):
            try:
                res = plan_scene(scene, planner="regrasp", time_limit=args.time, seed=seed)
            except PivotError as e:
                print(f"{name} seed {seed}: {e}")
                continue
            if not res.solved:
                continue
            p = res.plan
            static, boxed, segs = walk_clearances(p, scene, step, box_margin)
            q = p.extra.get("quality") or {}
            row = {"scene": name, "seed": seed, "segments": segs, "static": static,
                   "cost": q.get("cost"), "pivots": p.pivots, "regrasps": p.regrasps,
                   "walking": sum(ph.length for ph in p.phases if ph.type == "transit"),
                   "box": boxed, "check": check_plan(p, scene).ok,
                   "check_finer": check_plan(p, scene,
                                             tolerance=SWEEP_TOLERANCE / args.finer).ok}
            rows.append(row)
            got.append(row)
        if got:
            print(f"{name:28s} {len(got):5d} {sum(r['segments'] for r in got):5d} "
                  f"{1e3 * min(r['static'] for r in got):15.4f} "
                  f"{1e3 * min(r['box'] for r in got):9.3f} "
                  f"{sum(r['check'] for r in got):6d} {sum(r['check_finer'] for r in got):6d} "
                  f"{_median([r['cost'] for r in got]):8.1f} "
                  f"{_median([r['walking'] for r in got]):7.2f}",
                  flush=True)
        else:
            print(f"{name:28s} no plan", flush=True)
    if rows:
        print(f"least beyond the margins: obstacles and bounds "
              f"{1e3 * min(r['static'] for r in rows):.4f} mm, box "
              f"{1e3 * min(r['box'] for r in rows):.3f} mm; {len(rows)} plans, "
              f"{sum(r['segments'] for r in rows)} walk segments; check_plan "
              f"{sum(r['check'] for r in rows)}/{len(rows)}, {args.finer:g}x finer "
              f"{sum(r['check_finer'] for r in rows)}/{len(rows)}")
    write_json({"rows": rows, "args": vars(args)}, args.out)


if __name__ == "__main__":
    main()

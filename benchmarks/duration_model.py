"""The duration model's constants, fitted to real whole-body motions of planned scenes.

Usage::

    python benchmarks/duration_model.py --scenes fig10,slot,corridor --seed 0 --out result.json

Plans each scene (regrasp planner, the seed given), generates the plan's HRP-2 whole-body
motion (:func:`pivot_ompl.wholebody.generate_motion`, the scene's walk model), splits its
seconds by plan element (:func:`pivot_ompl.wholebody.durations.duration_breakdown`) and fits
one :class:`pivot_ompl.cost.DurationModel` to all of them together
(:func:`~pivot_ompl.wholebody.durations.fit_duration_model` of the pooled breakdowns). Prints
the constants as :class:`~pivot_ompl.cost.DurationModel` defaults (rounded to 0.1 s), and for
each scene the real motion's duration beside the estimate of the current defaults and of the
fitted ones. ``tests/wholebody/test_duration_model.py`` holds the defaults to the motions.
Exit code 1 when a scene finds no plan.
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import sys
from pathlib import Path

from common import write_json

from pivot_ompl.api import plan
from pivot_ompl.cost import DurationModel
from pivot_ompl.quality import plan_quality
from pivot_ompl.scene import load_scene
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.durations import duration_breakdown, fit_duration_model, pooled

FIELDS = [f.name for f in dataclasses.fields(DurationModel)]


def run(scenes: list[str], *, seed: int, time_limit: float) -> dict | None:
    """Plans, motions, their breakdowns and the model fitted to them (``None``: no plan)."""
    rows, splits, plans = [], [], []
    for name in scenes:
        scene = load_scene(name)
        res = plan(scene, planner="regrasp", time_limit=time_limit, seed=seed, bound=False)
        if not res.solved:
            print(f"{name}: no plan ({res.status})", file=sys.stderr)
            return None
        motion, stats = generate_motion(res.plan, walk=scene.walk)
        splits.append(duration_breakdown(motion, res.plan))
        plans.append(res.plan)
        rows.append({"scene": name, "motion_s": motion.duration, "compute_s": stats.compute,
                     "pivots": res.plan.pivots, "regrasps": res.plan.regrasps})
    fitted = fit_duration_model(pooled(splits))
    rounded = DurationModel(**{k: round(getattr(fitted, k), 1) for k in FIELDS})
    for row, p in zip(rows, plans, strict=True):
        for label, model in (("current", DurationModel()), ("fitted", rounded)):
            row[f"estimate_{label}_s"] = plan_quality(p, durations=model)["duration_estimate"]
    return {"benchmark": "duration_model", "seed": seed, "scenes": rows,
            "fitted": {k: getattr(fitted, k) for k in FIELDS},
            "defaults": {k: getattr(rounded, k) for k in FIELDS}}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default="fig10,slot,corridor",
                    help="comma-separated shipped scenes or scene files")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--time", type=float, default=60.0, help="planning time limit (s)")
    ap.add_argument("--out", type=Path, default=None, help="JSON result file")
    args = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    res = run([s for s in args.scenes.split(",") if s], seed=args.seed, time_limit=args.time)
    if res is None:
        return 1
    for row in res["scenes"]:
        print(f"{row['scene']}: motion {row['motion_s']:.1f} s (made in "
              f"{row['compute_s']:.1f} s), estimate {row['estimate_current_s']:.1f} s now, "
              f"{row['estimate_fitted_s']:.1f} s fitted")
    print("DurationModel(" + ", ".join(f"{k}={v}" for k, v in res["defaults"].items()) + ")")
    if args.out is not None:
        write_json(res, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""``pivot-ompl check SCENE PLAN``: validate a plan file (exit 0 valid, 1 invalid, 2 bad input)."""

from __future__ import annotations

import argparse
import sys

from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene, scene_digest
from pivot_ompl.validity.plan_check import check_plan


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``check`` verb."""
    p = sub.add_parser("check", help="validate a pivot-plan/1 file against a scene")
    p.add_argument("scene", help="scene YAML file")
    p.add_argument("plan", help="pivot-plan/1 JSON file")
    p.add_argument("--no-collisions", action="store_true", help="skip collision checks")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check the plan; print the verdict and the problems."""
    scene = load_scene(args.scene)
    plan = load_plan(args.plan)
    recorded = plan.extra.get("scene_sha256")
    if isinstance(recorded, str) and recorded != scene_digest(scene):
        print(f"note: the plan was made for another scene than {args.scene} (its "
              f"scene_sha256 {recorded[:12]}... differs from this scene's "
              f"{scene_digest(scene)[:12]}...)", file=sys.stderr)
    rep = check_plan(plan, scene, collisions=not args.no_collisions)
    for prob in rep.problems[:50]:
        print(f"  {prob}", file=sys.stderr)
    if rep.ok:
        print(f"plan valid: {rep.steps} pivot steps, {rep.transits} regrasp walks, "
              f"status {plan.status}")
        return 0
    print(f"plan INVALID: {len(rep.problems)} problem(s)", file=sys.stderr)
    return 1

"""``pivot-ompl check [SCENE] PLAN``: validate a plan file (exit 0 valid, 1 invalid, 2 bad input).

Without ``SCENE`` the plan's own scene is used (its ``scene_path`` file, else the shipped
scene of its name). A scene other than the one the plan was made for is named first.
"""

from __future__ import annotations

import argparse
import sys

from pivot_ompl.cli.scenes import SceneRecord, require_scene
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.plan_check import check_plan


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``check`` verb."""
    p = sub.add_parser("check", help="validate a pivot-plan/1 file against a scene")
    p.add_argument("scene", nargs="?", default=None,
                   help="scene file or shipped scene's name (default: the plan's own scene)")
    p.add_argument("plan", help="pivot-plan/1 JSON file")
    p.add_argument("--no-collisions", action="store_true", help="skip collision checks")
    p.add_argument("--exact", action="store_true",
                   help="pass a motion only if proven clear at every instant (the planner's "
                        "certificate), not to the sweep tolerance between samples")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check the plan; print the verdict and the problems."""
    given = load_scene(args.scene) if args.scene else None  # its errors first, as before
    plan = load_plan(args.plan)
    scene = require_scene(SceneRecord.of(plan), given, field="plan.scene")
    rep = check_plan(plan, scene, collisions=not args.no_collisions, exact=args.exact)
    for prob in rep.problems[:50]:
        print(f"  {prob}", file=sys.stderr)
    if rep.ok:
        walks = f"{rep.transits} regrasp walk{'' if rep.transits == 1 else 's'}"
        print(f"plan valid: {rep.steps} pivot steps, {walks}, status {plan.status}")
        return 0
    print(f"plan INVALID: {len(rep.problems)} problem(s)", file=sys.stderr)
    return 1

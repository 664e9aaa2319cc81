"""``pivot-ompl replan SCENE PLAN --box X Y YAW ...``: plan again from an observed state.

The box where it really is (``--box``), the grasp the robot holds it with (``--grasp``; none:
the box rests), obstacles that appeared (``--add-obstacles FILE.yaml``: an ``obstacles:`` list
written as in a scene file) or went (``--remove-obstacles I ...``: indices into the scene's
list). Writes the changed scene (``--scene-out``: start at the observed pose, obstacles as
changed) and a ``pivot-plan/1`` plan from there (``--out``) that ``pivot-ompl check NEW.yaml
NEW.json`` accepts; both or neither. ``PLAN`` is the plan being executed (it must be a plan
of ``SCENE``; recorded in the new plan as ``replanned_from``). Exit status as for ``plan``:
0 found, 1 none within ``--time``, 2 bad input (an observed pose in collision included).
"""

from __future__ import annotations

import argparse
import sys
import time

from pivot_ompl.api import MAX_SEED
from pivot_ompl.cli.args import finite, integer, output_files, time_limit
from pivot_ompl.cli.plan import result_line
from pivot_ompl.errors import InputError, Interrupted, PlanningError
from pivot_ompl.fileio import atomic_outputs, load_yaml, parse_deadline
from pivot_ompl.generate.sceneio import scene_text
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene, scene_digest
from pivot_ompl.session import PlanningSession


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``replan`` verb."""
    p = sub.add_parser("replan", help="plan again from an observed box pose and obstacles")
    p.add_argument("scene", help="scene file (YAML) or shipped scene's name")
    p.add_argument("plan", help="the pivot-plan/1 plan being executed")
    p.add_argument("--box", nargs=3, required=True, metavar=("X", "Y", "YAW"),
                   type=finite("--box"), help="observed box pose (m, m, rad)")
    p.add_argument("--grasp", type=integer("--grasp", 0, 3), default=None,
                   help="the grasp the robot holds the box with (default: the box rests)")
    p.add_argument("--robot", nargs=3, metavar=("X", "Y", "YAW"), type=finite("--robot"),
                   help="where the robot stands (recorded in the plan)")
    p.add_argument("--add-obstacles", metavar="FILE.yaml",
                   help="obstacles that appeared: a YAML file with an obstacles: list")
    p.add_argument("--remove-obstacles", nargs="+", type=integer("--remove-obstacles", 0),
                   default=(), metavar="I", help="indices of obstacles that went")
    p.add_argument("--time", type=time_limit("--time"), default=30.0,
                   help="time limit (s; inf: until solved)")
    p.add_argument("--seed", type=integer("--seed", 0, MAX_SEED), default=0,
                   help=f"seed (0..{MAX_SEED})")
    p.add_argument("--out", required=True, help="write the new pivot-plan/1 JSON here")
    p.add_argument("--scene-out", required=True, help="write the changed scene YAML here")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Replan and write the changed scene and the new plan.

    ``--time`` counts from the start: reading the scene, the plan and the added obstacles
    is inside it (a 100 000-obstacle file is stopped, not read to the end).
    """
    deadline = time.monotonic() + args.time
    scene = load_scene(args.scene, deadline=deadline)
    old = load_plan(args.plan)
    if old.scene != scene.name:
        raise InputError("PLAN", args.plan, f"is a plan of scene {old.scene!r}, not of "
                         f"{scene.name!r}")
    inputs = [scene.source, args.plan] + ([args.add_obstacles] if args.add_obstacles else [])
    out, scene_out = output_files(inputs, out=args.out, scene_out=args.scene_out)
    added = []
    if args.add_obstacles:
        doc = load_yaml(args.add_obstacles, should_stop=parse_deadline(deadline))
        if not isinstance(doc, dict) or set(doc) != {"obstacles"}:
            raise InputError("--add-obstacles", args.add_obstacles,
                             "must hold one key, obstacles: a list as in a scene file")
        added = doc["obstacles"]
        if not isinstance(added, list):
            raise InputError("--add-obstacles", args.add_obstacles, "obstacles must be a list")
    session = PlanningSession(scene, seed=args.seed, executing=old)
    left = deadline - time.monotonic()
    if left <= 0:
        raise Interrupted("reading the inputs")
    try:
        res = session.replan(box=args.box, grasp=args.grasp, robot=args.robot,
                             add_obstacles=added, remove_obstacles=list(args.remove_obstacles),
                             time_limit=left)
    except PlanningError as e:
        print(f"pivot-ompl replan: {e}", file=sys.stderr)
        return 2
    print(result_line(res))
    if not res.solved:
        why = "no plan exists" if res.status == "INFEASIBLE" else "no plan found"
        print(f"{why}: nothing written", file=sys.stderr)
        return 1
    new = session.scene
    assert out is not None and scene_out is not None  # noqa: S101 - required options
    res.plan.extra["replanned_from"] = str(args.plan)
    res.plan.extra.update(scene_path=str(scene_out.resolve()), scene_sha256=scene_digest(new))
    with atomic_outputs(scene_out, out) as (tmp_scene, tmp_plan):
        assert tmp_scene is not None and tmp_plan is not None  # noqa: S101 - both given
        tmp_scene.write_text(scene_text(new, comment=f"{new.name} as observed: replanned "
                                                     f"from {args.plan}"), encoding="utf-8")
        tmp_plan.write_text(res.plan.to_text(folder=out.parent), encoding="utf-8")
    print(f"scene written to {scene_out}, plan written to {out}")
    return 0

"""``pivot-ompl simulate PLAN.json --motion MOTION.npz --out REPORT.json``: physics in the loop.

The plan's whole-body motion run in MuJoCo (the ``physics`` extra: ``pip install
'pivot_ompl[physics]'``): the box a free body on the floor among the scene's obstacles, the
hands driven along the motion's grip frames, so the box moves only through the grip and its
contacts. Writes the report JSON (``pivot-physics/1``: box error against the plan, the
friction each pivot needed, hand force peaks, obstacle contacts, replans) and prints a
one-line summary. ``--perturb`` (repeatable): ``slip``, ``slip:N``, ``slip@K:DX,DY[,DYAW]``,
``patch:X,Y,R,MU``, ``mass:DX,DY,DZ``; ``--replan`` replans from the observed box whenever it
rests off the plan; ``--html`` writes a replay of the run (the simulated box beside the planned
one, a chapter per replan). Exit 0 goal reached, 1 not reached (or the time limit), 2 bad input.
The scene is ``--scene``, else the one the plan records.
"""

from __future__ import annotations

import argparse
import math

from pivot_ompl.api import MAX_SEED
from pivot_ompl.cli.args import integer, output_files, positive, time_limit
from pivot_ompl.cli.scenes import SceneRecord, require_scene


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` verb."""
    p = sub.add_parser("simulate", help="simulate a plan's whole-body motion in MuJoCo")
    p.add_argument("plan", help="the pivot-plan/1 plan")
    p.add_argument("--motion", required=True, help="its whole-body motion (.npz, animate's)")
    p.add_argument("--out", required=True, help="write the report JSON here")
    p.add_argument("--scene", help="scene file or shipped name (default: the plan's)")
    p.add_argument("--friction", type=positive("--friction"), default=0.5,
                   help="friction coefficient of the floor (mu)")
    p.add_argument("--box-mass", type=positive("--box-mass"), default=10.0,
                   help="mass of the box (kg)")
    p.add_argument("--perturb", action="append", default=[], metavar="SPEC",
                   help="a perturbation (repeatable): slip, slip:N, slip@K:DX,DY[,DYAW], "
                        "patch:X,Y,R,MU, mass:DX,DY,DZ")
    p.add_argument("--replan", action="store_true",
                   help="replan from the observed box whenever it rests off the plan")
    p.add_argument("--seed", type=integer("--seed", 0, MAX_SEED), default=0,
                   help=f"seed of random perturbations and replans (0..{MAX_SEED})")
    p.add_argument("--html", help="also write an HTML replay of the run here (the simulated "
                   "box beside the planned one, a chapter per replan)")
    p.add_argument("--time", type=time_limit("--time"), default=None,
                   help="wall-clock limit of the run (s; none by default)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Simulate, write the report, print its summary; 0 when the box reached the goal."""
    from pivot_ompl.physics import simulate
    from pivot_ompl.physics.backend import mujoco
    from pivot_ompl.planfile import load_plan

    out, html = output_files([args.plan, args.motion, args.scene],
                             suffixes={"out": [".json"], "html": [".html", ".htm"]},
                             out=args.out, html=args.html)
    mujoco()  # a missing extra is bad input, said before any work
    plan = load_plan(args.plan)
    scene = require_scene(SceneRecord.of(plan), args.scene, field="plan.scene")
    report = simulate(plan, args.motion, scene=scene, friction=args.friction,
                      box_mass=args.box_mass, perturb=args.perturb, replan=args.replan,
                      seed=args.seed,
                      time_limit=math.inf if args.time is None else args.time)
    report.plan = str(args.plan)
    assert out is not None  # noqa: S101 - a required option
    report.to_json(out)
    print(report.summary())
    print(f"report written to {out}")
    if html is not None:
        from pivot_ompl.physics.replay import write_replay

        print(f"replay written to {write_replay(report, html, scene=scene)}")
    return 0 if report.reached_goal else 1

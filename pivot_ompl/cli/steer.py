"""``pivot-ompl steer``: a Reeds-Shepp path turned into pivot rotations (no obstacles)."""

from __future__ import annotations

import argparse
import logging

from pivot_ompl.cli.args import finite
from pivot_ompl.grasp import check_grasp
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import default_scene, load_scene

log = logging.getLogger(__name__)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``steer`` verb."""
    p = sub.add_parser("steer", help="convert the Reeds-Shepp path start -> goal into pivots")
    p.add_argument("--start", nargs=3, required=True, metavar=("X", "Y", "YAW"),
                   type=finite("--start"), help="object start pose (m, m, rad)")
    p.add_argument("--goal", nargs=3, required=True, metavar=("X", "Y", "YAW"),
                   type=finite("--goal"), help="object goal pose (m, m, rad)")
    p.add_argument("--scene", help="take box, robot and pivot parameters from a scene file")
    p.add_argument("--grasp", type=int, default=0, help="grasp index 0..3 (default 0)")
    p.add_argument("--out", help="write the pivot-plan/1 JSON here")
    p.add_argument("--plot", help="write the figure (PNG) here")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Steer and write the plan/figure."""
    start, goal = tuple(args.start), tuple(args.goal)
    grasp = check_grasp(args.grasp, field="--grasp")
    if args.scene:
        base = load_scene(args.scene)
        name = base.name
    else:
        base = default_scene(start=start, goal=goal)
        name = "steer"
    steering = PivotSteering(turning_radius=base.turning_radius, alpha_max=base.alpha_max)
    phase = transfer_phase(base.model, steering, [start, goal], grasp)
    m = base.model
    plan = Plan(name, "exact", m.object_size, m.robot_footprint, m.standoff, base.alpha_max,
                start, [phase], {"planner": "steer", "turning_radius": base.turning_radius,
                                 "goal": list(goal)})
    print(f"{len(phase.steps)} pivot rotations, max |angle| "
          f"{max((abs(s.angle) for s in phase.steps), default=0.0):.6f} rad, "
          f"end {list(plan.object_end)}")
    if args.out:
        plan.to_json(args.out)
        print(f"plan written to {args.out}")
    if args.plot:
        from pivot_ompl.viz.plan_figure import plot_plan
        plot_plan(plan, args.plot, title=f"steer {list(start)} -> {list(goal)}")
        print(f"figure written to {args.plot}")
    return 0

"""``pivot-ompl steer``: a Reeds-Shepp path turned into pivot rotations (no obstacles).

Start and goal follow the scene file's rules (coordinates within +-1e4 m; yaw within
[-2 pi, 2 pi], wrapped into [-pi, pi)). ``--time`` bounds the conversion (exit 1 when it runs
out). ``--out`` and ``--plot`` are checked first and written through temporary files.
"""

from __future__ import annotations

import argparse
import logging
import time

from pivot_ompl.cli.args import finite, integer, output_files, time_limit
from pivot_ompl.errors import Interrupted
from pivot_ompl.fileio import atomic_outputs
from pivot_ompl.grasp import check_grasp
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import RS_PLOT_STEP, steps_of
from pivot_ompl.planfile import Plan, TransferPhase
from pivot_ompl.scene import check_pose, default_scene, load_scene

log = logging.getLogger(__name__)

#: Most Reeds-Shepp samples kept for plotting (a 9 km path would otherwise store 180 000).
MAX_RS_SAMPLES = 2000


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``steer`` verb."""
    p = sub.add_parser("steer", help="convert the Reeds-Shepp path start -> goal into pivots")
    p.add_argument("--start", nargs=3, required=True, metavar=("X", "Y", "YAW"),
                   type=finite("--start"), help="object start pose (m, m, rad)")
    p.add_argument("--goal", nargs=3, required=True, metavar=("X", "Y", "YAW"),
                   type=finite("--goal"), help="object goal pose (m, m, rad)")
    p.add_argument("--scene", help="take box, robot and pivot parameters from a scene file")
    p.add_argument("--grasp", type=integer("--grasp", 0, 3), default=0,
                   help="grasp index 0..3 (default 0)")
    p.add_argument("--time", type=time_limit("--time"), default=30.0,
                   help="time limit of the conversion (s, default 30)")
    p.add_argument("--out", help="write the pivot-plan/1 JSON here")
    p.add_argument("--plot", help="write the figure (PNG) here")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Steer and write the plan/figure."""
    start = check_pose(args.start, field="--start")
    goal = check_pose(args.goal, field="--goal")
    grasp = check_grasp(args.grasp, field="--grasp")
    if args.scene:
        base = load_scene(args.scene)
        name = base.name
    else:
        base = default_scene(start=start, goal=goal)
        name = "steer"
    out, fig = output_files([base.source], figures=["plot"], out=args.out, plot=args.plot)
    steering = PivotSteering(turning_radius=base.turning_radius, alpha_max=base.alpha_max)
    m = base.model
    deadline = time.monotonic() + min(args.time, 1e6)
    try:
        seq = steering.convert(m.car_pose(start, grasp), m.car_pose(goal, grasp),
                               half_length=m.edge_half_length(grasp),
                               should_stop=lambda: time.monotonic() > deadline)
    except Interrupted:
        raise Interrupted(f"steering at the --time limit of {args.time:g} s") from None
    n = max(2, min(MAX_RS_SAMPLES, int(seq.rs_length / RS_PLOT_STEP) + 1))
    rs = tuple(steering.paths.sample(seq.start, seq.goal, [i / (n - 1) for i in range(n)]))
    phase = TransferPhase(grasp, m.robot_pose(start, grasp), steps_of(m, seq, grasp), start, rs)
    plan = Plan(name, "exact", m.object_size, m.robot_footprint, m.standoff, base.alpha_max,
                start, [phase], {"planner": "steer", "turning_radius": base.turning_radius,
                                 "goal": list(goal)})
    print(f"{len(phase.steps)} pivot rotations, max |angle| "
          f"{max((abs(s.angle) for s in phase.steps), default=0.0):.6f} rad, "
          f"end {list(plan.object_end)}")
    with atomic_outputs(out, fig) as (tmp_out, tmp_fig):  # both or neither
        if tmp_out:
            tmp_out.write_text(plan.to_text(), encoding="utf-8")
        if tmp_fig:
            from pivot_ompl.viz.plan_figure import plot_plan
            plot_plan(plan, tmp_fig, title=f"steer {list(start)} -> {list(goal)}")
    if out:
        print(f"plan written to {out}")
    if fig:
        print(f"figure written to {fig}")
    return 0

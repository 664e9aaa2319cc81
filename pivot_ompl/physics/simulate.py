"""``simulate``: a plan's whole-body motion run in MuJoCo, its box tracked against the plan."""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion, load_motion
from pivot_ompl.physics.closed_loop import LoopSettings, goal_error, run_loop
from pivot_ompl.physics.drive import drive_signals, wrap
from pivot_ompl.physics.loop import Simulator
from pivot_ompl.physics.model import build_model
from pivot_ompl.physics.perturb import parse_perturbations
from pivot_ompl.physics.report import SLIP_LIMIT, SimulationReport
from pivot_ompl.planfile import Plan, load_plan
from pivot_ompl.scene import Scene, load_scene

log = logging.getLogger(__name__)

#: Default friction coefficient of the floor and box mass (kg).
DEFAULT_FRICTION, DEFAULT_MASS = 0.5, 10.0
#: Largest seed (numpy's Generator takes any; the planner's limit).
MAX_SEED = 2**31 - 1


def _scene_of(plan: Plan, scene: Scene | str | Path | None) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if scene is not None:
        return load_scene(scene)
    path = plan.extra.get("scene_path")
    if isinstance(path, str) and path and Path(path).is_file():
        return load_scene(path)
    return load_scene(plan.scene)


def simulate(plan: Plan | str | Path, motion: Motion | str | Path, *,
             scene: Scene | str | Path | None = None, friction: float = DEFAULT_FRICTION,
             box_mass: float = DEFAULT_MASS, perturb: Sequence[str] = (),
             replan: bool = False, seed: int = 0, time_limit: float = math.inf,
             settings: LoopSettings | None = None) -> SimulationReport:
    """Simulate ``motion`` (the whole-body motion of ``plan``) and report how the box followed.

    The box is a free body on the floor among the scene's obstacles; the hands, driven along
    the motion's grip frames, move it only through their soft grip and its contact with the
    floor (:mod:`pivot_ompl.physics`). See :class:`SimulationReport` for what is measured.

    Args:
        plan: the plan (or its ``pivot-plan/1`` file).
        motion: its whole-body motion (or its ``.npz`` file).
        scene: the scene (default: the plan's ``scene_path``, else the shipped scene of its
            name).
        friction: the floor's friction coefficient (mu).
        box_mass: the box's mass (kg).
        perturb: perturbation texts (:mod:`pivot_ompl.physics.perturb`); random ones are
            drawn from ``seed``.
        replan: close the loop: replan when the resting box drifted (see ``settings``).
        seed: the seed of the perturbations and of the replans.
        time_limit: wall-clock limit of the whole run (s); the run stops there with status
            ``time_limit``.
        settings: thresholds and limits of the closed loop (its ``replan`` and ``seed``
            are this call's).

    Raises:
        InputError: a bad argument or file, naming it; MuJoCo not installed.
    """
    deadline = time.monotonic() + time_limit if math.isfinite(time_limit) else math.inf
    if not (time_limit > 0):
        raise InputError("time_limit", time_limit, "must be > 0 s")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or not \
            0 <= seed <= MAX_SEED:
        raise InputError("seed", seed, f"must be an integer in [0, {MAX_SEED}]")
    plan_src = str(plan) if not isinstance(plan, Plan) else plan.extra.get("source", "")
    motion_src = str(motion) if not isinstance(motion, Motion) else motion.source
    if not isinstance(plan, Plan):
        plan = load_plan(plan)
    if not isinstance(motion, Motion):
        motion = load_motion(motion)
    sc = _scene_of(plan, scene)
    if motion.box_size is not None and not np.allclose(motion.box_size, plan.object_size,
                                                       atol=1e-6):
        raise InputError("motion.box_size", list(motion.box_size),
                         f"is not the plan's object size {list(plan.object_size)}")
    drive = drive_signals(motion)
    rng = np.random.default_rng(int(seed))
    perturbations = parse_perturbations(list(perturb), pivots=len(drive.pivots), rng=rng)
    assert motion.box_size is not None  # noqa: S101 - drive_signals checked it
    pm = build_model(sc, size=motion.box_size, mass=box_mass, friction=friction,
                     com_offset=perturbations.com_offset)
    sim = Simulator(pm, perturbations=perturbations)
    base = settings or LoopSettings()
    loop = dataclasses.replace(base, replan=bool(replan), seed=int(seed))
    out = run_loop(sim, plan, motion, sc, loop,
                   should_stop=lambda: time.monotonic() > deadline,
                   time_left=lambda: deadline - time.monotonic())
    a = out.trace.arrays()
    err = np.linalg.norm(a["sim_pos"] - a["plan_pos"], axis=1) if len(a["t"]) else np.zeros(1)
    yerr = (np.abs(wrap(a["sim_yaw"] - a["plan_yaw"])) if len(a["t"]) else np.zeros(1))
    gerr, gyerr = goal_error(sim, sc.goal)
    reached = gerr <= loop.goal_tolerance_m and gyerr <= loop.goal_tolerance_rad
    status = out.status
    if status == "done" and not reached:
        status = "goal_missed"
    pivots = out.trace.pivots
    report = SimulationReport(
        status=status, reached_goal=bool(reached and status == "done"),
        box_error_max_m=float(err.max()), box_error_final_m=float(err[-1]),
        box_yaw_error_max_rad=float(np.max(yerr)), box_yaw_error_final_rad=float(yerr[-1]),
        goal_error_m=gerr, goal_yaw_error_rad=gyerr, friction=float(friction),
        box_mass=float(box_mass),
        friction_needed_max=max((p.friction_median for p in pivots), default=0.0),
        pivots_at_limit=sum(1 for p in pivots if p.at_limit > 0.5),
        slipping_pivots=sum(1 for p in pivots if p.corner_slip > SLIP_LIMIT),
        hand_force_peak_n=(out.trace.hand_force_max[0], out.trace.hand_force_max[1]),
        obstacle_contacts=[{"start": a, "end": b, "obstacle": int(k), "depth_m": dep}
                           for a, b, k, dep in out.trace.obstacle_contacts],
        replans=out.replans, pivots=pivots, simulated_s=sim.time, wall_s=out.sim_wall,
        seed=int(seed), perturbations=perturbations.specs, scene=sc.name, plan=plan_src,
        motion=motion_src, trace=a, segments=out.segments)
    log.debug("%s", report.summary())
    return report

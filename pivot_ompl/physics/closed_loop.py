"""The run: the motion simulated up to each release of the box, replanned when it drifted.

The hands let go of the box at the end of each transfer phase (before a regrasp walk, at the
end). There the box rests, its pose observed (:meth:`Simulator.planar_pose`). With
``replan`` on, when it departs from the plan by more than the threshold (or, at the end, from
the goal by more than the tolerance), a :class:`~pivot_ompl.session.PlanningSession` replans
from the observed pose (the robot where the motion left it, the box resting: the plan may
start with any grasp), the whole-body motion of the new plan is generated, and the
simulation goes on with it from its first sample; the box stays where physics left it.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import PivotError
from pivot_ompl.motionfile import Motion
from pivot_ompl.physics.drive import DriveSignals, drive_signals, wrap
from pivot_ompl.physics.loop import RunTrace, Simulator
from pivot_ompl.physics.report import ReplanRecord
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class LoopSettings:
    """When and how the closed loop replans.

    Attributes:
        replan: replan at all (``False``: the open loop, the motion followed to its end).
        threshold_m, threshold_rad: a resting box further than this from the plan is replanned.
        goal_tolerance_m, goal_tolerance_rad: the goal counts as reached within these.
        max_replans: the most replans of one run.
        replan_time: each replan's planning time limit (s).
        seed: the planner's seed.
    """

    replan: bool = False
    threshold_m: float = 0.02
    threshold_rad: float = math.radians(2.0)
    goal_tolerance_m: float = 0.03
    goal_tolerance_rad: float = math.radians(3.0)
    max_replans: int = 5
    replan_time: float = 10.0
    seed: int = 0


@dataclass
class LoopOutcome:
    """What :func:`run_loop` did.

    Attributes:
        status: as :attr:`~pivot_ompl.physics.report.SimulationReport.status`.
        trace: the samples recorded.
        replans: the replans, in order.
        sim_wall: wall time spent simulating (s).
        segments: ``(motion, first, last)``: the samples of each motion simulated, in order
            (the trace's samples, motion by motion).
    """

    status: str
    trace: RunTrace
    replans: list[ReplanRecord] = field(default_factory=list)
    sim_wall: float = 0.0
    segments: list[tuple[Motion, int, int]] = field(default_factory=list)


def robot_pose(motion: Motion, i: int) -> tuple[float, float, float]:
    """The robot's base pose ``(x, y, yaw)`` at sample ``i`` of ``motion``."""
    x, y, z, w = (float(v) for v in motion.q[i, 3:7])
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return float(motion.q[i, 0]), float(motion.q[i, 1]), yaw


def departure(sim: Simulator, drive: DriveSignals, i: int) -> tuple[float, float]:
    """The resting box's planar distance (m) and heading difference (rad) from sample ``i``."""
    x, y, yaw = sim.planar_pose()
    return (math.hypot(x - drive.box_pos[i, 0], y - drive.box_pos[i, 1]),
            abs(float(wrap(yaw - drive.box_yaw[i]))))


def goal_error(sim: Simulator, goal: tuple[float, float, float]) -> tuple[float, float]:
    """The box's planar distance (m) and heading difference (rad) from ``goal``."""
    x, y, yaw = sim.planar_pose()
    return math.hypot(x - goal[0], y - goal[1]), abs(float(wrap(yaw - goal[2])))


def run_loop(sim: Simulator, plan: Plan, motion: Motion, scene: Scene, settings: LoopSettings,
             *, should_stop: Callable[[], bool],
             time_left: Callable[[], float] = lambda: math.inf) -> LoopOutcome:
    """Simulate ``motion`` (of ``plan``), replanning as :class:`LoopSettings` say.

    ``should_stop`` is polled while simulating and after each replan; a replan plans for at
    most ``time_left()`` seconds (the whole-body generation of its plan is not interrupted).
    """
    out = LoopOutcome("done", RunTrace())
    drive = drive_signals(motion)
    sim.place_box(drive.box_pos[0], np.r_[motion.box[0, 6], motion.box[0, 3:6]])
    session = None
    start = 0
    while True:
        ends = [r for r in drive.releases() if r >= start]
        replanned = False
        for r in ends:
            t0 = time.perf_counter()
            done = sim.follow(drive, out.trace, start=start, end=r, should_stop=should_stop)
            out.sim_wall += time.perf_counter() - t0
            if done >= start:
                out.segments.append((motion, start, done))
            if done < r:
                out.status = "time_limit"
                return out
            start = r + 1
            err, yerr = departure(sim, drive, r)
            gerr, gyerr = goal_error(sim, scene.goal)
            last = r == drive.n - 1
            if not settings.replan:
                continue
            drifted = err > settings.threshold_m or yerr > settings.threshold_rad
            missed = last and (gerr > settings.goal_tolerance_m
                               or gyerr > settings.goal_tolerance_rad)
            if not (drifted or missed):
                continue
            if last and not missed:
                continue  # drifted from the plan but at the goal: nothing to do
            if len(out.replans) >= settings.max_replans:
                out.status = "replans_exhausted"
                return out
            if session is None:
                from pivot_ompl.session import PlanningSession

                session = PlanningSession(scene, seed=settings.seed, executing=plan)
            new = _replan(session, sim, motion, r, err, yerr, settings, out,
                          min(settings.replan_time, max(0.05, time_left())))
            if new is None:
                return out
            if should_stop():
                out.status = "time_limit"
                return out
            plan, motion = new
            drive = drive_signals(motion)
            start, replanned = 0, True
            break
        if not replanned:
            return out


def _replan(session: object, sim: Simulator, motion: Motion, r: int, err: float, yerr: float,
            settings: LoopSettings, out: LoopOutcome,
            limit: float) -> tuple[Plan, Motion] | None:
    """Replan from the box as observed and generate the new plan's motion (None: failed)."""
    from pivot_ompl.wholebody import generate_motion

    observed = sim.planar_pose()
    robot = robot_pose(motion, r)
    log.info("t = %.2f s: box %.1f cm / %.2f deg off the plan: replanning from (%.3f, %.3f, "
             "%.3f)", sim.time, 100 * err, math.degrees(yerr), *observed)
    t0 = time.perf_counter()
    try:
        res = session.replan(box=observed, robot=robot,  # type: ignore[attr-defined]
                             time_limit=limit, seed=settings.seed)
    except PivotError as e:
        log.warning("replanning failed: %s", e)
        out.status = "replan_failed"
        return None
    plan_time = time.perf_counter() - t0
    t1 = time.perf_counter()
    motion_new = None
    if res.solved:
        try:
            motion_new, _ = generate_motion(res.plan, walk=session.scene.walk)  # type: ignore[attr-defined]
        except PivotError as e:
            log.warning("no whole-body motion for the new plan: %s", e)
    out.replans.append(ReplanRecord(sim.time, observed, err, yerr, plan_time,
                                    time.perf_counter() - t1, res.plan.pivots,
                                    res.plan.regrasps, res.status))
    if motion_new is None:
        out.status = "replan_failed"
        return None
    return res.plan, motion_new

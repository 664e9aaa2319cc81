"""Timing a plan for replay: keyframes of the box and the robot footprint over time.

A plan has no time, so the replay gives it one: each pivot rotation lasts
``|angle| / pivot_speed`` (at least ``min_step`` s) and is sampled every ``sample_angle`` rad
so the box follows the arc; each transfer phase starts by tilting the box towards the robot
about its supporting edge (``tilt`` rad over ``tilt_time`` s) and ends by putting it back
upright; a transit walks the robot's centre at ``walk_speed`` (turning at ``turn_speed``)
while the box rests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.viz.shapes import box_transform, planar


@dataclass(frozen=True)
class ReplayTiming:
    """Speeds of a plan-only replay (rad/s, m/s, s, rad)."""

    pivot_speed: float = 0.5
    min_step: float = 0.3
    sample_angle: float = math.radians(3.0)
    walk_speed: float = 0.5
    turn_speed: float = 1.0
    tilt: float = math.radians(5.0)
    tilt_time: float = 0.4


@dataclass
class Keyframes:
    """Sampled world transforms of the animated nodes.

    Attributes:
        times: ``(K,)`` seconds, non-decreasing, starting at 0.
        box: ``(K, 4, 4)`` ``T_world_box`` (box centre).
        robot: ``(K, 4, 4)`` ``T_world_robot`` (footprint centre on the floor, x = heading).
        phase: ``(K,)`` index of the plan phase each key belongs to.
        step: ``(K,)`` index of the pivot step rotating in that phase (-1: tilting or
            walking).
    """

    times: list[float] = field(default_factory=list)
    box: list[np.ndarray] = field(default_factory=list)
    robot: list[np.ndarray] = field(default_factory=list)
    phase: list[int] = field(default_factory=list)
    step: list[int] = field(default_factory=list)

    def add(self, t: float, box: np.ndarray, robot: np.ndarray, phase: int,
            step: int = -1) -> None:
        """Append one key."""
        self.times.append(t)
        self.box.append(box)
        self.robot.append(robot)
        self.phase.append(phase)
        self.step.append(step)

    @property
    def duration(self) -> float:
        """Length of the replay (s)."""
        return self.times[-1] if self.times else 0.0


def plan_keyframes(plan: Plan, *, timing: ReplayTiming | None = None) -> Keyframes:
    """Keyframes of a whole plan (see the module docstring for the timing rules)."""
    tm = timing or ReplayTiming()
    model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff)
    kf = Keyframes()
    t = 0.0
    obj: Pose = plan.start
    robot: Pose | None = None
    for i, ph in enumerate(plan.phases):
        if isinstance(ph, TransferPhase):
            obj, robot, t = _transfer(kf, model, ph, i, t, tm)
        elif isinstance(ph, TransitPhase):
            robot, t = _transit(kf, model, ph, i, t, tm)
            obj = ph.object_pose
    if not kf.times:  # no phase: a still frame
        pose = robot or model.robot_pose(obj, 0)
        kf.add(0.0, box_transform(model, obj), planar(pose), 0)
    return kf


def _transfer(kf: Keyframes, model: BoxGraspModel, ph: TransferPhase, index: int, t: float,
              tm: ReplayTiming) -> tuple[Pose, Pose, float]:
    k = ph.grasp
    obj, rob = ph.object_start, ph.robot_start
    n_tilt = 4
    for j in range(n_tilt + 1):  # incline the box towards the robot
        kf.add(t + tm.tilt_time * j / n_tilt,
               box_transform(model, obj, grasp=k, tilt=tm.tilt * j / n_tilt), planar(rob),
               index)
    t += tm.tilt_time
    for i_step, step in enumerate(ph.steps):
        dur = max(tm.min_step, abs(step.angle) / tm.pivot_speed)
        n = max(1, math.ceil(abs(step.angle) / tm.sample_angle))
        for j in range(1, n + 1):
            a = step.angle * j / n
            o = step.object if j == n else rotate_about(obj, step.pivot, a)
            r = step.robot if j == n else rotate_about(rob, step.pivot, a)
            kf.add(t + dur * j / n, box_transform(model, o, grasp=k, tilt=tm.tilt), planar(r),
                   index, i_step)
        t += dur
        obj, rob = step.object, step.robot
    for j in range(1, n_tilt + 1):  # put it back upright
        kf.add(t + tm.tilt_time * j / n_tilt,
               box_transform(model, obj, grasp=k, tilt=tm.tilt * (1 - j / n_tilt)), planar(rob),
               index)
    return obj, rob, t + tm.tilt_time


def _transit(kf: Keyframes, model: BoxGraspModel, ph: TransitPhase, index: int, t: float,
             tm: ReplayTiming) -> tuple[Pose, float]:
    box = box_transform(model, ph.object_pose)
    path = ph.robot_path
    kf.add(t, box, planar(path[0]), index)
    for a, b in zip(path, path[1:], strict=False):
        dyaw = wrap_angle(b[2] - a[2])
        dist = math.hypot(b[0] - a[0], b[1] - a[1])
        dur = max(dist / tm.walk_speed, abs(dyaw) / tm.turn_speed, 1e-3)
        n = max(1, math.ceil(abs(dyaw) / (0.25 * math.pi)))  # slerp needs < pi per key
        for j in range(1, n + 1):
            s = j / n
            pose = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw)
            kf.add(t + dur * s, box, planar(pose), index)
        t += dur
    return path[-1], t

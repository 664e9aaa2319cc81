"""Checks of a whole-body motion file, computed from the motion's own configurations.

Every check recomputes what it needs with pinocchio from ``q`` and the URDF named in the file
(never from the generator's internals):

* ``zmp`` -- ZMP of the LIPM from the CoM of ``q`` (second finite differences):
  ``zmp = c_xy - c_z / g * c''_xy``, inside the support polygon (sole rectangles of the feet in
  contact per ``support``; convex hull in double support) at every sample. The value is the
  worst signed margin (m, > 0 inside).
* ``feet`` -- a foot in contact does not slide, turn or sink: sole-centre displacement from the
  start of each contact interval < 1 mm, height > -1 mm.
* ``hands`` -- while ``holding``, each hand frame is within 1 cm of its grip point on the box
  (``box`` pose x ``grip_box``).
* ``joint_limits`` -- every joint within its URDF limits (1e-6 rad slack).
* ``joint_velocity`` -- every joint's largest finite-difference speed over the whole motion
  within its URDF velocity limit (value: worst fraction of the limit; the joint and the
  time named).
* ``pivot_corner`` -- during each pivot rotation one bottom corner of the box's supporting edge
  stays fixed (< 1 mm) on the floor; with a plan, at the step's ``pivot``.
* ``joint_accel`` -- every joint's largest acceleration (second differences) over the whole
  motion within its limit: 30 rad/s^2 for the arms, chest and head, which only follow the
  box, 50 rad/s^2 for the legs (value: worst fraction of the limit; the joint and the time
  named). ``MotionReport.peaks`` holds every joint's peaks
  (:mod:`pivot_ompl.wholebody.checks_peaks`).
* ``box_accel`` -- the box's angular acceleration while the hands hold it below 5 rad/s^2.
* ``box_clearance`` -- the robot's collision primitives, hands and fingers excluded, never
  penetrate the box (checked on about 2000 evenly spread samples).
* ``box_floor`` -- no box corner below the floor (> -1 mm).
* ``obstacles`` (with a scene) -- every link's collision geometry and the (tilted) box keep
  at least ``obstacle_clearance`` (1 cm by default) from every obstacle at every sample
  (coal broad phase; samples between queries are certified by a bound on how far the body
  can move, see :mod:`pivot_ompl.wholebody.clearance`). A failure names the link, the time,
  the obstacle and the depth; ``MotionReport.clearance`` holds the minimum per link.
* ``com_file`` -- the ``com`` array agrees with the CoM of ``q`` (< 1 mm).
* ``robot_plan`` (with a plan) -- the robot (sole midpoint) stands at each pivot step's
  ``robot`` pose at the step's end (< 1 cm, 0.02 rad) and keeps within 3 cm of a transit's
  ``robot_path``.
* ``box_plan`` (with a plan) -- the box pose equals the plan's object pose (with the recorded
  tilt) at the end of every pivot step and during transits (< 1 mm, < 1e-3 rad).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import profile_of
from pivot_ompl.motionfile import DYNAMICS, Motion
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import Scene
from pivot_ompl.wholebody import checks_box, checks_peaks, checks_robot
from pivot_ompl.wholebody.check_context import (
    CheckContext,
    CheckResult,
    Tolerances,
    kinematics,
)
from pivot_ompl.wholebody.clearance import ClearanceReport
from pivot_ompl.wholebody.joint_peaks import (
    BOX_ANGULAR_ACCEL_LIMIT,
    JointPeaks,
)
from pivot_ompl.wholebody.lipm import lipm_zmp
from pivot_ompl.wholebody.urdf_model import load_urdf_model

__all__ = ["CHECKS", "CheckContext", "CheckResult", "MotionReport", "Tolerances",
           "check_motion", "lipm_zmp"]

log = logging.getLogger(__name__)

#: A motion check: its result, or ``None`` where it does not apply (no plan, no scene).
Check = Callable[[CheckContext], CheckResult | None]

#: The checks after ``phase_order`` and ``finite``, in the order of the report.
CHECKS: tuple[Check, ...] = (
    checks_robot.com_file, checks_robot.zmp, checks_robot.feet, checks_robot.hands,
    checks_robot.joint_limits, checks_peaks.joint_velocity, checks_peaks.joint_accel,
    checks_peaks.box_accel, checks_box.box_floor, checks_box.pivot_corner, checks_box.box_clearance,
    checks_box.obstacles, checks_box.box_plan, checks_robot.robot_plan)


@dataclass
class MotionReport:
    """All checks of a motion."""

    results: list[CheckResult] = field(default_factory=list)
    #: Obstacle clearance per link and of the box (with a scene).
    clearance: ClearanceReport | None = None
    #: Every joint's largest speed and acceleration.
    peaks: JointPeaks | None = None

    @property
    def passed(self) -> bool:
        """True when every check passed."""
        return all(r.passed for r in self.results)

    def __getitem__(self, name: str) -> CheckResult:
        for r in self.results:
            if r.name == name:
                return r
        raise KeyError(name)

    def table(self) -> str:
        """A printable table of the results, its columns and units explained below it."""
        lines = [f"{'check':14s} {'result':6s} {'worst':>12s} {'passes':>6s} {'limit':>10s} "
                 f"{'unit':4s}  detail"]
        for r in self.results:
            sense = ">=" if r.name in AT_LEAST else "<="
            lines.append(f"{r.name:14s} {'PASS' if r.passed else 'FAIL':6s} "
                         f"{r.value:12.6f} {sense:>6s} {r.limit:10.4g} {r.unit:4s}  {r.detail}")
        lines.append("PASS" if self.passed else "FAIL")
        lines.extend(TABLE_LEGEND)
        return "\n".join(lines)


#: Checks whose worst value is a margin: they pass at or above their limit (the others at or
#: below it).
AT_LEAST = frozenset({"zmp", "obstacles", "box_clearance"})
#: What the columns and units of :meth:`MotionReport.table` mean.
TABLE_LEGEND = (
    "worst: the motion's worst value of the check (its smallest margin or largest error); "
    "passes: worst >= or <= limit;",
    "units: m metres, rad radians, smp samples, x ratio to the joint's own limit "
    "(1 = at the limit), r/s2 rad/s²; detail: where the worst value is.",
)


def _phase_sequence(phase: np.ndarray, n_phases: int | None) -> CheckResult:
    """Phases run 0, 1, 2, ... in order (each sample in its phase or the next one)."""
    bad = np.zeros(len(phase), dtype=bool)
    if len(phase):
        bad[0] = phase[0] != 0
        bad[1:] = (np.diff(phase) < 0) | (np.diff(phase) > 1)
        bad |= phase < 0
        if n_phases is not None:
            bad |= phase >= n_phases
    idx = np.nonzero(bad)[0]
    i = int(idx[0]) if len(idx) else -1
    detail = f"sample {i}: phase {int(phase[i])}" if i >= 0 else ""
    return CheckResult("phase_order", not len(idx), float(len(idx)), 0.0, "smp", detail, i)


def _all_finite(motion: Motion) -> CheckResult:
    """Every numeric array of the motion is finite (NaN anywhere fails)."""
    for key in ("t", "q", "box", "com", "zmp", "tilt"):
        a = getattr(motion, key)
        if a is None:
            continue
        rows = np.isfinite(np.asarray(a, dtype=float)).reshape(len(a), -1).all(axis=1)
        if not rows.all():
            i = int(np.argmin(rows))
            return CheckResult("finite", False, float((~rows).sum()), 0.0, "smp",
                               f"{key} at sample {i}", i)
    return CheckResult("finite", True, 0.0, 0.0, "smp", "")


def check_motion(motion: Motion, plan: Plan | None = None, *, scene: Scene | None = None,
                 zmp_tolerance: float = 0.0, foot_tolerance: float = 1e-3,
                 hand_tolerance: float = 0.01, corner_tolerance: float = 1e-3,
                 upper_accel_limit: float | None = None,
                 accel_limit: float | None = None,
                 box_accel_limit: float = BOX_ANGULAR_ACCEL_LIMIT,
                 obstacle_tolerance: float = 0.01) -> MotionReport:
    """Run every check on ``motion`` (and against ``plan`` when given).

    Args:
        motion: the motion.
        plan: the plan it was generated from (enables ``pivot_corner`` at the plan's pivots
            ``box_plan`` and ``robot_plan``).
        zmp_tolerance: smallest accepted ZMP margin (m; 0 = on the polygon boundary).
        foot_tolerance: feet slide/sink limit (m).
        hand_tolerance: hand-to-grip limit (m).
        corner_tolerance: pivot corner / box pose limit (m).
        upper_accel_limit: largest acceleration of an arm, chest or head joint (rad/s^2;
            default the motion's robot profile's, :data:`UPPER_ACCEL_LIMIT` for HRP-2).
        accel_limit: largest acceleration of any other joint (rad/s^2; default the
            profile's, :data:`ACCEL_LIMIT` for HRP-2).
        box_accel_limit: largest angular acceleration of the held box (rad/s^2).
        scene: the scene of the motion: enables the ``obstacles`` check.
        obstacle_tolerance: smallest accepted clearance of a link or the box to an
            obstacle (m).

    Raises:
        InputError: the motion file is inconsistent with its URDF, or ``plan`` is not the
            plan of this motion (phase count, box size).
    """
    motion.require(*DYNAMICS, "box_size")
    phase, box_size = motion.phase, motion.box_size
    assert phase is not None and box_size is not None  # required above
    if plan is not None:
        _require_plan_of(motion, plan, phase, box_size)
    rep = MotionReport()
    rep.results.append(_phase_sequence(phase, None if plan is None else len(plan.phases)))
    finite = _all_finite(motion)
    rep.results.append(finite)
    if not finite.passed:  # NaN would make every other check meaningless (or PASS)
        return rep
    robot = load_urdf_model(motion.urdf)
    profile = profile_of(motion.model, field="motion.robot_model")
    if upper_accel_limit is None:
        upper_accel_limit = profile.upper_accel_limit
    if accel_limit is None:
        accel_limit = profile.leg_accel_limit
    tol = Tolerances(zmp=zmp_tolerance, foot=foot_tolerance, hand=hand_tolerance,
                     corner=corner_tolerance, upper_accel=upper_accel_limit, accel=accel_limit,
                     box_accel=box_accel_limit, obstacle=obstacle_tolerance)
    ctx = CheckContext(motion, plan, scene, robot, kinematics(motion, robot), tol)
    for check in CHECKS:
        result = check(ctx)
        if result is not None:
            rep.results.append(result)
    rep.clearance = ctx.clearance
    rep.peaks = ctx.peaks
    return rep


def _require_plan_of(motion: Motion, plan: Plan, phase: np.ndarray,
                     box_size: tuple[float, float, float]) -> None:
    """Raise InputError unless ``plan`` has the motion's phase count and box size."""
    n_phases = int(phase.max()) + 1
    if len(plan.phases) != n_phases:
        raise InputError("plan.phases", len(plan.phases),
                         f"the motion has {n_phases} phases: not the plan it was made from")
    if not np.allclose(plan.object_size, box_size, atol=1e-9):
        raise InputError("plan.object_size", plan.object_size,
                         f"the motion's box is {tuple(box_size)}")

"""Peak checks of a motion: every joint's largest speed and acceleration, the held box's turn.

A real controller faults on the one sample where a joint's torque peaks, so these checks judge
the maximum over the whole motion, never a percentile, and name the sample where it occurs.
Speeds are first differences of ``q`` over the sample period, accelerations second
differences (the motion's own samples; nothing is filtered).

Limits (:mod:`pivot_ompl.wholebody.joint_peaks` gives the torques behind them):

* speed: each joint's URDF velocity limit;
* acceleration: 30 rad/s² for the arm, chest and head joints, which only follow the box,
  50 rad/s² for the others (the legs, which walk);
* the box's angular acceleration while held: 5 rad/s².
"""

from __future__ import annotations

import logging

import numpy as np

from pivot_ompl.motionfile import Motion
from pivot_ompl.wholebody.check_context import CheckContext, CheckResult
from pivot_ompl.wholebody.joint_peaks import JointPeaks, joint_peaks

log = logging.getLogger(__name__)

def _peaks(ctx: CheckContext) -> JointPeaks:
    if ctx.peaks is None:
        ctx.peaks = joint_peaks(ctx.motion, ctx.kin.velocity, upper_accel=ctx.tol.upper_accel,
                                accel=ctx.tol.accel)
    return ctx.peaks


def joint_velocity(ctx: CheckContext) -> CheckResult:
    """Every joint's largest speed within its URDF velocity limit (value: worst fraction)."""
    w = _peaks(ctx).worst_velocity()
    ratio = w.velocity / w.velocity_limit
    i = int(np.searchsorted(ctx.motion.t, w.velocity_time))
    return CheckResult("joint_velocity", ratio <= 1.0 + 1e-6, ratio, 1.0, "x",
                       f"{w.joint} {w.velocity:.2f} rad/s (limit {w.velocity_limit:g}) at "
                       f"t = {w.velocity_time:.3f} s", i)


def joint_accel(ctx: CheckContext) -> CheckResult:
    """Every joint's largest acceleration within its limit (value: worst fraction)."""
    w = _peaks(ctx).worst_accel()
    ratio = w.accel / w.accel_limit
    i = int(np.searchsorted(ctx.motion.t, w.accel_time))
    return CheckResult("joint_accel", ratio <= 1.0, ratio, 1.0, "x",
                       f"{w.joint} {w.accel:.1f} rad/s² (limit {w.accel_limit:g}) at "
                       f"t = {w.accel_time:.3f} s", i)


def box_angular_accel(motion: Motion) -> tuple[float, int]:
    """The held box's largest angular acceleration (rad/s²) and its sample (-1: never held).

    The box's angular velocity between two samples is the rotation vector of their relative
    rotation over the period; its change between two periods, over the period, is counted
    where the hands hold the box at all three samples.
    """
    from scipy.spatial.transform import Rotation

    holding = motion.holding
    if holding is None or len(motion.t) < 3:
        return 0.0, -1
    t = np.asarray(motion.t, dtype=float)
    rot = Rotation.from_quat(np.asarray(motion.box, dtype=float)[:, 3:])  # x y z w
    dt = np.diff(t)
    omega = (rot[1:] * rot[:-1].inv()).as_rotvec() / dt[:, None]  # world frame
    alpha = np.linalg.norm(np.diff(omega, axis=0), axis=1) / (0.5 * (dt[1:] + dt[:-1]))
    held = np.asarray(holding, dtype=bool)
    held3 = held[:-2] & held[1:-1] & held[2:]
    alpha = np.where(held3, alpha, 0.0)
    if not held3.any():
        return 0.0, -1
    i = int(np.argmax(alpha))
    return float(alpha[i]), i + 1


def box_accel(ctx: CheckContext) -> CheckResult:
    """The held box's largest angular acceleration within ``ctx.tol.box_accel`` (5 rad/s²)."""
    a, i = box_angular_accel(ctx.motion)
    limit = ctx.tol.box_accel
    where = f"at t = {ctx.motion.t[i]:.3f} s, phase {int(ctx.array('phase')[i])}" \
        if i >= 0 else "never held"
    return CheckResult("box_accel", a <= limit, a, limit, "r/s2",
                       f"angular acceleration of the held box; largest {where}", i)

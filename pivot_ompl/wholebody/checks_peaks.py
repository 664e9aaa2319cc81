"""Peak checks of a motion: every joint's largest speed and acceleration, the held box's turn.

A real controller faults on the one sample where a joint's torque peaks, so these checks judge
the maximum over the whole motion, never a percentile, and name the sample where it occurs.
Speeds are first differences of ``q`` over the sample period, accelerations second
differences (the motion's own samples; nothing is filtered).

Limits (see the README, *Whole-body checks*, for the torques behind them):

* speed: each joint's URDF velocity limit;
* acceleration: :data:`UPPER_ACCEL_LIMIT` (30 rad/s²) for the arm, chest and head joints,
  which only follow the box, :data:`ACCEL_LIMIT` (50 rad/s²) for the others (the legs, which
  walk);
* the box's angular acceleration while held: :data:`BOX_ANGULAR_ACCEL_LIMIT` (5 rad/s²).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from pivot_ompl.motionfile import Motion
from pivot_ompl.wholebody.check_context import CheckContext, CheckResult

log = logging.getLogger(__name__)

#: Largest acceleration of an arm, chest or head joint (rad/s²).
UPPER_ACCEL_LIMIT = 30.0
#: Largest acceleration of any other joint (rad/s²).
ACCEL_LIMIT = 50.0
#: Largest angular acceleration of the box while the hands hold it (rad/s²).
BOX_ANGULAR_ACCEL_LIMIT = 5.0
#: Name prefixes of the joints held to :data:`UPPER_ACCEL_LIMIT`.
UPPER_JOINTS = ("RARM", "LARM", "CHEST", "HEAD")


def accel_limit_of(joint: str, *, upper: float = UPPER_ACCEL_LIMIT,
                   other: float = ACCEL_LIMIT) -> float:
    """The acceleration limit of ``joint`` (rad/s²): ``upper`` for arms, chest and head."""
    return upper if joint.startswith(UPPER_JOINTS) else other


@dataclass(frozen=True)
class JointPeak:
    """One joint's largest speed and acceleration over a motion.

    Attributes:
        joint: the joint's name.
        velocity: largest |speed| (rad/s), at time ``velocity_time`` (s, the later sample of
            the difference).
        velocity_limit: its URDF velocity limit (rad/s).
        accel: largest |acceleration| (rad/s²), at time ``accel_time`` (s, the middle
            sample of the second difference).
        accel_limit: its acceleration limit (rad/s²).
    """

    joint: str
    velocity: float
    velocity_time: float
    velocity_limit: float
    accel: float
    accel_time: float
    accel_limit: float

    @property
    def passed(self) -> bool:
        """Both peaks within their limits."""
        return (self.velocity <= self.velocity_limit * (1.0 + 1e-6)
                and self.accel <= self.accel_limit)


@dataclass(frozen=True)
class JointPeaks:
    """Every joint's :class:`JointPeak`, in the motion's joint order."""

    joints: tuple[JointPeak, ...]

    def worst_accel(self) -> JointPeak:
        """The joint whose acceleration peak is the largest share of its limit."""
        return max(self.joints, key=lambda p: p.accel / p.accel_limit)

    def worst_velocity(self) -> JointPeak:
        """The joint whose speed peak is the largest share of its limit."""
        return max(self.joints, key=lambda p: p.velocity / p.velocity_limit)

    def table(self) -> str:
        """One line per joint: its peaks, their limits and times, PASS or FAIL."""
        lines = [f"{'joint':14s} {'|v| max':>8s} {'limit':>6s} {'at t (s)':>9s}  "
                 f"{'|a| max':>8s} {'limit':>6s} {'at t (s)':>9s}  result"]
        for p in self.joints:
            lines.append(f"{p.joint:14s} {p.velocity:8.2f} {p.velocity_limit:6.1f} "
                         f"{p.velocity_time:9.3f}  {p.accel:8.1f} {p.accel_limit:6.1f} "
                         f"{p.accel_time:9.3f}  {'PASS' if p.passed else 'FAIL'}")
        return "\n".join(lines)


def joint_peaks(motion: Motion, velocity_limits: np.ndarray, *,
                upper_accel: float = UPPER_ACCEL_LIMIT,
                accel: float = ACCEL_LIMIT) -> JointPeaks:
    """Every joint's largest speed and acceleration over ``motion`` (finite differences).

    Args:
        motion: the motion (``q`` with the free flyer first).
        velocity_limits: the actuated joints' velocity limits (rad/s), in ``q``'s order.
        upper_accel: acceleration limit of the arm, chest and head joints (rad/s²).
        accel: acceleration limit of the other joints (rad/s²).
    """
    t = np.asarray(motion.t, dtype=float)
    q = np.asarray(motion.q, dtype=float)[:, 7:]
    out = []
    dt = np.diff(t)
    vel = np.abs(np.diff(q, axis=0)) / dt[:, None] if len(t) > 1 else np.zeros((0, q.shape[1]))
    if len(t) > 2:
        # second differences on a possibly uneven grid
        v = np.diff(q, axis=0) / dt[:, None]
        acc = np.abs(np.diff(v, axis=0)) / (0.5 * (dt[1:] + dt[:-1]))[:, None]
    else:
        acc = np.zeros((0, q.shape[1]))
    for j, name in enumerate(motion.joint_names):
        iv = int(np.argmax(vel[:, j])) if len(vel) else -1
        ia = int(np.argmax(acc[:, j])) if len(acc) else -1
        out.append(JointPeak(
            str(name),
            float(vel[iv, j]) if iv >= 0 else 0.0, float(t[iv + 1]) if iv >= 0 else 0.0,
            float(velocity_limits[j]),
            float(acc[ia, j]) if ia >= 0 else 0.0, float(t[ia + 1]) if ia >= 0 else 0.0,
            accel_limit_of(str(name), upper=upper_accel, other=accel)))
    return JointPeaks(tuple(out))


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
    """The held box's largest angular acceleration within :data:`BOX_ANGULAR_ACCEL_LIMIT`."""
    a, i = box_angular_accel(ctx.motion)
    limit = ctx.tol.box_accel
    where = f"at t = {ctx.motion.t[i]:.3f} s, phase {int(ctx.array('phase')[i])}" \
        if i >= 0 else "never held"
    return CheckResult("box_accel", a <= limit, a, limit, "r/s2",
                       f"angular acceleration of the held box; largest {where}", i)

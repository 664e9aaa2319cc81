"""Every joint's largest speed and acceleration over a motion, and their limits.

Speeds are first differences of ``q`` over the sample period, accelerations second
differences (the motion's own samples; nothing is filtered).
:mod:`pivot_ompl.wholebody.checks_peaks` judges a motion by the limits below.

Why these limits: an acceleration costs torque. The joint-space inertia of HRP-2's model
(``pin.crba``, largest diagonal over the holding samples of the fig10 demo) times the limit
is at most 9.3 N·m at a shoulder at 30 rad/s² (RARM_JOINT0, 0.31 kg·m²: 15 % of its 60 N·m)
and 29 N·m at the chest yaw (0.97 kg·m²: 73 % of its 40 N·m, the tightest, and why the upper
body is held to 30 and generated at 20), 0.3 N·m at the neck; at 50 rad/s² a swinging leg's
knee costs 17 N·m and its hip pitch and roll 60 N·m of 100 N·m, leaving the rest for the
weight the stance leg carries. The efforts are the URDF's (from the HRP-2 fact sheet, which
calls them placeholders, not AIST ratings); the box, which rests on the floor and is pushed,
not carried, is not in the model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, profile_of
from pivot_ompl.motionfile import Motion

__all__ = ["ACCEL_LIMIT", "BOX_ANGULAR_ACCEL_LIMIT", "UPPER_ACCEL_LIMIT", "UPPER_JOINTS",
           "JointPeak", "JointPeaks", "accel_limit_of", "joint_peaks"]

#: Largest acceleration of an arm, chest or head joint (rad/s²).
UPPER_ACCEL_LIMIT = 30.0
#: Largest acceleration of any other joint (rad/s²).
ACCEL_LIMIT = 50.0
#: Largest angular acceleration of the box while the hands hold it (rad/s²).
BOX_ANGULAR_ACCEL_LIMIT = 5.0
#: Name prefixes of the default model's joints held to :data:`UPPER_ACCEL_LIMIT` (each
#: profile has its own: :attr:`~pivot_ompl.humanoids.HumanoidProfile.upper_prefixes`).
UPPER_JOINTS = PROFILES[DEFAULT_MODEL].upper_prefixes


def accel_limit_of(joint: str, *, upper: float = UPPER_ACCEL_LIMIT,
                   other: float = ACCEL_LIMIT,
                   upper_joints: tuple[str, ...] = UPPER_JOINTS) -> float:
    """The acceleration limit of ``joint`` (rad/s²).

    ``upper`` for arms, chest and head (the joints named by a prefix of ``upper_joints``).
    """
    return upper if joint.startswith(upper_joints) else other


@dataclass(frozen=True)
class JointPeak:
    """One joint's largest speed and acceleration over a motion.

    Attributes:
        joint: the joint's name.
        velocity: largest ``|speed|`` (rad/s), at time ``velocity_time`` (s, the later sample of
            the difference).
        velocity_limit: its URDF velocity limit (rad/s).
        accel: largest ``|acceleration|`` (rad/s²), at time ``accel_time`` (s, the middle
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
    upper_joints = profile_of(motion.model, field="motion.robot_model").upper_prefixes
    for j, name in enumerate(motion.joint_names):
        iv = int(np.argmax(vel[:, j])) if len(vel) else -1
        ia = int(np.argmax(acc[:, j])) if len(acc) else -1
        out.append(JointPeak(
            str(name),
            float(vel[iv, j]) if iv >= 0 else 0.0, float(t[iv + 1]) if iv >= 0 else 0.0,
            float(velocity_limits[j]),
            float(acc[ia, j]) if ia >= 0 else 0.0, float(t[ia + 1]) if ia >= 0 else 0.0,
            accel_limit_of(str(name), upper=upper_accel, other=accel,
                           upper_joints=upper_joints)))
    return JointPeaks(tuple(out))

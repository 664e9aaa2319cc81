"""Joints that slow down before their limits: a velocity damper on the kinematics QP.

The QP of each tick (PlaCo's kinematics solver) keeps every joint within its position
limits, but a joint driven towards a limit at speed is stopped there within one tick: an
acceleration of ``v / dt`` (a shoulder roll at 1.9 rad/s stopped in 5 ms: 380 rad/s²),
a torque spike on a real robot. :class:`JointDamper` narrows, before each tick, the position
limits the QP sees for the given joints to the farthest step from which the joint can still
stop at its limit changing its step by at most ``accel dt²`` a tick (:func:`braking_step`:
the braking distance of the discrete motion, so a joint brakes only when it must and then
exactly as hard as it must, never more than ``accel``). For the ``smooth`` joints (the arms,
chest and head, which only follow the box) every change of speed is bounded by ``accel`` too:
the next position within ``accel dt²`` of where the joint's present speed takes it (kept
inside the limits). Since a step allowed by :func:`braking_step` leaves the next tick a step
at most ``accel dt²`` shorter allowed, the two bounds never conflict.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np


def braking_step(distance: float, delta: float) -> float:
    """The longest step towards a limit ``distance`` away that still stops at the limit.

    A joint whose step (position change per tick) may shrink by at most ``delta`` a tick
    (``accel dt²``) and takes the step ``s`` now covers ``s + (s - delta) + (s - 2 delta) +
    ...`` before it stands: with ``n = floor(s / delta)`` further steps, ``(n + 1) s - delta
    n (n + 1) / 2``. Returns the largest ``s`` with that at most ``distance`` (0 at the
    limit): ``s = distance / (n + 1) + delta n / 2``, which lies in ``[n delta, (n + 1)
    delta)`` exactly when ``n (n + 1) <= 2 distance / delta < (n + 1) (n + 2)``.
    """
    if distance <= 0.0:
        return 0.0
    if delta <= 0.0:
        return distance
    x = 2.0 * distance / delta
    n = math.floor(0.5 * (math.sqrt(1.0 + 4.0 * x) - 1.0))
    if n * (n + 1) > x:  # round-off of the square root, either way
        n -= 1
    elif (n + 1) * (n + 2) <= x:
        n += 1
    return distance / (n + 1) + 0.5 * delta * n


def braking_steps(distance: np.ndarray, delta: float) -> np.ndarray:
    """:func:`braking_step` of every element of ``distance`` (``delta`` > 0).

    The piece ``n`` from the square root is not corrected for round-off: the step is
    continuous in ``distance`` across pieces, so a neighbouring piece's formula differs from
    the exact step by the round-off only.
    """
    d = np.maximum(distance, 0.0)
    n = np.floor(0.5 * np.sqrt(1.0 + (8.0 / delta) * d) - 0.5)
    return d / (n + 1.0) + (0.5 * delta) * n


class JointDamper:
    """Per-tick position limits that make the given joints brake before their limits.

    The bounds also hold every joint's speed within its URDF velocity limit (a step of at
    most ``velocity limit * dt``), so that the solver needs no velocity constraints of its
    own: the same feasible steps with half the inequality rows.

    Args:
        robot: the PlaCo ``RobotWrapper`` (its model's joint limits are narrowed and
            restored; its ``state.q`` read).
        joints: the joints bounded each tick (their URDF limits are read once).
        accel: the largest acceleration while braking, and of the ``smooth`` joints at any
            time (rad/s²).
        dt: the tick (s).
        smooth: the joints whose every change of speed is bounded by ``accel``.
        damped: the joints that brake before their position limits (default: ``joints``).
    """

    def __init__(self, robot: Any, joints: Iterable[str], *, accel: float, dt: float,
                 smooth: Iterable[str] = (), damped: Iterable[str] | None = None) -> None:
        """Read the joints' limits and their places in the configuration."""
        self.robot, self.accel, self.dt = robot, accel, dt
        model = robot.model
        names = list(joints)
        self._iq = np.array([model.joints[model.getJointId(j)].idx_q for j in names],
                            dtype=int)
        iv = np.array([model.joints[model.getJointId(j)].idx_v for j in names], dtype=int)
        self._lower_all = np.array(model.lowerPositionLimit, dtype=float)
        self._upper_all = np.array(model.upperPositionLimit, dtype=float)
        self._lo, self._hi = self._lower_all[self._iq], self._upper_all[self._iq]
        self._step_max = np.array(model.velocityLimit, dtype=float)[iv] * dt
        self.limits = {j: (float(a), float(b))
                       for j, a, b in zip(names, self._lo, self._hi, strict=True)}
        self.smooth = {j for j in smooth if j in self.limits}
        damp = set(names if damped is None else damped)
        self._smooth = np.array([j in self.smooth for j in names], dtype=bool)
        self._damped = np.array([j in damp for j in names], dtype=bool)
        self._any_smooth, self._all_smooth = bool(self._smooth.any()), bool(self._smooth.all())
        self._last: np.ndarray | None = None
        # per-tick work on the damped joints only, the others bounded by their speed alone
        di = np.nonzero(self._damped)[0]
        self._di, self._lo_hi = di, np.concatenate((-self._lo[di], self._hi[di]))
        self._sign = np.concatenate((np.ones(len(di)), -np.ones(len(di))))
        self._lower, self._upper = self._lower_all.copy(), self._upper_all.copy()

    def apply(self) -> None:
        """Set this tick's limits from the joints' current positions (and last ones)."""
        delta = self.accel * self.dt * self.dt
        q = np.asarray(self.robot.state.q)[self._iq]
        nd = len(self._di)
        down, up = self._step_max.copy(), self._step_max.copy()
        if nd:
            qd = q[self._di]
            # distances to the lower and upper limits, then the braking steps
            brake = braking_steps(self._sign * np.concatenate((qd, qd)) + self._lo_hi, delta)
            down[self._di] = np.minimum(down[self._di], brake[:nd])
            up[self._di] = np.minimum(up[self._di], brake[nd:])
        low = np.maximum(self._lo, q - down)
        high = np.minimum(self._hi, q + up)
        last, s = self._last, self._smooth
        if last is not None and self._any_smooth:
            coast = 2.0 * q - last  # where each joint goes at its present speed
            low_s = np.minimum(np.maximum(low, coast - delta), high)
            high_s = np.maximum(np.minimum(high, coast + delta), low_s)
            if self._all_smooth:
                low, high = low_s, high_s
            else:
                low, high = np.where(s, low_s, low), np.where(s, high_s, high)
        self._last = q
        self._set(low, high)

    def restore(self) -> None:
        """Put the URDF limits back."""
        self._set(self._lo, self._hi)

    def _set(self, low: np.ndarray, high: np.ndarray) -> None:
        model = self.robot.model
        self._lower[self._iq], self._upper[self._iq] = low, high  # the other entries: URDF's
        model.lowerPositionLimit, model.upperPositionLimit = self._lower, self._upper

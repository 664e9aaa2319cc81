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


def braking_steps(distance: np.ndarray, delta: np.ndarray | float) -> np.ndarray:
    """:func:`braking_step` of every element of ``distance`` (``delta`` > 0, one or per element).

    The piece ``n`` from the square root is not corrected for round-off: the step is
    continuous in ``distance`` across pieces, so a neighbouring piece's formula differs from
    the exact step by the round-off only.
    """
    d = np.maximum(distance, 0.0)
    n = np.floor(0.5 * np.sqrt(1.0 + (8.0 / delta) * d) - 0.5)
    return d / (n + 1.0) + (0.5 * delta) * n


def braking_distance(step: np.ndarray, delta: np.ndarray | float) -> np.ndarray:
    """The distance a joint covers before it stands from the step ``step`` (``delta`` > 0).

    The inverse of :func:`braking_step` at ``step``: ``(n + 1) step - delta n (n + 1) / 2``
    with ``n = floor(step / delta)``. From a limit at least this far away, the braking step
    is at least ``step`` (:func:`braking_step` grows with the distance).
    """
    n = np.floor(step / delta)
    return (n + 1.0) * step - 0.5 * delta * n * (n + 1.0)


#: ``accel dt²`` standing for "no braking": the braking step of a distance is the distance
#: (:func:`braking_step` with one piece, ``n = 0``, for every distance of a joint's range).
_NO_BRAKING = 1e30


class JointDamper:
    """Per-tick position limits that make the given joints brake before their limits.

    The bounds also hold every joint's speed within its URDF velocity limit (a step of at
    most ``velocity limit * dt``), so that the solver needs no velocity constraints of its
    own: the same feasible steps with half the inequality rows.

    Each tick's work is a few operations on one vector of ``2 n`` entries, the negated
    lower and the upper bounds of the ``n`` joints side by side: a joint's step towards a
    limit is :func:`braking_steps` of its distance to the limit capped at
    :func:`braking_distance` of its speed's step (beyond which the speed bounds it), with
    ``accel dt²`` so large for the joints that do not brake that the step is the distance.

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
        iq = np.array([model.joints[model.getJointId(j)].idx_q for j in names], dtype=int)
        iv = np.array([model.joints[model.getJointId(j)].idx_v for j in names], dtype=int)
        # the joints' places in q, a slice when they are consecutive (cheaper to index)
        self._q_at: slice | np.ndarray = iq
        if len(iq) and np.array_equal(iq, np.arange(iq[0], iq[0] + len(iq))):
            self._q_at = slice(int(iq[0]), int(iq[0]) + len(iq))
        lower_all = np.array(model.lowerPositionLimit, dtype=float)
        upper_all = np.array(model.upperPositionLimit, dtype=float)
        self._lo, self._hi = lower_all[iq], upper_all[iq]
        self.limits = {j: (float(a), float(b))
                       for j, a, b in zip(names, self._lo, self._hi, strict=True)}
        self.smooth = {j for j in smooth if j in self.limits}
        damp = set(names if damped is None else damped)
        delta = accel * dt * dt
        self._n = len(names)
        # the stacked vectors: entry i bounds joint i from below (negated), n + i from above
        step = np.tile(np.array(model.velocityLimit, dtype=float)[iv] * dt, 2)
        d = np.tile([delta if j in damp and delta > 0.0 else _NO_BRAKING for j in names], 2)
        self._lim = np.concatenate((-self._lo, self._hi))
        self._cap = braking_distance(step, d)
        self._delta = d
        self._coast_d = np.tile([delta if j in self.smooth else np.inf for j in names], 2)
        self._any_smooth = bool(self.smooth)
        self._last: np.ndarray | None = None
        self._lower, self._upper = lower_all, upper_all

    def apply(self) -> None:
        """Set this tick's limits from the joints' current positions (and last ones)."""
        n = self._n
        q = np.asarray(self.robot.state.q)[self._q_at]
        s = np.concatenate((-q, q))
        # the distances to the limits, capped where the speed bounds
        d = np.minimum(self._lim - s, self._cap)
        b = s + braking_steps(d, self._delta)  # [-low, high]
        np.minimum(b, self._lim, out=b)
        last = self._last
        if last is not None and self._any_smooth:
            # within accel dt² of where each smooth joint goes at its present speed
            t = np.minimum(b, (2.0 * s - last) + self._coast_d)
            np.maximum(t[:n], -b[n:], out=t[:n])  # low <= high
            np.maximum(t[n:], -t[:n], out=t[n:])
            b = t
        self._last = s
        self._set(-b[:n], b[n:])

    def restore(self) -> None:
        """Put the URDF limits back."""
        self._set(self._lo, self._hi)

    def _set(self, low: np.ndarray, high: np.ndarray) -> None:
        model = self.robot.model
        self._lower[self._q_at], self._upper[self._q_at] = low, high  # the others: URDF's
        model.lowerPositionLimit, model.upperPositionLimit = self._lower, self._upper

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


def braking_step(distance: float, delta: float) -> float:
    """The longest step towards a limit ``distance`` away that still stops at the limit.

    A joint whose step (position change per tick) may shrink by at most ``delta`` a tick
    (``accel dt²``) and takes the step ``s`` now covers ``s + (s - delta) + (s - 2 delta) +
    ...`` before it stands: with ``n = floor(s / delta)`` further steps, ``(n + 1) s - delta
    n (n + 1) / 2``. Returns the largest ``s`` with that at most ``distance`` (0 at the
    limit; ``distance`` when one step reaches it within ``delta``).
    """
    if distance <= 0.0:
        return 0.0
    if delta <= 0.0:
        return distance
    # continuous estimate of the number of further braking ticks, then the exact piece
    n = max(0, int(math.sqrt(2.0 * distance / delta)) - 1)
    while True:
        s = (distance + delta * n * (n + 1) / 2.0) / (n + 1)
        if s < (n + 1) * delta or s <= 0.0:
            if s >= n * delta:
                return s
            n -= 1  # the estimate overshot the piece
        else:
            n += 1
        if n < 0:  # pragma: no cover - unreachable for distance > 0
            return 0.0


class JointDamper:
    """Per-tick position limits that make the given joints brake before their limits.

    Args:
        robot: the PlaCo ``RobotWrapper`` (its joint limits are narrowed and restored).
        joints: the joints to damp (their URDF limits are read once).
        accel: the largest acceleration while braking, and of the ``smooth`` joints at any
            time (rad/s²).
        dt: the tick (s).
        smooth: the joints whose every change of speed is bounded by ``accel``.
    """

    def __init__(self, robot: Any, joints: Iterable[str], *, accel: float, dt: float,
                 smooth: Iterable[str] = ()) -> None:
        """Read the joints' limits."""
        self.robot, self.accel, self.dt = robot, accel, dt
        self.limits = {j: tuple(float(v) for v in robot.get_joint_limits(j)) for j in joints}
        self.smooth = {j for j in smooth if j in self.limits}
        self._last: dict[str, float] = {}

    def apply(self) -> None:
        """Set this tick's limits from the joints' current positions (and last ones)."""
        delta = self.accel * self.dt * self.dt
        for name, (lo, hi) in self.limits.items():
            q = float(self.robot.get_joint(name))
            low = max(lo, min(q, q - braking_step(q - lo, delta)))
            high = min(hi, max(q, q + braking_step(hi - q, delta)))
            prev = self._last.get(name)
            if name in self.smooth and prev is not None:
                coast = q + (q - prev)  # where the joint goes at its present speed
                low = min(max(low, coast - delta), high)
                high = max(min(high, coast + delta), low)
            self._last[name] = q
            self.robot.set_joint_limits(name, low, high)

    def restore(self) -> None:
        """Put the URDF limits back."""
        for name, (lo, hi) in self.limits.items():
            self.robot.set_joint_limits(name, lo, hi)

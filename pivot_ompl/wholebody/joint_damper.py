"""Joints that slow down before their limits: a velocity damper on the kinematics QP.

The QP of each tick (PlaCo's kinematics solver) keeps every joint within its position
limits, but a joint driven towards a limit at speed is stopped there within one tick: an
acceleration of ``v / dt`` (a shoulder roll at 1.9 rad/s stopped in 5 ms: 380 rad/s²),
a torque spike on a real robot. :class:`JointDamper` narrows, before each tick, the position
limits the QP sees for the given joints to what a joint moving towards a limit may reach
while still able to stop there decelerating at most ``accel``: the speed towards a limit at
distance ``d`` is bounded by ``sqrt(2 accel d)``, so the step of one tick by
``dt sqrt(2 accel d)``. For the ``smooth`` joints (the arms, which only follow the box) every
change of speed is bounded by ``accel`` too: the next position within ``accel dt²`` of where
the joint's present speed takes it (kept inside the limits).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any


class JointDamper:
    """Per-tick position limits that make the given joints brake before their limits.

    Args:
        robot: the PlaCo ``RobotWrapper`` (its joint limits are narrowed and restored).
        joints: the joints to damp (their URDF limits are read once).
        accel: the largest deceleration towards a limit (rad/s²).
        dt: the tick (s).
    """

    def __init__(self, robot: Any, joints: Iterable[str], *, accel: float, dt: float,
                 smooth: Iterable[str] = ()) -> None:
        """Read the joints' limits (``smooth``: joints whose every acceleration is bounded)."""
        self.robot, self.accel, self.dt = robot, accel, dt
        self.limits = {j: tuple(float(v) for v in robot.get_joint_limits(j)) for j in joints}
        self.smooth = {j for j in smooth if j in self.limits}
        self._last: dict[str, float] = {}

    def apply(self) -> None:
        """Set this tick's limits from the joints' current positions (and last ones)."""
        dt, a = self.dt, self.accel
        for name, (lo, hi) in self.limits.items():
            q = float(self.robot.get_joint(name))
            below = dt * math.sqrt(2.0 * a * max(0.0, q - lo))
            above = dt * math.sqrt(2.0 * a * max(0.0, hi - q))
            low, high = max(lo, min(q, q - below)), min(hi, max(q, q + above))
            prev = self._last.get(name)
            if name in self.smooth and prev is not None:
                coast = q + (q - prev)  # where the joint goes at its present speed
                low = min(max(low, coast - a * dt * dt), high)
                high = max(min(high, coast + a * dt * dt), low)
            self._last[name] = q
            self.robot.set_joint_limits(name, low, high)

    def restore(self) -> None:
        """Put the URDF limits back."""
        for name, (lo, hi) in self.limits.items():
            self.robot.set_joint_limits(name, lo, hi)

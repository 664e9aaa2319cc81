"""The joint damper: joints driven at their limits brake and speed up within the bound."""

from __future__ import annotations

import numpy as np
import pytest

from pivot_ompl.wholebody.joint_damper import JointDamper


class _Robot:
    """The two methods of PlaCo's RobotWrapper the damper uses, for one joint."""

    def __init__(self, q: float, lo: float, hi: float) -> None:
        self.q, self.urdf, self.lim = q, (lo, hi), (lo, hi)

    def get_joint_limits(self, name: str) -> np.ndarray:
        return np.array(self.urdf)

    def get_joint(self, name: str) -> float:
        return self.q

    def set_joint_limits(self, name: str, lo: float, hi: float) -> None:
        self.lim = (lo, hi)


def _drive(robot: _Robot, damper: JointDamper, targets: list[float]) -> np.ndarray:
    """A QP that wants each target at once: it goes as far as the limits let it."""
    qs = [robot.q]
    for target in targets:
        damper.apply()
        lo, hi = robot.lim
        assert robot.urdf[0] <= lo <= hi <= robot.urdf[1]  # never wider than the URDF's
        robot.q = min(max(target, lo), hi)
        qs.append(robot.q)
    return np.array(qs)


@pytest.mark.parametrize("smooth", [False, True])
def test_a_joint_thrown_at_its_limit_brakes_within_the_bound(smooth):
    dt, a = 0.005, 20.0
    robot = _Robot(0.3, -0.1745, 1.0)
    damper = JointDamper(robot, ["J"], accel=a, dt=dt, smooth=["J"] if smooth else [])
    q = _drive(robot, damper, [-1.0] * 400)  # pulled far beyond the lower limit
    assert q.min() >= -0.1745 - 1e-12 and q[-1] == pytest.approx(-0.1745, abs=1e-3)
    acc = np.diff(q, 2) / dt**2
    braking = acc[acc > 0]  # slowing down towards the limit
    assert braking.max() <= 2 * a + 1e-6


def test_a_smooth_joint_leaves_its_limit_gently():
    """Pinned at its limit, then pulled the other way: no jump of speed."""
    dt, a = 0.005, 20.0
    robot = _Robot(-0.1745, -0.1745, 1.0)
    damper = JointDamper(robot, ["J"], accel=a, dt=dt, smooth=["J"])
    q = _drive(robot, damper, [-1.0] * 20 + [1.0] * 200)
    acc = np.diff(q, 2) / dt**2
    assert np.abs(acc).max() <= 2 * a + 1e-6
    plain = JointDamper(_Robot(-0.1745, -0.1745, 1.0), ["J"], accel=a, dt=dt)
    q2 = _drive(plain.robot, plain, [-1.0] * 20 + [1.0] * 200)
    assert np.abs(np.diff(q2, 2) / dt**2).max() > 10 * a  # without it: a jump


def test_the_urdf_limits_come_back():
    robot = _Robot(0.0, -1.0, 1.0)
    damper = JointDamper(robot, ["J"], accel=20.0, dt=0.005)
    damper.apply()
    assert robot.lim != (-1.0, 1.0)
    damper.restore()
    assert robot.lim == (-1.0, 1.0)

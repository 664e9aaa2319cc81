"""The joint damper: joints driven at their limits brake and speed up within the bound."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.wholebody.joint_damper import JointDamper, braking_step, braking_steps


class _Robot:
    """What the damper reads of PlaCo's RobotWrapper (``model`` limits, ``state.q``), one joint."""

    class _Joint:
        idx_q = 0
        idx_v = 0

    def __init__(self, q: float, lo: float, hi: float, speed: float = 1e3) -> None:
        self.urdf = (lo, hi)
        self.model = SimpleNamespace(lowerPositionLimit=np.array([lo]),
                                     upperPositionLimit=np.array([hi]),
                                     velocityLimit=np.array([speed]),
                                     joints=[None, self._Joint()], getJointId=lambda name: 1)
        self.state = SimpleNamespace(q=np.array([q]))

    @property
    def q(self) -> float:
        return float(self.state.q[0])

    @q.setter
    def q(self, value: float) -> None:
        self.state.q = np.array([value])

    @property
    def lim(self) -> tuple[float, float]:
        return float(self.model.lowerPositionLimit[0]), float(self.model.upperPositionLimit[0])


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


def _covered(step: float, delta: float) -> float:
    """Distance a joint covers taking ``step`` now, then steps shorter by ``delta`` each tick."""
    total = 0.0
    while step > 0.0:
        total, step = total + step, step - delta
    return total


@given(st.floats(0.0, 2.0), st.floats(1e-6, 1e-2))
def test_the_braking_step_is_the_longest_that_still_stops(distance, delta):
    s = braking_step(distance, delta)
    assert 0.0 <= s <= distance
    assert _covered(s, delta) <= distance + 1e-9  # stops at the limit
    if s < distance:  # and no longer step does (braking no harder than needed)
        assert _covered(s + 1e-6 * delta + 1e-12, delta) > distance - 1e-9


def test_the_array_braking_steps_are_the_exact_ones():
    rng = np.random.default_rng(0)
    d = np.concatenate(([0.0, -0.1, 1e-12], rng.uniform(0.0, 2.0, 500),
                        [k * (k + 1) * 2.5e-4 for k in range(50)]))  # piece boundaries
    exact = np.array([braking_step(x, 5e-4) for x in d])
    assert np.allclose(braking_steps(d, 5e-4), exact, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("smooth", [False, True])
def test_a_joint_thrown_at_its_limit_brakes_within_the_bound(smooth):
    dt, a = 0.005, 20.0
    robot = _Robot(0.3, -0.1745, 1.0)
    damper = JointDamper(robot, ["J"], accel=a, dt=dt, smooth=["J"] if smooth else [])
    q = _drive(robot, damper, [-1.0] * 400)  # pulled far beyond the lower limit
    assert q.min() >= -0.1745 - 1e-12 and q[-1] == pytest.approx(-0.1745, abs=1e-12)
    assert np.all(np.diff(q) <= 1e-15)  # straight to the limit: no overshoot, no bounce
    acc = np.diff(q, 2) / dt**2
    braking = acc[acc > 0]  # slowing down towards the limit
    assert braking.max() <= a * (1 + 1e-9)


def test_a_smooth_joint_leaves_its_limit_gently():
    """Pinned at its limit, then pulled the other way: no jump of speed."""
    dt, a = 0.005, 20.0
    robot = _Robot(-0.1745, -0.1745, 1.0)
    damper = JointDamper(robot, ["J"], accel=a, dt=dt, smooth=["J"])
    q = _drive(robot, damper, [-1.0] * 20 + [1.0] * 200 + [-1.0] * 200)
    acc = np.diff(q, 2) / dt**2
    assert np.abs(acc).max() <= a * (1 + 1e-9)
    plain = JointDamper(_Robot(-0.1745, -0.1745, 1.0), ["J"], accel=a, dt=dt)
    q2 = _drive(plain.robot, plain, [-1.0] * 20 + [1.0] * 200)
    assert np.abs(np.diff(q2, 2) / dt**2).max() > 10 * a  # without it: a jump


def test_on_a_model_joint_the_damper_keeps_its_bound():
    """HRP-2's left shoulder roll in PlaCo's QP, pulled past one limit, then the other."""
    placo = pytest.importorskip("placo")
    from pivot_ompl.hrp2 import urdf_path

    dt, a, joint = 0.005, 20.0, "LARM_JOINT1"
    robot = placo.RobotWrapper(str(urdf_path()), placo.Flags.ignore_collisions)
    solver = placo.KinematicsSolver(robot)
    solver.dt = dt
    solver.mask_fbase(True)
    solver.enable_velocity_limits(True)
    solver.enable_joint_limits(True)
    task = solver.add_joints_task()
    task.set_joints({joint: 3.0})
    task.configure("pull", "soft", 1.0)
    lo, hi = (float(v) for v in robot.get_joint_limits(joint))
    damper = JointDamper(robot, [joint], accel=a, dt=dt, smooth=[joint])
    q = [robot.get_joint(joint)]
    for k in range(600):
        if k == 300:
            task.set_joints({joint: -3.0})
        robot.update_kinematics()
        damper.apply()
        solver.solve(True)
        q.append(robot.get_joint(joint))
    damper.restore()
    qs = np.array(q)
    acc = np.abs(np.diff(qs, 2)) / dt**2
    assert acc.max() <= a * (1 + 1e-6)
    assert qs[300] == pytest.approx(hi, abs=1e-9) and qs[-1] == pytest.approx(lo, abs=1e-9)
    assert np.all(np.diff(qs[:301]) >= -1e-12)  # reaches the limit without a bounce
    assert np.abs(np.diff(qs) / dt).max() > 2.0  # and it did move fast in between
    assert tuple(robot.get_joint_limits(joint)) == pytest.approx((lo, hi))


def test_the_urdf_limits_come_back():
    robot = _Robot(0.0, -1.0, 1.0)
    damper = JointDamper(robot, ["J"], accel=20.0, dt=0.005)
    damper.apply()
    assert robot.lim != (-1.0, 1.0)
    damper.restore()
    assert robot.lim == (-1.0, 1.0)


@pytest.mark.parametrize("damped", [True, False])
def test_the_bounds_hold_the_velocity_limit(damped: bool) -> None:
    """Far from its limits a joint may move at most its velocity limit times the tick."""
    robot = _Robot(0.0, -2.0, 2.0, speed=3.0)
    damper = JointDamper(robot, ["J"], accel=20.0, dt=0.01, damped=["J"] if damped else [])
    damper.apply()
    assert robot.lim == pytest.approx((-0.03, 0.03))


class _Robots:
    """Several joints after a floating base (q index 7 + i), as PlaCo's model has them."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, speed: np.ndarray) -> None:
        n = len(lo)
        self.model = SimpleNamespace(
            lowerPositionLimit=np.concatenate((np.full(7, -1e9), lo)),
            upperPositionLimit=np.concatenate((np.full(7, 1e9), hi)),
            velocityLimit=np.concatenate((np.zeros(6), speed)),
            joints=[None] + [SimpleNamespace(idx_q=7 + i, idx_v=6 + i) for i in range(n)],
            getJointId=lambda name: 1 + int(name[1:]))
        self.state = SimpleNamespace(q=np.zeros(7 + n))


def _reference_bounds(q, last, lo, hi, step, delta, damped, smooth):
    """One joint's bounds from the scalar rules (the damper's docstring), joint by joint."""
    down = min(step, braking_step(q - lo, delta)) if damped else step
    up = min(step, braking_step(hi - q, delta)) if damped else step
    low, high = max(lo, q - down), min(hi, q + up)
    if smooth and last is not None:
        coast = 2.0 * q - last
        low = min(max(low, coast - delta), high)
        high = max(min(high, coast + delta), low)
    return low, high


@given(st.integers(0, 2**32 - 1))
def test_every_joint_gets_the_bounds_of_the_scalar_rules(seed):
    """Joints of every kind (damped or not, smooth or not), near and far from their limits."""
    rng = np.random.default_rng(seed)
    n, dt, a = 12, 0.01, 20.0
    lo = rng.uniform(-2.0, -0.1, n)
    hi = rng.uniform(0.1, 2.0, n)
    speed = rng.uniform(0.5, 4.0, n)
    robot = _Robots(lo, hi, speed)
    names = [f"J{i}" for i in range(n)]
    damped = [j for j in names if rng.random() < 0.6]
    smooth = [j for j in damped if rng.random() < 0.7] + [j for j in names if rng.random() < 0.1]
    damper = JointDamper(robot, names, accel=a, dt=dt, smooth=smooth, damped=damped)
    last = None
    for _ in range(3):
        # near a limit (within its braking distance), at it, or anywhere in the range
        q = np.where(rng.random(n) < 0.5, np.where(rng.random(n) < 0.5, lo, hi)
                     + rng.uniform(-0.3, 0.3, n), rng.uniform(lo, hi))
        q = np.clip(q, lo, hi)
        robot.state.q = np.concatenate((np.zeros(7), q))
        damper.apply()
        got_lo = robot.model.lowerPositionLimit[7:]
        got_hi = robot.model.upperPositionLimit[7:]
        for i, j in enumerate(names):
            want = _reference_bounds(q[i], None if last is None else last[i], lo[i], hi[i],
                                     speed[i] * dt, a * dt * dt, j in damped, j in smooth)
            assert (got_lo[i], got_hi[i]) == pytest.approx(want, abs=1e-12), j
        assert np.all(robot.model.lowerPositionLimit[:7] == -1e9)  # the base untouched
        last = q
    damper.restore()
    assert np.array_equal(robot.model.lowerPositionLimit[7:], lo)

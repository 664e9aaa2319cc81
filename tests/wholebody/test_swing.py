"""The swing foot's targets: held down for the lift-off delay, then a minimum-jerk swing."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.wholebody.swing import SwingFoot
from pivot_ompl.wholebody.walker import WalkSettings


def _frame(x: float, y: float) -> np.ndarray:
    T = np.eye(4)
    T[:2, 3] = (x, y)
    return T


class _Trajectory:
    """A pattern generator's trajectory: double support on [0, 0.1), the left foot supporting
    on [0.1, 0.1 + single); the right foot goes from ``a`` to ``b``."""

    def __init__(self, single: float, a: np.ndarray, b: np.ndarray) -> None:
        self.t1, self.a, self.b = 0.1 + single, a, b

    def support_is_both(self, t: float) -> bool:
        return t < 0.1 or t >= self.t1

    def get_part_t_start(self, t: float) -> float:
        return 0.1

    def get_part_t_end(self, t: float) -> float:
        return self.t1

    def support_side(self, t: float) -> str:
        return "left"

    def get_T_world_right(self, t: float) -> np.ndarray:
        return self.a if t <= 0.1 else self.b  # the pattern's own swing is not followed

    def get_T_world_left(self, t: float) -> np.ndarray:
        raise AssertionError("the support foot's target is not the swing's")


def _tasks() -> SimpleNamespace:
    return SimpleNamespace(right_foot_task=SimpleNamespace(T_world_frame=None),
                           left_foot_task=SimpleNamespace(T_world_frame=None))


@settings(max_examples=30, deadline=None)
@given(dx=st.floats(0.02, 0.3), dy=st.floats(-0.1, 0.1))
def test_swing_is_held_then_lands_on_the_landing_frame_smoothly(dx: float, dy: float) -> None:
    s = WalkSettings()
    swing, tasks = SwingFoot(s), _tasks()
    a, b = _frame(0.0, -0.1), _frame(dx, -0.1 + dy)
    traj = _Trajectory(s.single_support_duration, a, b)
    dt = s.dt
    ts = np.arange(0.1, traj.t1 - 1e-9, dt)  # the single support
    held, xs = [], []
    for t in ts:
        held.append(swing.update(traj, float(t), tasks))
        T = tasks.right_foot_task.T_world_frame
        xs.append(T[:3, 3].copy())
    held_t = ts[np.array(held)]
    assert held_t.size and held_t.max() - 0.1 < swing.lift_off_delay
    assert np.allclose(xs[0], a[:3, 3])  # the foot starts where it was
    assert np.allclose(xs[-1], b[:3, 3], atol=1e-4)  # and lands on its landing frame
    x = np.array(xs)
    acc = np.diff(x, 2, axis=0) / dt**2
    # minimum jerk from rest: the acceleration grows from zero at lift-off and returns to
    # zero at touch-down (a cubic or a linear swing starts at its peak or with a jump)
    peak = np.abs(acc).max()
    h = len(held_t)
    assert np.abs(acc[h - 1:h + 1]).max() < 0.4 * peak
    assert np.abs(acc[-2:]).max() < 0.4 * peak
    assert x[:, 2].max() == pytest.approx(s.foot_height, rel=0.05)


def test_double_support_leaves_the_targets_alone() -> None:
    swing, tasks = SwingFoot(WalkSettings()), _tasks()
    traj = _Trajectory(0.8, _frame(0, 0), _frame(0.1, 0))
    assert swing.update(traj, 0.05, tasks) is False
    assert tasks.right_foot_task.T_world_frame is None

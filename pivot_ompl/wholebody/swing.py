"""The swing foot's target over a single support: held down briefly, then a minimum-jerk swing.

PlaCo's walk pattern generator constrains the ZMP only at its LIPM samples: it reaches the new
support foot one sample after the double support ends. Holding the swing foot down meanwhile
(:attr:`SwingFoot.lift_off_delay`) keeps that ZMP transfer inside a real double support
polygon. The swing then runs over the rest of the single support from the foot's frame at its
start to its landing frame on :class:`~pivot_ompl.wholebody.timeline.MinJerkSwing` (speed and
acceleration zero at lift-off and touch-down), not on PlaCo's swing trajectory, a cubic whose
acceleration jumps at lift-off (the knees' peak acceleration).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import MinJerkSwing

__all__ = ["SwingFoot"]


class _Swing:
    """One single support of a trajectory: its times, its swing foot and that foot's path."""

    __slots__ = ("traj", "t0", "t1", "delay", "T0", "path", "right")

    def __init__(self, traj: Any, t: float, settings: WalkSettings, delay: float) -> None:
        self.traj = traj
        self.t0, self.t1 = t0, t1 = traj.get_part_t_start(t), traj.get_part_t_end(t)
        self.delay = 0.0 if t1 - t0 <= 2 * delay else delay
        self.right = str(traj.support_side(t)) == "left"  # the swing foot
        get = traj.get_T_world_right if self.right else traj.get_T_world_left
        self.T0 = np.array(get(t0))
        self.path = MinJerkSwing(self.T0, np.array(get(t1)), settings.foot_height)


class SwingFoot:
    """Sets the swing foot's task target of each tick of a walk (see the module docstring).

    Args:
        settings: the walk's timing (single support, LIPM samples, tick) and foot height.
    """

    settings: WalkSettings
    _current: _Swing | None

    def __init__(self, settings: WalkSettings) -> None:
        self.settings = settings
        self._current = None  # the single support of the last tick

    @property
    def lift_off_delay(self) -> float:
        """Time the swing foot stays down after a single support starts (s)."""
        s = self.settings
        return s.single_support_duration / s.single_support_timesteps + 2.5 * s.solver_dt

    def update(self, traj: Any, t: float, tasks: Any) -> bool:
        """Set the swing foot's target in PlaCo's ``WalkTasks`` at time ``t`` of ``traj``.

        Returns whether the swing foot is held (both feet in contact); ``False`` in a
        double support, where the pattern generator's targets stand.
        """
        cur = self._current
        if cur is None or cur.traj is not traj or not cur.t0 < t < cur.t1:
            if traj.support_is_both(t):
                return False
            cur = self._current = _Swing(traj, t, self.settings, self.lift_off_delay)
        task = tasks.right_foot_task if cur.right else tasks.left_foot_task
        t0, delay = cur.t0, cur.delay
        if t - t0 < delay:
            task.T_world_frame = cur.T0
            return True
        task.T_world_frame = cur.path.at((t - t0 - delay) / (cur.t1 - t0 - delay))
        return False

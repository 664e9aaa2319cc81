"""The swing foot's target over a single support: held down briefly, then a minimum-jerk swing.

PlaCo's walk pattern generator constrains the ZMP only at its LIPM samples: it reaches the new
support foot one sample after the double support ends. Holding the swing foot down meanwhile
(:attr:`SwingFoot.lift_off_delay`) keeps that ZMP transfer inside a real double support
polygon. The swing then runs over the rest of the single support from the foot's frame at its
start to its landing frame on :func:`~pivot_ompl.wholebody.timeline.min_jerk_swing` (speed and
acceleration zero at lift-off and touch-down), not on PlaCo's swing trajectory, a cubic whose
acceleration jumps at lift-off (the knees' peak acceleration).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import min_jerk_swing

__all__ = ["SwingFoot"]


class SwingFoot:
    """Sets the swing foot's task target of each tick of a walk (see the module docstring).

    Args:
        settings: the walk's timing (single support, LIPM samples, tick) and foot height.
    """

    settings: WalkSettings
    _current: tuple[Any, tuple[float, str], np.ndarray, np.ndarray] | None

    def __init__(self, settings: WalkSettings) -> None:
        self.settings = settings
        self._current = None  # (trajectory, (t0, side), lift-off frame, landing frame)

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
        if traj.support_is_both(t):
            return False
        t0, t1 = traj.get_part_t_start(t), traj.get_part_t_end(t)
        delay = self.lift_off_delay
        if t1 - t0 <= 2 * delay:
            delay = 0.0
        side = "right" if str(traj.support_side(t)) == "left" else "left"
        key = (t0, side)
        cur = self._current
        if cur is None or cur[0] is not traj or cur[1] != key:
            get = traj.get_T_world_right if side == "right" else traj.get_T_world_left
            cur = self._current = (traj, key, np.array(get(t0)), np.array(get(t1)))
        _, _, T0, T1 = cur
        task = tasks.right_foot_task if side == "right" else tasks.left_foot_task
        if t - t0 < delay:
            task.T_world_frame = T0
            return True
        s = (t - t0 - delay) / (t1 - t0 - delay)
        task.T_world_frame = min_jerk_swing(T0, T1, s, self.settings.foot_height)
        return False

"""Uniform box poses over the floor: the random source of every sampler of the object roadmap."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import Pose


class PoseSampler:
    """Uniform object poses in the floor bounds, yaw in ``[-yaw_range, yaw_range)``.

    Args:
        checker: the scene's bounds and the box's validity.
        rng: the planner's generator (the only source of randomness).
        yaw_range: half-width of the yaw interval (rad).
    """

    def __init__(self, checker: PivotChecker, rng: np.random.Generator, *,
                 yaw_range: float) -> None:
        """Sample over ``checker``'s floor."""
        b = checker.world.bounds
        self.checker = checker
        self.rng = rng
        self.yaw_range = yaw_range
        self._lo = (b[0], b[1])
        self._hi = (b[2], b[3])

    def uniform(self) -> Pose:
        """A uniform pose (x, y, then yaw drawn in that order)."""
        return (float(self.rng.uniform(self._lo[0], self._hi[0])),
                float(self.rng.uniform(self._lo[1], self._hi[1])),
                float(self.rng.uniform(-self.yaw_range, self.yaw_range)))

    def box_valid(self, should_stop: Callable[[], bool], *, attempts: int = 1000) -> Pose | None:
        """A uniform pose where the box alone is free; ``None`` when ``should_stop`` says so.

        After ``attempts`` invalid draws the next uniform pose is returned unchecked (the
        visibility test refuses it).
        """
        for k in range(attempts):
            if k % 50 == 49 and should_stop():
                return None
            q = self.uniform()
            if self.checker.box_valid(q):
                return q
        return self.uniform()

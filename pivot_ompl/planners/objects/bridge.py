"""The bridge test (Hsu et al. 2003) for narrow passages of the box, and the nodes it adds.

Two box poses at the same yaw, both in collision, lie on either side of a passage if the box
is free at their midpoint: that midpoint is a passage node. The box's axes (the directions
each grasp's car drives straight) at the bridge's random yaw give the directions in which
nodes are added along the passage on both sides. No direction of the world is used.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.objects.samplers import PoseSampler
from pivot_ompl.se2 import Pose


class BridgeTest:
    """Bridge tests over the floor.

    Args:
        checker: the box's validity.
        sampler: the uniform poses (and the generator of the second sample's offset).
        sigma: standard deviation (m) of the second sample's offset.
        steps: distances (m) of the nodes added from a passage node along each axis.
    """

    def __init__(self, checker: PivotChecker, sampler: PoseSampler, *, sigma: float,
                 steps: tuple[float, ...]) -> None:
        """Bridge tests with these settings."""
        self.checker = checker
        self.sampler = sampler
        self.sigma = sigma
        self.steps = steps

    def passage(self, should_stop: Callable[[], bool], *, attempts: int = 100) -> list[Pose]:
        """Up to ``attempts`` bridge tests; the first passage's nodes (``[]``: none found).

        The passage node first, then the free poses along the box's four axis directions
        (each direction until the box collides). Polls ``should_stop`` every 10 tests.
        """
        ck, rng = self.checker, self.sampler.rng
        w = ck.world
        for k in range(attempts):
            if k % 10 == 0 and should_stop():
                return []
            q1 = self.sampler.uniform()
            if not w.box_in_bounds(q1) or w.box_distance(q1) > 0:
                continue
            q2 = (q1[0] + float(rng.normal(0, self.sigma)),
                  q1[1] + float(rng.normal(0, self.sigma)), q1[2])
            if not w.box_in_bounds(q2) or w.box_distance(q2) > 0:
                continue
            mid = (0.5 * (q1[0] + q2[0]), 0.5 * (q1[1] + q2[1]), q1[2])
            if ck.box_valid(mid):
                return [mid, *self._along(mid)]
        return []

    def _along(self, mid: Pose) -> list[Pose]:
        out: list[Pose] = []
        for a in (mid[2] + k * 0.5 * math.pi for k in range(4)):
            for d in self.steps:
                q = (mid[0] + d * math.cos(a), mid[1] + d * math.sin(a), mid[2])
                if not self.checker.box_valid(q):
                    break
                out.append(q)
        return out

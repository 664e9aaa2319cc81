"""Diffusion (the regrasp paper, Section IV): grow the object roadmap towards random targets.

A target is the goal (``goal_bias``), a pose near a critical configuration (``critical_bias``)
or a uniform pose the box may reach; the nearest object node is extended towards it along the box's
Reeds-Shepp path by at most ``epsilon``, up to the last free pose: the diffusion creeps into
narrow passages instead of jumping over them.
"""

from __future__ import annotations

import math

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.objects.samplers import PoseSampler
from pivot_ompl.se2 import Pose, wrap_angle


class Diffusion:
    """Targets and extensions of the diffusion.

    Args:
        checker: the box's validity and the Reeds-Shepp curves.
        sampler: uniform poses and the generator.
        goal: the goal pose.
        epsilon: longest extension (m of Reeds-Shepp path).
        extend_step: spacing (m of Reeds-Shepp path) of the poses tested along an extension
            (:attr:`~pivot_ompl.planners.sampling_config.SamplingConfig.extend_step`).
        goal_bias, critical_bias: probabilities of the goal and of a critical
            configuration's neighbourhood as the target.
    """

    def __init__(self, checker: PivotChecker, sampler: PoseSampler, goal: Pose, *,
                 epsilon: float, goal_bias: float, critical_bias: float,
                 extend_step: float) -> None:
        """Diffusion with these settings."""
        self.checker = checker
        self.sampler = sampler
        self.goal = goal
        self.epsilon = epsilon
        self.extend_step = extend_step
        self.goal_bias = goal_bias
        self.critical_bias = critical_bias

    def target(self, critical: list[Pose]) -> Pose:
        """The next target (``critical``: the recorded critical configurations)."""
        rng = self.sampler.rng
        u = rng.uniform()
        if u < self.goal_bias:
            return self.goal
        if u < self.goal_bias + self.critical_bias and critical:
            c = critical[int(rng.integers(len(critical)))]
            return (c[0] + float(rng.normal(0, 0.3)), c[1] + float(rng.normal(0, 0.3)),
                    c[2] + float(rng.normal(0, 0.5)))
        return self.sampler.reachable()

    def extend(self, near: Pose, target: Pose) -> Pose:
        """The last free pose moving from ``near`` towards ``target`` (at most ``epsilon``).

        The box is symmetric: it steers to the target's half turn nearest to ``near``'s yaw.
        Returns ``near`` itself when the first step collides.
        """
        rs = self.checker.steering.paths
        if abs(wrap_angle(target[2] - near[2])) > 0.5 * math.pi:
            target = (target[0], target[1], wrap_angle(target[2] + math.pi))
        d = rs.distance(near, target)
        if d == 0.0:
            return near
        reach = min(1.0, self.epsilon / d)
        n = max(1, int(reach * d / self.extend_step))
        last = near
        for q in rs.sample(near, target, [reach * (k + 1) / n for k in range(n)]):
            if not self.checker.box_valid(q):
                break
            last = q
        return last

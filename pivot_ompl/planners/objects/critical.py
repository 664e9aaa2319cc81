"""Critical configurations (the regrasp paper, Section III): where holding the box starts to fail.

Along a valid edge of the object roadmap (the box alone pivots along it), the robot holding
the box at grasp ``k`` may collide at some poses and not at others. The last free pose before
a change (or the first after it) is a *critical configuration*: a candidate place to release
or take the box, added to the roadmap unless a recorded one lies within ``spacing``.
"""

from __future__ import annotations

from collections.abc import Callable

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.pivoting.steering import PivotSequence
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.objects.roadmap import Roadmap, canonical
from pivot_ompl.se2 import Pose


class CriticalConfigurations:
    """Finds and records critical configurations along box-only edges.

    Args:
        checker: state validity (the robot holding the box).
        roadmap: where critical configurations are added (kind ``"critical"``).
        grasps: the grasps whose validity changes are looked for.
        spacing: a configuration within this (m, pose metric) of a recorded one is skipped.

    Attributes:
        indices: roadmap indices of the recorded configurations, in order.
    """

    indices: list[int]

    def __init__(self, checker: PivotChecker, roadmap: Roadmap, *, grasps: tuple[int, ...],
                 spacing: float) -> None:
        """None recorded yet."""
        self.checker = checker
        self.evaluate = Evaluator(checker, CostModel())
        self.roadmap = roadmap
        self.grasps = grasps
        self.spacing = spacing
        self.indices = []

    def box_visible(self, a: Pose, b: Pose, should_stop: Callable[[], bool]) -> Status:
        """The object roadmap's visibility: whether the box alone pivots from ``a`` to ``b``.

        ``VALID``: it does, and the critical configurations along the edge are recorded;
        ``INVALID``: it does not; ``STOPPED``: the check was stopped first (no wall between
        them is known). The box's cheap test along the path runs first.
        """
        if not self.checker.path_free(a, b, 0, with_robot=False):
            return Status.INVALID
        e = self.evaluate.transfer(a, b, 0, with_robot=False, should_stop=should_stop)
        if e.valid and e.edge is not None:
            self.record(e.edge.sequence)
        return e.status

    def record(self, sequence: PivotSequence) -> None:
        """Record the critical configurations along a box-only pivot sequence."""
        ck, m, rm = self.checker, self.checker.model, self.roadmap
        poses = [canonical(m.object_from_car(r.car, 0)) for r in sequence.rotations]
        if len(poses) < 2:
            return
        for g in self.grasps:
            free = [ck.robot_valid(p, g) for p in poses]
            for i in range(1, len(poses)):
                if free[i] == free[i - 1]:
                    continue
                q = poses[i - 1] if free[i - 1] else poses[i]
                near = rm.nearest(q, 1, among=self.indices)
                if near and rm.distances(near, q)[0] < self.spacing:
                    continue
                self.indices.append(rm.add(q, "critical"))

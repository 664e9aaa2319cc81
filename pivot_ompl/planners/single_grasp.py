"""A bidirectional single-grasp connection (RRT-Connect on the pivoting car), tried first.

Where no regrasp is needed, the shortest way to a plan is to keep one grasp: a tree grows
from the start and one from the goal, both at grasp ``g``, each extension a pivot sequence
of at most ``step`` along the Reeds-Shepp path of the car (Kuffner and LaValle's
RRT-Connect: extend one tree towards a random pose, then pull the other tree to the new
node, swap). The budget is a number of motion checks (not wall-clock time), so a seed gives
the same result on any machine; every check goes through the shared checker's cache, after
the cheap test of :meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.path_free` (a refused
edge counts as a check).

Edges are checked in the direction the plan follows them (a pivot sequence depends on its
direction): start tree parent -> child, goal tree child -> parent. The path ends exactly at
the goal pose with the start's grasp.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator, Found, Status
from pivot_ompl.planners.objects.roadmap import YAW_WEIGHT
from pivot_ompl.se2 import Pose


@dataclass
class _Tree:
    """Object poses with parents; ``towards_root``: edges are followed child -> parent."""

    root: Pose
    towards_root: bool
    poses: list[Pose] = field(default_factory=list)
    parent: list[int] = field(default_factory=list)
    _arr: np.ndarray = field(default_factory=lambda: np.zeros((64, 3)))

    def __post_init__(self) -> None:
        self.add(self.root, -1)

    def add(self, pose: Pose, parent: int) -> int:
        i = len(self.poses)
        if i >= len(self._arr):
            self._arr = np.concatenate([self._arr, np.zeros_like(self._arr)])
        self._arr[i] = pose
        self.poses.append(pose)
        self.parent.append(parent)
        return i

    def nearest(self, pose: Pose) -> int:
        """The node nearest to ``pose`` (box centre distance plus weighted full yaw)."""
        a = self._arr[:len(self.poses)]
        dyaw = np.abs((a[:, 2] - pose[2] + math.pi) % (2.0 * math.pi) - math.pi)
        return int(np.argmin(np.hypot(a[:, 0] - pose[0], a[:, 1] - pose[1]) + YAW_WEIGHT * dyaw))

    def branch(self, i: int) -> list[Pose]:
        """Poses from node ``i`` up to the root."""
        out = []
        while i >= 0:
            out.append(self.poses[i])
            i = self.parent[i]
        return out


@dataclass
class SingleGraspConnect:
    """RRT-Connect at one grasp between two object poses.

    Args:
        checker: validity of states and transfer edges.
        start, goal: object poses.
        grasp: the grasp kept all the way.
        rng: random generator.
        step: longest extension (m of the car's Reeds-Shepp path).
    """

    checker: PivotChecker
    start: Pose
    goal: Pose
    grasp: int
    rng: np.random.Generator
    step: float = 1.5
    checks: int = field(default=0, init=False)
    _evaluate: Evaluator = field(init=False, repr=False)

    def __post_init__(self) -> None:
        b = self.checker.world.bounds
        self._lo, self._hi = (b[0], b[1]), (b[2], b[3])
        self._a = _Tree(self.start, towards_root=False)
        self._b = _Tree(self.goal, towards_root=True)
        self._evaluate = Evaluator(self.checker, CostModel())

    def _edge(self, tree: _Tree, near: Pose, new: Pose, should_stop: Callable[[], bool]
              ) -> Status:
        """Check the transfer between ``near`` (in ``tree``) and ``new`` as the plan will."""
        self.checks += 1
        a, b = (new, near) if tree.towards_root else (near, new)
        try:
            if not self.checker.path_free(a, b, self.grasp, should_stop=should_stop):
                return Status.INVALID
        except Interrupted:
            return Status.STOPPED
        return self._evaluate.transfer(a, b, self.grasp, should_stop=should_stop).status

    def _extend(self, tree: _Tree, target: Pose, should_stop: Callable[[], bool]
                ) -> tuple[str, int]:
        """One step of ``tree`` towards ``target``.

        ``("reached" | "advanced" | "trapped" | "stopped", i)``.
        """
        ck, g = self.checker, self.grasp
        m, rs = ck.model, ck.steering.paths
        i = tree.nearest(target)
        near = tree.poses[i]
        ca, cb = m.car_pose(near, g), m.car_pose(target, g)
        d = rs.distance(ca, cb)
        if d <= self.step:
            new, status = target, "reached"
        else:
            new = m.object_from_car(rs.interpolate(ca, cb, self.step / d), g)
            status = "advanced"
        if new == near or not ck.state_valid(new, g):
            return "trapped", i
        edge = self._edge(tree, near, new, should_stop)
        if edge is not Status.VALID:
            return ("stopped" if edge is Status.STOPPED else "trapped"), i
        return status, tree.add(new, i)

    def run(self, budget: int, should_stop: Callable[[], bool]) -> Found[list[Pose]]:
        """Grow until the trees meet or ``budget`` checks.

        ``VALID`` with the path's object poses; ``INVALID`` when the budget ran out first;
        ``STOPPED``. Calling it again continues with the same trees.
        """
        a, b = self._a, self._b
        if self.checks == 0:  # direct
            direct = self._edge(a, self.start, self.goal, should_stop)
            if direct is not Status.INVALID:
                return Found(direct, [self.start, self.goal] if direct is Status.VALID
                             else None)
        while self.checks < budget:
            if should_stop():
                return Found(Status.STOPPED)
            q = (float(self.rng.uniform(self._lo[0], self._hi[0])),
                 float(self.rng.uniform(self._lo[1], self._hi[1])),
                 float(self.rng.uniform(-math.pi, math.pi)))
            status, i = self._extend(a, q, should_stop)
            if status == "stopped":
                return Found(Status.STOPPED)
            if status != "trapped":
                new = a.poses[i]
                while self.checks < budget and not should_stop():  # connect b to the new node
                    status_b, j = self._extend(b, new, should_stop)
                    if status_b == "reached":
                        return Found(Status.VALID, self._path(a, i, b, j))
                    if status_b == "stopped":
                        return Found(Status.STOPPED)
                    if status_b == "trapped":
                        break
            a, b = b, a
        return Found(Status.INVALID)

    def _path(self, a: _Tree, i: int, b: _Tree, j: int) -> list[Pose]:
        """The start-to-goal poses when node ``i`` of ``a`` and ``j`` of ``b`` coincide."""
        if a.towards_root:
            a, i, b, j = b, j, a, i
        first = a.branch(i)[::-1]  # start .. meeting node
        second = b.branch(j)[1:]  # after the meeting node .. goal
        return first + second


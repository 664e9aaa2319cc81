"""OMPL ``MotionValidator``: the pivot sequence of a Reeds-Shepp edge, or a regrasp walk.

* Same grasp: the edge is the Reeds-Shepp path of the grasp's car between the two object
  poses, converted to pivot rotations; each rotation's swept box and robot are certified
  collision-free (:mod:`pivot_ompl.validity.certify`, tolerance 2 mm) and inside the bounds.
* Different grasps at the same object pose (to 1e-9 m / rad): the robot's walk round the
  resting box from one grasp pose to the other must exist (:mod:`pivot_ompl.transit.planner`).
* Anything else (a grasp change while the box moves) is invalid.

OMPL's motion counters stay 0 for Python validators: see ``checker.counters``.
"""

from __future__ import annotations

from typing import Any

from ompl import base as ob

from pivot_ompl.base.state import read_state
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import pose_distance

#: Two object poses closer than this (m and rad) are the same pose for a grasp change.
SAME_POSE_TOL = 1e-9


class PivotMotionValidator(ob.MotionValidator):
    """Checks motions between compound states (see the module docstring).

    Args:
        si: the space information (not stored).
        checker: the shared validity core (caches converted edges and walks).
    """

    def __init__(self, si: ob.SpaceInformation, checker: PivotChecker) -> None:
        """Wrap ``checker``."""
        super().__init__(si)
        self.checker = checker

    def checkMotion(self, s1: Any, s2: Any) -> bool:  # noqa: N802 - OMPL's name
        """Whether the motion ``s1 -> s2`` is valid."""
        p1, g1 = read_state(s1)
        p2, g2 = read_state(s2)
        if g1 == g2:
            return self.checker.transfer(p1, p2, g1).valid
        dxy, dyaw = pose_distance(p1, p2)
        if dxy <= SAME_POSE_TOL and dyaw <= SAME_POSE_TOL:
            return self.checker.transit(p1, g1, g2).valid
        self.checker.counters.invalid += 1
        return False

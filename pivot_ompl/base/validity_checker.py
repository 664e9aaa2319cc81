"""OMPL ``StateValidityChecker``: box and robot-at-grasp inside bounds and collision-free."""

from __future__ import annotations

from typing import Any

from ompl import base as ob

from pivot_ompl.base.state import read_state
from pivot_ompl.checking.pivot_checker import PivotChecker


class PivotValidityChecker(ob.StateValidityChecker):
    """Valid iff the box and the robot at the state's grasp are inside the bounds and free.

    Args:
        si: the space information (not stored: a Python object holding its space information
            makes a reference cycle through C++ that is never collected).
        checker: the shared validity core.
    """

    def __init__(self, si: ob.SpaceInformation, checker: PivotChecker) -> None:
        """Wrap ``checker``."""
        super().__init__(si)
        self.checker = checker

    def isValid(self, state: Any) -> bool:  # noqa: N802 - OMPL's name
        """Box and robot inside bounds and collision-free."""
        pose, grasp = read_state(state)
        return self.checker.state_valid(pose, grasp)

    def clearance(self, state: Any) -> float:
        """Smallest distance (m) of box or robot to obstacles or the bounds' sides."""
        pose, grasp = read_state(state)
        return self.checker.clearance(pose, grasp)

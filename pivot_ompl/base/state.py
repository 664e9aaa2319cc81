"""Reading and writing the compound state ``(object pose, grasp)``.

The state space is that of :mod:`pivot_ompl.base.space`.
"""

from __future__ import annotations

from typing import Any

from pivot_ompl.se2 import Pose


def read_state(state: Any) -> tuple[Pose, int]:
    """``(object pose, grasp)`` of a compound state."""
    se2 = state[0]
    return (se2.getX(), se2.getY(), se2.getYaw()), int(state[1].value)


def write_state(state: Any, pose: Pose, grasp: int) -> None:
    """Set a compound state to ``(pose, grasp)``."""
    state[0].setXY(pose[0], pose[1])
    state[0].setYaw(pose[2])
    state[1].value = int(grasp)

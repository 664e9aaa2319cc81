"""The phases of a ``pivot-plan/1`` plan: transfers (pivot rotations) and transits (walks).

The records :class:`~pivot_ompl.planfile.plan.Plan` holds (:mod:`pivot_ompl.planfile` says how
they are written); each checks its fields when built.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pivot_ompl.argcheck import guard as _guard
from pivot_ompl.argcheck import guard_all as _guard_all
from pivot_ompl.se2 import Pose

__all__ = ["Phase", "TransferPhase", "TransferStep", "TransitPhase"]


@dataclass(frozen=True)
class TransferStep:
    """One pivot rotation of a transfer phase (poses after the rotation)."""

    pivot: tuple[float, float]
    angle: float
    object: Pose
    robot: Pose

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a field that is not finite numbers."""
        _guard("TransferStep", pivot=(self.pivot, 2), angle=(self.angle, None),
               object=(self.object, 3), robot=(self.robot, 3))


@dataclass(frozen=True)
class TransferPhase:
    """The robot holds the box at ``grasp`` and pivots it through ``steps``.

    Attributes:
        grasp: grasp index (0..3).
        robot_start: robot pose at the phase start.
        steps: the rotations.
        object_start: object pose at the phase start (not written: the previous phase's end).
        rs_path: optional car poses along the Reeds-Shepp path(s), for plotting.
    """

    grasp: int
    robot_start: Pose
    steps: tuple[TransferStep, ...]
    object_start: Pose
    rs_path: tuple[Pose, ...] = ()

    type = "transfer"

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a wrong field."""
        _guard("TransferPhase", grasp=(self.grasp, -1), robot_start=(self.robot_start, 3),
               object_start=(self.object_start, 3))
        _guard_all("TransferPhase", "steps", self.steps, TransferStep)
        _guard_all("TransferPhase", "rs_path", self.rs_path)

    @property
    def object_end(self) -> Pose:
        """Object pose at the end of the phase."""
        return self.steps[-1].object if self.steps else self.object_start

    @property
    def robot_end(self) -> Pose:
        """Robot pose at the end of the phase."""
        return self.steps[-1].robot if self.steps else self.robot_start


@dataclass(frozen=True)
class TransitPhase:
    """The robot walks alone from grasp ``from_grasp`` to ``to_grasp`` of the resting box."""

    from_grasp: int
    to_grasp: int
    robot_path: tuple[Pose, ...]
    object_pose: Pose

    type = "transit"

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a wrong field."""
        _guard("TransitPhase", from_grasp=(self.from_grasp, -1), to_grasp=(self.to_grasp, -1),
               object_pose=(self.object_pose, 3))
        _guard_all("TransitPhase", "robot_path", self.robot_path)

    @property
    def length(self) -> float:
        """Walking distance of the robot's centre (m)."""
        p = self.robot_path
        return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(p, p[1:], strict=False))


Phase = TransferPhase | TransitPhase

"""pivot_ompl: pivoting manipulation and regrasp planning for a humanoid robot on OMPL.

Public API (see README): :func:`load_scene`, :func:`plan`, :func:`make_space_information`,
:func:`make_setup`, :class:`PivotSteering`, the plan file dataclasses and the
:class:`PivotError` exception family.
"""

from __future__ import annotations

from .errors import (
    InputError,
    PivotError,
    PlanFileError,
    PlanningError,
    SceneError,
    SteeringError,
    UnreachableError,
    WholeBodyError,
)
from .grasp import BoxGraspModel
from .planfile import Plan, TransferPhase, TransferStep, TransitPhase, load_plan
from .scene import Scene, load_scene
from .steering import PivotSequence, PivotSteering

__all__ = [
    "BoxGraspModel", "InputError", "PivotError", "PivotSequence", "PivotSteering", "Plan",
    "PlanFileError", "PlanningError", "Scene", "SceneError", "SteeringError", "TransferPhase",
    "TransferStep", "TransitPhase", "UnreachableError", "WholeBodyError", "load_plan",
    "load_scene",
]
__version__ = "0.1.0"

"""pivot_ompl: pivoting manipulation and regrasp planning for a humanoid robot on OMPL.

The public API (see docs/python-api.md): :func:`load_scene` and :func:`load_plan` (the file
contracts), :func:`scene_from_map` and :func:`import_map` (a ROS map_server map as a scene,
docs/maps.md), :func:`plan` (plan a scene, :class:`PlanResult`), :func:`make_setup` (the OMPL
problem object, :class:`PivotProblem`), :class:`PivotSteering` (Reeds-Shepp paths to pivot
rotations), :class:`BoxGraspModel` (the grasp conventions), the plan dataclasses and the
:class:`PivotError` exception family; :func:`simulate` (physics in the loop, the ``physics``
extra: :class:`SimulationReport`). Every name but the exceptions is imported on first use
(OMPL on first use of :func:`plan`, :func:`make_setup` or :class:`PivotSteering`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pivot_ompl.errors import (
    InputError,
    MapError,
    PivotError,
    PlanFileError,
    PlanningError,
    SceneError,
    SteeringError,
    UnreachableError,
    WholeBodyError,
)

if TYPE_CHECKING:
    from pivot_ompl.api import PlanResult, plan
    from pivot_ompl.base.problem import PivotProblem, make_setup
    from pivot_ompl.grasp import BoxGraspModel
    from pivot_ompl.maps import MapCleaning, MapImport, import_map, scene_from_map
    from pivot_ompl.physics.report import SimulationReport
    from pivot_ompl.physics.simulate import simulate
    from pivot_ompl.pivoting.steering import PivotSequence, PivotSteering
    from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase, load_plan
    from pivot_ompl.scene import Scene, load_scene

#: Name -> module of the names imported on first use: importing the package (the command
#: line's first step) costs almost nothing and is never interrupted half-way by a Ctrl-C.
_LAZY = {"BoxGraspModel": "pivot_ompl.grasp", "Plan": "pivot_ompl.planfile",
         "TransferPhase": "pivot_ompl.planfile", "TransferStep": "pivot_ompl.planfile",
         "TransitPhase": "pivot_ompl.planfile", "load_plan": "pivot_ompl.planfile",
         "Scene": "pivot_ompl.scene", "load_scene": "pivot_ompl.scene",
         "MapCleaning": "pivot_ompl.maps", "MapImport": "pivot_ompl.maps",
         "import_map": "pivot_ompl.maps", "scene_from_map": "pivot_ompl.maps",
         "plan": "pivot_ompl.api", "PlanResult": "pivot_ompl.api",
         "make_setup": "pivot_ompl.base.problem", "PivotProblem": "pivot_ompl.base.problem",
         "PivotSteering": "pivot_ompl.pivoting.steering",
         "PivotSequence": "pivot_ompl.pivoting.steering",
         "simulate": "pivot_ompl.physics.simulate",
         "SimulationReport": "pivot_ompl.physics.report"}


def __getattr__(name: str) -> Any:
    """Import the public names on first use (those of the API and steering need OMPL)."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'pivot_ompl' has no attribute {name!r}")


def __dir__() -> list[str]:
    """The module's names with the lazy ones (``dir()`` and tab completion list them)."""
    return sorted({*globals(), *_LAZY})


__all__ = [
    "BoxGraspModel", "InputError", "MapCleaning", "MapError", "MapImport", "PivotError",
    "PivotProblem", "PivotSequence", "PivotSteering", "Plan", "PlanFileError", "PlanResult",
    "PlanningError", "Scene", "SceneError", "SimulationReport", "SteeringError",
    "TransferPhase", "TransferStep", "TransitPhase", "UnreachableError", "WholeBodyError",
    "import_map", "load_plan", "load_scene", "make_setup", "plan", "scene_from_map", "simulate",
]
__version__ = "0.4.0.dev0"

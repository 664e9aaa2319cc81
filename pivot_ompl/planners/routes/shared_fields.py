"""The assembly fields of recent scenes, shared by the lattices of their plans.

An :class:`~pivot_ompl.validity.assembly_field.AssemblyField` depends only on the scene's
geometry (the model, the obstacles, the bounds and the kept clearance of the checker's
world) and the grid spacing, and fills its grids as they are asked for. Every plan builds a
checker and a lattice of its own; :func:`assembly_field` hands a later plan of the same
scene (same :func:`~pivot_ompl.scene.scene_digest`) the field an earlier one filled, so the
grids are rasterised once per scene, not once per plan. The grids are the same either way:
plans do not change.
"""

from __future__ import annotations

from pivot_ompl.cache import BoundedCache
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import scene_digest
from pivot_ompl.validity.assembly_field import AssemblyField

__all__ = ["FIELD_SCENES", "assembly_field"]

#: Fields kept (least recently used dropped first): a few scenes at one or two spacings.
FIELD_SCENES = 8

_fields: BoundedCache[tuple[str, float, float], AssemblyField] = BoundedCache(FIELD_SCENES)


def assembly_field(checker: PivotChecker, resolution: float) -> AssemblyField:
    """The assembly field of ``checker``'s scene at ``resolution`` (m), shared by scene."""
    key = (scene_digest(checker.scene), float(resolution), float(checker.world.clearance))
    return _fields.get_or_compute(
        key, lambda: AssemblyField(checker.model, checker.world, resolution))

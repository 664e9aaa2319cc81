"""The assembly fields of recent scenes, shared by the lattices of their plans.

An :class:`~pivot_ompl.validity.assembly_field.AssemblyField` depends only on the scene's
geometry (the model, the obstacles, the bounds and the kept clearance of the checker's
world) and the grid spacing, and fills its grids as they are asked for. Every plan builds a
checker and a lattice of its own; :func:`assembly_field` hands a later plan of the same
scene (same :func:`~pivot_ompl.scene.scene_digest`) the field an earlier one filled (kept by
:func:`~pivot_ompl.scene.shared.scene_shared`, the one memo of what plans of a scene
share), so the grids are rasterised once per scene, not once per plan. The grids are the
same either way: plans do not change. The lattice's connected components
(:func:`shared_components`) are kept with their field, per grasp parity and region, as
read-only arrays, and so are its routes (:func:`shared_routes`), per region and the
lattice's prices and search limit.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.routes.lattice_frame import LatticeFrame
from pivot_ompl.scene.shared import scene_shared
from pivot_ompl.validity.assembly_field import AssemblyField

__all__ = ["ROUTES_KEPT", "assembly_field", "shared_components", "shared_routes"]

Labels = tuple[np.ndarray, np.ndarray]
#: each field's lattice components by ``(parity, the region's WKB or None)``
_labels: weakref.WeakKeyDictionary[AssemblyField, dict[tuple[int, bytes | None], Labels]] = \
    weakref.WeakKeyDictionary()
#: Most routes kept per field, region and prices (then forgotten all at once).
ROUTES_KEPT = 4096
#: each field's lattice routes by ``(region's WKB or None, prices and limit)``
_routes: weakref.WeakKeyDictionary[AssemblyField, dict[tuple, dict]] = \
    weakref.WeakKeyDictionary()


def assembly_field(checker: PivotChecker, resolution: float, *,
                   region: BaseGeometry | None = None,
                   area: Callable[[AssemblyField], np.ndarray] | None = None,
                   frame: LatticeFrame | None = None) -> AssemblyField:
    """The assembly field of ``checker``'s scene at ``resolution`` (m), shared by scene.

    With a ``region``, the field restricted to ``area(field)`` (the grid positions an
    assembly in the region may take, :meth:`AssemblyField.restrict`), shared by scene and
    region. In ``frame`` where given (:mod:`.lattice_frame`: the field of the turned floor),
    shared by frame too.
    """
    world = checker.world if frame is None or frame.world is None else frame.world
    what = ("assembly field", float(resolution), float(checker.world.clearance),
            None if region is None else shapely.to_wkb(region),
            0.0 if frame is None else frame.yaw)

    def made() -> AssemblyField:
        field = AssemblyField(checker.model, world, resolution)
        if region is not None and area is not None:
            field.restrict(area(field))
        return field

    field = scene_shared(checker.scene, what, made)
    assert field is not None
    return field


def shared_components(field: AssemblyField, parity: int, region: BaseGeometry | None,
                      compute: Callable[[], Labels]) -> Labels:
    """The lattice components over ``field`` at ``parity`` within ``region``, computed once.

    ``compute`` makes them where no lattice over the same field and region has (its
    arrays are then made read-only: every lattice reads the same ones).
    """
    per = _labels.setdefault(field, {})
    key = (parity, None if region is None else shapely.to_wkb(region))
    hit = per.get(key)
    if hit is None:
        hit = compute()
        for a in hit:
            a.setflags(write=False)
        per[key] = hit
    return hit


def shared_routes(field: AssemblyField, region: BaseGeometry | None,
                  settings: tuple[float, ...]) -> dict:
    """The routes dictionary shared by the lattices over ``field`` within ``region``.

    ``settings``: whatever else a route depends on (the push and spin prices, the search's
    limit), so that lattices priced otherwise keep their own. The caller stores its routes
    in it (and empties it beyond :data:`ROUTES_KEPT`).
    """
    per = _routes.setdefault(field, {})
    key = (None if region is None else shapely.to_wkb(region), settings)
    return per.setdefault(key, {})

"""The pinocchio model of a motion's URDF: kinematics and collision geometry, built once."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

from pivot_ompl.humanoids import urdf_file

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class UrdfModel:
    """A free-flyer pinocchio model and its collision geometry model.

    Attributes:
        model: ``pinocchio.Model`` (free-flyer root).
        geom: ``pinocchio.GeometryModel`` of the URDF's collision geometries.
        urdf: the URDF's path as named in the motion file.
    """

    model: Any
    geom: Any
    urdf: str


def load_urdf_model(urdf: str, *, field: str = "motion.urdf") -> UrdfModel:
    """Build the pinocchio model and collision geometry of ``urdf``.

    ``urdf`` is a humanoid profile's URDF name, or a shipped file's data path.

    Raises:
        InputError: the file is not found (``field`` names where it was given).
    """
    import pinocchio as pin

    path = urdf_file(urdf, field=field)
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    geom = pin.buildGeomFromUrdf(model, str(path), pin.GeometryType.COLLISION)
    log.debug("built the pinocchio model of %s: nq %d, %d collision geometries", urdf,
              model.nq, len(geom.geometryObjects))
    return UrdfModel(model, geom, urdf)

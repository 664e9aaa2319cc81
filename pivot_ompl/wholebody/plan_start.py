"""Where a plan's whole-body motion starts: the robot observed by a replan, if any."""

from __future__ import annotations

import math

from pivot_ompl.errors import InputError
from pivot_ompl.planfile import Plan
from pivot_ompl.se2 import Pose


def observed_robot(plan: Plan) -> Pose | None:
    """Where the robot was observed standing (a replanned plan's ``observed_robot``), or ``None``.

    Raises:
        InputError: the field is not three finite numbers.
    """
    raw = plan.extra.get("observed_robot")
    if raw is None:
        return None
    if not (isinstance(raw, list) and len(raw) == 3
            and all(isinstance(v, int | float) and not isinstance(v, bool)
                    and math.isfinite(v) for v in raw)):
        raise InputError("observed_robot", raw, "must be [x, y, yaw], three finite numbers")
    return (float(raw[0]), float(raw[1]), float(raw[2]))

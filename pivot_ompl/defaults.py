"""Default values of the paper's set-up (controllability paper, Section V)."""

from __future__ import annotations

import math

#: The paper's box: width (local x), depth (local y), height (m).
OBJECT_SIZE = (0.8, 0.6, 1.3)
#: Reeds-Shepp turning radius (m).
TURNING_RADIUS = 2.0
#: Bound on each pivot rotation (rad): pi/8 = 22.5 deg.
ALPHA_MAX = math.pi / 8
#: HRP-2's bounding box on the floor: depth along its heading, width (m).
ROBOT_FOOTPRINT = (0.40, 0.70)
#: Gap between the held face and the robot's front (m).
STANDOFF = 0.25
#: Height of the robot's bounding volume (m).
ROBOT_HEIGHT = 1.54

"""Scene files (``scenes/*.yaml``): the floor area, the box, the robot, obstacles, start, goal.

Format (a contract for users and outside tools)::

    name: two-rooms
    bounds: [xmin, ymin, xmax, ymax]          # floor area every footprint stays in (m)
    object: {size: [w, d, h]}                  # box, w along its local x
    robot: {model: hrp2, footprint: [depth, width], standoff: s,
            walk: {step_forward: 0.15, step_backward: 0.08, step_lateral: 0.06,
                   step_turn: 0.25, side_cost: 2.5, back_cost: 1.875, turn_cost: 0.6}}
    pivot: {alpha_max: 0.39269908169872414, turning_radius: 2.0}   # optional
    obstacles:                                 # static vertical prisms standing on the floor
      - {type: box, center: [x, y], size: [sx, sy], yaw: 0.0, height: 1.0}
      - {type: cylinder, center: [x, y], radius: r, height: 1.0}
      - {type: polygon, points: [[x, y], ...], height: 1.0}
    start: [x, y, yaw]                         # object poses
    goal: [x, y, yaw]

Lengths in metres, angles in radians. Every error names the file, the field and the value.

``robot.model`` names a humanoid profile (``pivot-ompl robots``: ``hrp2``, the default, or
``talos``); its footprint, standoff, height and walk model are the defaults of the other
``robot`` fields. A footprint given is kept where it is larger than the model's own (more
cautious) and grown to it where smaller; ``walk`` fields given replace the model's.

Limits (a scene outside them has no sensible plan; it is refused with the field named):
coordinates within +-:data:`MAX_COORD` m, the floor area at most :data:`MAX_EXTENT` m on a side,
box and footprint sides within [:data:`MIN_SIZE`, :data:`MAX_SIZE`] m, ``alpha_max`` within
[:data:`MIN_ALPHA_MAX`, pi/2] rad, ``turning_radius`` within [:data:`MIN_TURNING_RADIUS`,
:data:`MAX_TURNING_RADIUS`] m, at most :data:`MAX_OBSTACLES` obstacles and
:data:`MAX_POLYGON_POINTS` points per polygon; a polygon must be simple (no self-intersection).
Yaw angles must lie within [-2 pi, 2 pi] (larger magnitudes are refused: degrees given by
mistake); those outside [-pi, pi] are wrapped into [-pi, pi) on load.

Modules: :mod:`~pivot_ompl.scene.model` (the data and the limits),
:mod:`~pivot_ompl.scene.reader` (documents validated), :mod:`~pivot_ompl.scene.files`
(files and shipped scenes).
"""

from pivot_ompl.scene.files import load_scene, scene_digest, scene_path  # noqa: I001 (after reader)
from pivot_ompl.scene.model import (
    DEFAULT_ALPHA_MAX,
    DEFAULT_OBJECT_SIZE,
    DEFAULT_TURNING_RADIUS,
    MAX_COORD,
    MAX_EXTENT,
    MAX_OBSTACLES,
    MAX_POLYGON_POINTS,
    MAX_SIZE,
    MAX_TURNING_RADIUS,
    MAX_YAW,
    MIN_ALPHA_MAX,
    MIN_SIZE,
    MIN_TURNING_RADIUS,
    BoxObstacle,
    CylinderObstacle,
    Obstacle,
    PolygonObstacle,
    Scene,
    WalkParameters,
    default_scene,
)
from pivot_ompl.scene.reader import ROBOT_MODELS, check_pose, obstacles_from_list, scene_from_dict

__all__ = [
    "DEFAULT_ALPHA_MAX", "DEFAULT_OBJECT_SIZE", "DEFAULT_TURNING_RADIUS", "MAX_COORD",
    "MAX_EXTENT", "MAX_OBSTACLES", "MAX_POLYGON_POINTS", "MAX_SIZE", "MAX_TURNING_RADIUS",
    "MAX_YAW", "MIN_ALPHA_MAX", "MIN_SIZE", "MIN_TURNING_RADIUS", "ROBOT_MODELS", "BoxObstacle",
    "CylinderObstacle", "Obstacle", "PolygonObstacle", "Scene", "WalkParameters", "check_pose",
    "default_scene", "load_scene", "obstacles_from_list", "scene_digest", "scene_from_dict",
    "scene_path",
]

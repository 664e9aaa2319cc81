"""The scene's data: its obstacles, walk model and the scene itself, with the file's limits.

See :mod:`pivot_ompl.scene` for the file format these are read from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, HumanoidProfile
from pivot_ompl.se2 import Pose

#: The controllability paper's set-up (Section V): box width (local x), depth, height (m).
DEFAULT_OBJECT_SIZE = (0.8, 0.6, 1.3)
#: Reeds-Shepp turning radius (m).
DEFAULT_TURNING_RADIUS = 2.0
#: Bound on each pivot rotation (rad): pi/8 = 22.5 deg.
DEFAULT_ALPHA_MAX = math.pi / 8

#: Largest coordinate magnitude (m): far below where doubles lose the 1e-6 m pose tolerance.
MAX_COORD = 1.0e4
#: Largest side of the floor area (m): the regrasping grid (0.1 m) stays within 4 M cells.
MAX_EXTENT = 200.0
#: Smallest and largest side of the box and of the robot's footprint (m).
MIN_SIZE, MAX_SIZE = 0.05, 20.0
#: Smallest bound on a pivot rotation (rad): below it a metre takes thousands of rotations.
MIN_ALPHA_MAX = 0.01
#: Range of the Reeds-Shepp turning radius (m).
MIN_TURNING_RADIUS, MAX_TURNING_RADIUS = 0.1, 1000.0
#: Most obstacles, and most points of one polygon.
MAX_OBSTACLES, MAX_POLYGON_POINTS = 100_000, 10_000
#: Largest accepted yaw magnitude (rad) before wrapping (2 pi, with round-off).
MAX_YAW = 2.0 * math.pi + 1e-9


@dataclass(frozen=True)
class BoxObstacle:
    """A box prism: centre (m), size (m) along its local axes, yaw (rad), height (m)."""

    center: tuple[float, float]
    size: tuple[float, float]
    yaw: float
    height: float
    type = "box"


@dataclass(frozen=True)
class CylinderObstacle:
    """A vertical cylinder: centre (m), radius (m), height (m)."""

    center: tuple[float, float]
    radius: float
    height: float
    type = "cylinder"


@dataclass(frozen=True)
class PolygonObstacle:
    """A prism over a simple polygon (possibly non-convex), vertices in order (m)."""

    points: tuple[tuple[float, float], ...]
    height: float
    type = "polygon"


Obstacle = BoxObstacle | CylinderObstacle | PolygonObstacle


@dataclass(frozen=True)
class WalkParameters:
    """How the robot walks alone (the scene's ``robot.walk`` block; HRP-2 defaults).

    A walk's cost is in metres of forward walking: it is proportional to the number of steps
    the walk takes, so by default the costs follow from the step limits.

    Attributes:
        step_forward, step_backward, step_lateral: longest step of the sole midpoint
            forward, backward and sideways (m).
        step_turn: largest yaw change of one step (rad).
        side_cost: cost of one metre walked sideways, per metre walked forward (>= 1).
        back_cost: same for walking backward (>= 1).
        turn_cost: cost of turning, metres of forward walking per radian (>= 0).
    """

    step_forward: float = PROFILES[DEFAULT_MODEL].step_forward
    step_backward: float = PROFILES[DEFAULT_MODEL].step_backward
    step_lateral: float = PROFILES[DEFAULT_MODEL].step_lateral
    step_turn: float = PROFILES[DEFAULT_MODEL].step_turn
    side_cost: float = step_forward / step_lateral
    back_cost: float = step_forward / step_backward
    turn_cost: float = step_forward / step_turn

    @classmethod
    def of_profile(cls, robot: HumanoidProfile, **given: float) -> WalkParameters:
        """``robot``'s step limits with ``given`` fields; costs not given follow the limits."""
        s = {"step_forward": robot.step_forward, "step_backward": robot.step_backward,
             "step_lateral": robot.step_lateral, "step_turn": robot.step_turn, **given}
        f = s["step_forward"]
        costs = {"side_cost": f / s["step_lateral"], "back_cost": f / s["step_backward"],
                 "turn_cost": f / s["step_turn"]}
        return cls(**{**costs, **s})

    @property
    def turning_radius(self) -> float:
        """Smallest radius of a forward walk turning at every step (m)."""
        return self.step_forward / self.step_turn


@dataclass(frozen=True)
class Scene:
    """A planning problem.

    Attributes:
        name: scene name.
        bounds: ``(xmin, ymin, xmax, ymax)`` of the floor area (m).
        model: box and robot geometry (:class:`~pivot_ompl.grasp.BoxGraspModel`).
        robot_model: the humanoid's profile name (:mod:`pivot_ompl.humanoids`).
        walk: how the robot walks alone (step limits, walking costs).
        alpha_max: bound on each pivot rotation (rad).
        turning_radius: Reeds-Shepp turning radius (m).
        obstacles: static prisms.
        start, goal: object poses.
        source: the file it was read from, or ``""``.
    """

    name: str
    bounds: tuple[float, float, float, float]
    model: BoxGraspModel
    start: Pose
    goal: Pose
    obstacles: tuple[Obstacle, ...] = ()
    alpha_max: float = DEFAULT_ALPHA_MAX
    turning_radius: float = DEFAULT_TURNING_RADIUS
    robot_model: str = DEFAULT_MODEL
    source: str = field(default="", compare=False)
    walk: WalkParameters = field(default_factory=WalkParameters)


def default_scene(*, start: Pose = (0.0, 0.0, 0.0), goal: Pose = (0.0, 0.0, 0.0),
                  margin: float = 5.0) -> Scene:
    """The paper's obstacle-free set-up around ``start`` and ``goal`` (bounds with a margin)."""
    xs = (start[0], goal[0])
    ys = (start[1], goal[1])
    model = BoxGraspModel(DEFAULT_OBJECT_SIZE)
    return Scene("free", (min(xs) - margin, min(ys) - margin, max(xs) + margin,
                          max(ys) + margin), model, start, goal)

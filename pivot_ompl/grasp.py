"""Box, robot and grasp conventions (the contract every other module and outside tool uses).

Object pose
    ``(x, y, yaw)``: the centre of the box's footprint on the floor and the yaw of the box's
    local x axis, which runs along ``size[0]``.

Grasp ``k`` in {0, 1, 2, 3}
    The robot faces the local direction ``yaw + k*pi/2`` of the box and stands on the opposite
    side: its centre lies at distance ``half_k + standoff + depth/2`` from the box centre,
    against that direction, with its heading pointing at the box centre. ``half_k`` is
    ``size[0]/2`` for even ``k`` and ``size[1]/2`` for odd ``k``.

Supporting edge
    We pivot on the footprint edge **nearest to the robot** (under the held face). Reasons: the
    box is inclined towards the robot, so its weight leans into the hands and the robot can
    never push it over away from itself; the pivot corners lie right in front of the feet, where
    the arms have the most reach to hold the box down on them; and the robot, rigidly attached,
    rotates about points close to its own body, so its swept area per rotation is smallest.
    Its length is ``2l``: ``l = size[1]/2`` for even ``k`` (the edge runs along local y) and
    ``l = size[0]/2`` for odd ``k``. Its two ends are the only pivots while the grasp holds:
    ``A`` is the left end and ``B`` the right end as seen by the robot.

Reeds-Shepp car of a grasp
    The car is the supporting edge's centre, heading along the edge's normal pointing away
    from the robot (the robot's facing direction):
    ``car = (x - half_k cos h, y - half_k sin h, h)`` with ``h = yaw + k*pi/2``.
    Driving the car forward moves the box away from the robot; reverse pulls it back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, profile_of
from pivot_ompl.se2 import Pose, place_points, rectangle_corners, wrap_angle

GRASPS: tuple[int, ...] = (0, 1, 2, 3)

#: How the box is held (shared by the planner's bodies and the whole-body generator):
#: inclination towards the robot about the supporting edge (rad),
HOLD_TILT = math.radians(5.0)
#: grip height above the floor in the untilted grasp frame (m), clipped to ``h - GRIP_TOP``,
GRIP_HEIGHT = 0.95
GRIP_TOP = 0.10
#: half distance between the two grip points (m), clipped to ``l - GRIP_EDGE``,
GRIP_SPACING = 0.25
GRIP_EDGE = 0.05
#: and the grip point's distance in front of the held face (m).
GRIP_OFFSET = 0.055

Polygon = tuple[tuple[float, float], ...]

#: What a wrong argument raises inside a method of :class:`BoxGraspModel` (turned into the
#: :class:`InputError` naming it: the methods are the planners' inner loop, so they check
#: their arguments only when the computation fails, at no cost otherwise).
_WRONG = (KeyError, TypeError, IndexError, ValueError, OverflowError)


def _length(x: object) -> bool:
    """Whether ``x`` is a finite real number (not a bool)."""
    return (not isinstance(x, bool) and isinstance(x, int | float)
            and math.isfinite(x))


@dataclass(frozen=True)
class BoxGraspModel:
    """Geometry of the box and of the robot's bounding box at each grasp.

    Attributes:
        object_size: box size ``(w, d, h)`` in m, ``w`` along the box's local x axis.
        robot_footprint: robot bounding box on the floor ``(depth, width)`` in m; depth is
            along the robot's heading.
        standoff: gap between the held face and the robot's front (m).
        robot_height: height of the robot's bounding volume (m).
        robot_model: the humanoid's profile name (:mod:`pivot_ompl.humanoids`): its
            walking envelope and shoulders shape the planner's bodies (left out of the
            ``repr``, which digests of HRP-2's scenes were made from:
            :func:`~pivot_ompl.scene.scene_digest` adds another model).
    """

    object_size: tuple[float, float, float]
    robot_footprint: tuple[float, float] = PROFILES[DEFAULT_MODEL].footprint
    standoff: float = PROFILES[DEFAULT_MODEL].standoff
    robot_height: float = PROFILES[DEFAULT_MODEL].height
    robot_model: str = field(default=DEFAULT_MODEL, repr=False)
    # per-grasp tables, each instance's own (set by __post_init__; not fields)
    _half: ClassVar[dict[int, float]]
    _ell: ClassVar[dict[int, float]]
    _offset: ClassVar[dict[int, float]]
    _quarter: ClassVar[dict[int, float]]

    def __post_init__(self) -> None:
        """Validate sizes (all strictly positive, standoff non-negative) and the model."""
        profile_of(self.robot_model, field="robot_model")
        for name, n in (("object_size", 3), ("robot_footprint", 2)):
            v = getattr(self, name)
            if isinstance(v, str | bytes) or not isinstance(v, tuple | list) or len(v) != n:
                raise InputError(name, v, f"must be {n} lengths in m")
            for i, x in enumerate(v):
                if not _length(x) or x <= 0:
                    raise InputError(f"{name}[{i}]", x, "must be a positive length in m")
        for name in ("standoff", "robot_height"):
            x = getattr(self, name)
            if not _length(x) or x < 0:
                raise InputError(name, x, "must be a non-negative length in m")
        # per grasp, computed as the methods did: a wrong grasp is a missing key
        half = {g: 0.5 * self.object_size[g % 2] for g in GRASPS}
        for name, table in (
                ("_half", half),
                ("_ell", {g: 0.5 * self.object_size[(g + 1) % 2] for g in GRASPS}),
                ("_offset", {g: half[g] + self.standoff + 0.5 * self.robot_footprint[0]
                             for g in GRASPS}),
                ("_quarter", {g: g * (0.5 * math.pi) for g in GRASPS})):
            object.__setattr__(self, name, table)

    def _refused(self, **args: object) -> InputError:
        """The :class:`InputError` naming the first wrong one of a method's ``args``.

        Wrong: a ``grasp`` not a grasp index, another argument not a pose of three finite
        numbers.
        """
        for name, value in args.items():
            if name == "grasp":
                try:
                    check_grasp(value)  # type: ignore[arg-type]
                except InputError as e:
                    return e
            elif not (isinstance(value, tuple | list) and len(value) == 3
                      and all(_length(x) for x in value)):
                return InputError(name, value, "must be a pose (x, y, yaw) of finite numbers")
        name, value = next(iter(args.items()))
        return InputError(name, value, "is not an argument of this method")

    # -- grasp geometry -------------------------------------------------------------------
    def half_extent(self, grasp: int) -> float:
        """Half of the box's extent along the robot's facing direction at ``grasp`` (m)."""
        try:
            return self._half[grasp]
        except (KeyError, TypeError) as e:
            raise self._refused(grasp=grasp) from e

    def edge_half_length(self, grasp: int) -> float:
        """Half-length ``l`` of the supporting edge at ``grasp`` (m)."""
        try:
            return self._ell[grasp]
        except (KeyError, TypeError) as e:
            raise self._refused(grasp=grasp) from e

    def robot_offset(self, grasp: int) -> float:
        """Distance from the box centre to the robot centre at ``grasp`` (m)."""
        try:
            return self._offset[grasp]
        except (KeyError, TypeError) as e:
            raise self._refused(grasp=grasp) from e

    def heading(self, obj: Pose, grasp: int) -> float:
        """The robot's (and the car's) heading at ``grasp`` for object pose ``obj`` (rad)."""
        try:
            return obj[2] + self._quarter[grasp]
        except _WRONG as e:
            raise self._refused(obj=obj, grasp=grasp) from e

    def robot_pose(self, obj: Pose, grasp: int) -> Pose:
        """``T_world_robot``: the robot's centre and heading for object pose ``obj``."""
        try:
            h = obj[2] + self._quarter[grasp]
            r = self._offset[grasp]
            return (obj[0] - r * math.cos(h), obj[1] - r * math.sin(h), h)
        except _WRONG as e:
            raise self._refused(obj=obj, grasp=grasp) from e

    def car_pose(self, obj: Pose, grasp: int) -> Pose:
        """The Reeds-Shepp car (supporting-edge centre, robot heading) for ``obj``."""
        try:
            h = obj[2] + self._quarter[grasp]
            r = self._half[grasp]
            return (obj[0] - r * math.cos(h), obj[1] - r * math.sin(h), h)
        except _WRONG as e:
            raise self._refused(obj=obj, grasp=grasp) from e

    def object_from_car(self, car: Pose, grasp: int) -> Pose:
        """Inverse of :meth:`car_pose`: the object pose whose car at ``grasp`` is ``car``."""
        try:
            r = self._half[grasp]
            h = car[2]
            return (car[0] + r * math.cos(h), car[1] + r * math.sin(h),
                    wrap_angle(h - self._quarter[grasp]))
        except _WRONG as e:
            raise self._refused(car=car, grasp=grasp) from e

    def robot_from_car(self, car: Pose, grasp: int) -> Pose:
        """The robot pose attached to ``car`` at ``grasp``."""
        r = self.standoff + 0.5 * self.robot_footprint[0]
        try:
            self._half[grasp]  # noqa: B018 - the grasp's check: a wrong one is a missing key
            return (car[0] - r * math.cos(car[2]), car[1] - r * math.sin(car[2]), car[2])
        except _WRONG as e:
            raise self._refused(car=car, grasp=grasp) from e

    def pivots(self, car: Pose, grasp: int) -> tuple[tuple[float, float], tuple[float, float]]:
        """World positions of the pivot corners ``(A, B)`` (left, right seen by the robot)."""
        try:
            ell = self._ell[grasp]
            nx, ny = -math.sin(car[2]), math.cos(car[2])
            return ((car[0] + ell * nx, car[1] + ell * ny),
                    (car[0] - ell * nx, car[1] - ell * ny))
        except _WRONG as e:
            raise self._refused(car=car, grasp=grasp) from e

    # -- footprints ----------------------------------------------------------------------
    def object_corners(self, obj: Pose) -> list[tuple[float, float]]:
        """The box footprint's four corners for object pose ``obj``."""
        try:
            return rectangle_corners(obj, self.object_size[0], self.object_size[1])
        except _WRONG as e:
            raise self._refused(obj=obj) from e

    def walking_extent(self) -> tuple[float, float, float]:
        """The walking body: its reach ``(ahead, behind, half_width)`` from the robot pose (m).

        The footprint, grown to the robot's measured walking envelope
        (:attr:`~pivot_ompl.humanoids.HumanoidProfile.walk_envelope`: the knees ahead, the
        chest behind, the shoulders' sway to the sides) where the envelope reaches further:
        the planner checks a
        walking robot as this rectangle x :attr:`robot_height`.
        """
        d, w = 0.5 * self.robot_footprint[0], 0.5 * self.robot_footprint[1]
        ahead, behind, side = profile_of(self.robot_model).walk_envelope
        return max(d, ahead), max(d, behind), max(w, side)

    def walking_outline(self) -> tuple[tuple[float, float], ...]:
        """The walking body's corners (CCW) in the robot frame (:meth:`walking_extent`)."""
        ahead, behind, hw = self.walking_extent()
        return ((-behind, -hw), (ahead, -hw), (ahead, hw), (-behind, hw))

    def robot_corners(self, robot: Pose) -> list[tuple[float, float]]:
        """The walking body's four corners on the floor for robot pose ``robot``."""
        try:
            return place_points(robot, self.walking_outline())
        except _WRONG as e:
            raise self._refused(robot=robot) from e

    def robot_radius(self) -> float:
        """Radius (m) of the disk the walking body sweeps turning in place about its pose."""
        ahead, behind, hw = self.walking_extent()
        return math.hypot(max(ahead, behind), hw)

    def robot_inradius(self) -> float:
        """Radius (m) of the largest disk round the robot pose inside the walking body."""
        return min(self.walking_extent())

    # -- the held assembly ----------------------------------------------------------------
    def grip_lateral(self, grasp: int) -> float:
        """Lateral offset (m) of each grip point from the held face's centre line."""
        return min(GRIP_SPACING, self.edge_half_length(grasp) - GRIP_EDGE)

    def held_polygons(self, grasp: int) -> tuple[Polygon, ...]:
        """What the holding robot occupies beyond its footprint, in the robot frame.

        Robot frame: origin at the robot's centre, x along its heading, y to its left (m).
        Two convex floor polygons (vertical prisms up to the robot's height):

        * the arms: the convex hull of both shoulders' floor envelopes (squares of half-side
          ``shoulder_envelope`` round the profile's shoulder joints, from the URDF) and both
          hands' envelopes (half-side ``hand_envelope``
          round the grip points, ``GRIP_OFFSET`` in front of the held face at lateral offset
          :meth:`grip_lateral`), up to the held face;
        * the inclined box's overhang: tilted by :data:`HOLD_TILT` towards the robot about
          its supporting edge, the box's top leans ``h sin(tilt)`` over the gap, across the
          whole face.
        """
        front = 0.5 * self.robot_footprint[0]
        face = front + self.standoff
        robot = profile_of(self.robot_model)
        sx, sy = robot.shoulder_xy
        a_s, a_h = robot.shoulder_envelope, robot.hand_envelope
        gx, gy = face - GRIP_OFFSET, self.grip_lateral(grasp)
        right = ((sx - a_s, -(sy + a_s)), (sx + a_s, -(sy + a_s)),
                 (gx - a_h, -(gy + a_h)), (face, -(gy + a_h)))
        arms = right + tuple((x, -y) for x, y in reversed(right))
        lean = self.object_size[2] * math.sin(HOLD_TILT)
        ell = self.edge_half_length(grasp)
        overhang = ((face - lean, -ell), (face, -ell), (face, ell), (face - lean, ell))
        return (arms, overhang)

    def held_outline(self, grasp: int) -> tuple[tuple[float, float], ...]:
        """Floor points (robot frame) whose convex hull is the holding robot's body.

        The walking body (:meth:`walking_extent`: the robot steps while it pivots the box,
        and its hands swing from their walking posture to the grips) and
        :meth:`held_polygons`: one convex prism, so the planner checks the whole held
        assembly with one distance query.
        """
        pts = list(self.walking_outline())
        for poly in self.held_polygons(grasp):
            pts += poly
        return tuple(pts)

    def held_corners(self, robot: Pose, grasp: int) -> list[tuple[float, float]]:
        """World floor points of :meth:`held_outline` for the robot at ``robot``."""
        outline = self.held_outline(grasp)
        try:
            return place_points(robot, outline)
        except _WRONG as e:
            raise self._refused(robot=robot) from e

def check_grasp(grasp: int, *, field: str = "grasp") -> int:
    """Return ``grasp`` if it is one of :data:`GRASPS`, else raise :class:`InputError`."""
    if isinstance(grasp, bool) or not isinstance(grasp, int) or grasp not in GRASPS:
        raise InputError(field, grasp, "must be a grasp index 0, 1, 2 or 3")
    return grasp

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

Limits (a scene outside them has no sensible plan; it is refused with the field named):
coordinates within +-:data:`MAX_COORD` m, the floor area at most :data:`MAX_EXTENT` m on a side,
box and footprint sides within [:data:`MIN_SIZE`, :data:`MAX_SIZE`] m, ``alpha_max`` within
[:data:`MIN_ALPHA_MAX`, pi/2] rad, ``turning_radius`` within [:data:`MIN_TURNING_RADIUS`,
:data:`MAX_TURNING_RADIUS`] m, at most :data:`MAX_OBSTACLES` obstacles and
:data:`MAX_POLYGON_POINTS` points per polygon; a polygon must be simple (no self-intersection).
Yaw angles must lie within [-2 pi, 2 pi] (larger magnitudes are refused: degrees given by
mistake); those outside [-pi, pi] are wrapped into [-pi, pi) on load.
"""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import shapely.geometry
import shapely.validation

from pivot_ompl import hrp2
from pivot_ompl.errors import InputError, Interrupted, SceneError
from pivot_ompl.fileio import input_path, load_yaml, parse_deadline
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.se2 import Pose, wrap_angle

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

    step_forward: float = hrp2.STEP_FORWARD
    step_backward: float = hrp2.STEP_BACKWARD
    step_lateral: float = hrp2.STEP_LATERAL
    step_turn: float = hrp2.STEP_TURN
    side_cost: float = hrp2.STEP_FORWARD / hrp2.STEP_LATERAL
    back_cost: float = hrp2.STEP_FORWARD / hrp2.STEP_BACKWARD
    turn_cost: float = hrp2.STEP_FORWARD / hrp2.STEP_TURN

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
        robot_model: robot model name (``"hrp2"``).
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
    robot_model: str = "hrp2"
    source: str = field(default="", compare=False)
    walk: WalkParameters = field(default_factory=WalkParameters)


ROBOT_MODELS = {"hrp2": {"footprint": hrp2.FOOTPRINT, "standoff": hrp2.STANDOFF,
                         "height": hrp2.HEIGHT}}


class KindOf:
    """Stands for a value in a message by its type alone (``a str``): never its content."""

    def __init__(self, value: Any) -> None:
        """The stand-in of ``value``."""
        self.kind = type(value).__name__

    def __repr__(self) -> str:
        """``a <type>``."""
        return f"a {self.kind}"


class _Reader:
    """Typed field access that raises :class:`SceneError` naming file, field and value."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, fld: str, value: Any, reason: str) -> SceneError:
        return SceneError(fld, value, reason, source=self.source)

    def mapping(self, d: Any, fld: str, required: set[str], optional: set[str]) -> dict:
        if not isinstance(d, dict):  # its content is not echoed: the file may be no scene
            raise self.fail(fld or "<document>", KindOf(d), "must be a mapping")
        for k in d:
            if k not in required | optional:
                name = f"{fld}.{k}" if fld else str(k)
                raise self.fail(name, KindOf(d[k]),
                                f"unknown key (allowed: {sorted(required | optional)})")
        for k in sorted(required):
            if k not in d:
                raise self.fail(f"{fld}.{k}" if fld else k, None, "is required")
        return d

    def number(self, v: Any, fld: str, *, positive: bool = False,
               nonneg: bool = False, lo: float = -MAX_COORD, hi: float = MAX_COORD) -> float:
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise self.fail(fld, v, "must be a finite number")
        try:
            x = float(v)
        except OverflowError:
            x = math.inf
        if not math.isfinite(x):
            raise self.fail(fld, v, "must be a finite number")
        if positive and x <= 0:
            raise self.fail(fld, v, "must be > 0")
        if nonneg and x < 0:
            raise self.fail(fld, v, "must be >= 0")
        if not lo <= x <= hi:
            raise self.fail(fld, v, f"must be within [{lo:g}, {hi:g}]")
        return x

    def angle(self, v: Any, fld: str) -> float:
        """A yaw (rad) within [-2 pi, 2 pi], wrapped into [-pi, pi) when outside [-pi, pi]."""
        a = self.number(v, fld, lo=-MAX_YAW, hi=MAX_YAW)
        return a if -math.pi <= a <= math.pi else wrap_angle(a)

    def vector(self, v: Any, n: int, fld: str, *, positive: bool = False,
               lo: float = -MAX_COORD, hi: float = MAX_COORD) -> tuple[float, ...]:
        if not isinstance(v, list | tuple) or len(v) != n:
            raise self.fail(fld, v, f"must be a list of {n} numbers")
        return tuple(self.number(x, f"{fld}[{i}]", positive=positive, lo=lo, hi=hi)
                     for i, x in enumerate(v))

    def pose(self, v: Any, fld: str) -> tuple[float, float, float]:
        """``[x, y, yaw]``: coordinates within +-MAX_COORD m, the yaw as :meth:`angle`."""
        if not isinstance(v, list | tuple) or len(v) != 3:
            raise self.fail(fld, v, "must be a list of 3 numbers [x, y, yaw]")
        return (self.number(v[0], f"{fld}[0]"), self.number(v[1], f"{fld}[1]"),
                self.angle(v[2], f"{fld}[2]"))


def scene_from_dict(doc: Any, *, source: str = "",
                    should_stop: Callable[[], bool] | None = None) -> Scene:
    """Build a :class:`Scene` from a parsed YAML document (see the module docstring).

    Raises:
        SceneError: a wrong field (naming it and its value).
        Interrupted: ``should_stop()`` became true (polled before every obstacle and
            before a polygon's validity check).
    """
    r = _Reader(source)
    top = r.mapping(doc, "", {"name", "bounds", "object", "start", "goal"},
                    {"robot", "pivot", "obstacles"})
    name = top["name"]
    if not isinstance(name, str) or not name:
        raise r.fail("name", name, "must be a non-empty string")
    b = r.vector(top["bounds"], 4, "bounds")
    if not (b[0] < b[2] and b[1] < b[3]):
        raise r.fail("bounds", list(b), "must satisfy xmin < xmax and ymin < ymax")
    if max(b[2] - b[0], b[3] - b[1]) > MAX_EXTENT:
        raise r.fail("bounds", list(b), f"the floor area must be at most {MAX_EXTENT:g} m on a "
                     "side")
    obj = r.mapping(top["object"], "object", {"size"}, set())
    size = r.vector(obj["size"], 3, "object.size", positive=True, lo=MIN_SIZE, hi=MAX_SIZE)
    robot = r.mapping(top.get("robot", {}), "robot", set(),
                      {"model", "footprint", "standoff", "walk"})
    model_name = robot.get("model", "hrp2")
    if model_name not in ROBOT_MODELS:
        raise r.fail("robot.model", model_name,
                     f"unknown robot model (known: {sorted(ROBOT_MODELS)})")
    rm = _robot_defaults(model_name)
    foot = (r.vector(robot["footprint"], 2, "robot.footprint", positive=True, lo=MIN_SIZE,
                     hi=MAX_SIZE)
            if "footprint" in robot else rm["footprint"])
    standoff = (r.number(robot["standoff"], "robot.standoff", nonneg=True, hi=MAX_SIZE)
                if "standoff" in robot else rm["standoff"])
    walk = _walk(r, robot.get("walk", {}))
    piv = r.mapping(top.get("pivot", {}), "pivot", set(), {"alpha_max", "turning_radius"})
    alpha_max = r.number(piv.get("alpha_max", DEFAULT_ALPHA_MAX), "pivot.alpha_max",
                         positive=True, lo=MIN_ALPHA_MAX, hi=0.5 * math.pi)
    turning = r.number(piv.get("turning_radius", DEFAULT_TURNING_RADIUS),
                       "pivot.turning_radius", positive=True, lo=MIN_TURNING_RADIUS,
                       hi=MAX_TURNING_RADIUS)
    obstacles = []
    raw_obs = top.get("obstacles", [])
    if raw_obs is None:
        raw_obs = []
    if not isinstance(raw_obs, list):
        raise r.fail("obstacles", raw_obs, "must be a list")
    if len(raw_obs) > MAX_OBSTACLES:
        raise r.fail("obstacles", len(raw_obs), f"at most {MAX_OBSTACLES} obstacles")
    for i, o in enumerate(raw_obs):
        if should_stop is not None and should_stop():
            raise Interrupted("reading the scene")
        obstacles.append(_obstacle(r, o, f"obstacles[{i}]", should_stop))
    model = BoxGraspModel(size, foot, standoff, rm["height"])  # type: ignore[arg-type]
    start = r.pose(top["start"], "start")
    goal = r.pose(top["goal"], "goal")
    for fld, pose in (("start", start), ("goal", goal)):
        for x, y in model.object_corners(pose):
            if not (b[0] <= x <= b[2] and b[1] <= y <= b[3]):
                raise r.fail(fld, list(pose), f"the box footprint leaves bounds {list(b)}")
    return Scene(name, b, model, start, goal, tuple(obstacles), alpha_max,  # type: ignore[arg-type]
                 turning, model_name, source, walk=walk)


def _walk(r: _Reader, raw: Any) -> WalkParameters:
    """The ``robot.walk`` block: step limits (> 0) and walking costs (>= 1; turning >= 0)."""
    names = ("step_forward", "step_backward", "step_lateral", "step_turn", "side_cost",
             "back_cost", "turn_cost")
    d = r.mapping({} if raw is None else raw, "robot.walk", set(), set(names))
    out = {}
    for k in names:
        if k not in d:
            continue
        fld = f"robot.walk.{k}"
        v = r.number(d[k], fld, positive=k.startswith("step"), nonneg=k == "turn_cost")
        if k in ("side_cost", "back_cost") and v < 1.0:
            raise r.fail(fld, v, "must be >= 1 (walking forward costs 1 per metre)")
        if k == "step_turn" and v > 0.5 * math.pi:
            raise r.fail(fld, v, "must be <= pi/2 rad")
        out[k] = v
    return WalkParameters(**out)


def _robot_defaults(name: str) -> dict[str, Any]:
    """Footprint, standoff and height of a robot model (HRP-2's derive from robots/hrp2)."""
    base = dict(ROBOT_MODELS[name])
    if name == "hrp2":
        try:
            base.update(hrp2.hrp2_floor_geometry())
        except ImportError:  # no pinocchio: the preset constants
            return base
    return base


def obstacles_from_list(items: Any, *, source: str = "", field: str = "obstacles"
                        ) -> tuple[Obstacle, ...]:
    """Obstacles written as in a scene file's ``obstacles:`` list, validated the same way.

    Raises:
        SceneError: a malformed item, naming ``field[i]`` and the value.
    """
    r = _Reader(source)
    if not isinstance(items, list):
        raise r.fail(field, items, "must be a list")
    if len(items) > MAX_OBSTACLES:
        raise r.fail(field, len(items), f"at most {MAX_OBSTACLES} obstacles")
    return tuple(_obstacle(r, o, f"{field}[{i}]") for i, o in enumerate(items))


def _obstacle(r: _Reader, o: Any, f: str, should_stop: Callable[[], bool] | None = None
              ) -> Obstacle:
    if not isinstance(o, dict):
        raise r.fail(f, KindOf(o), "must be a mapping")
    kind = o.get("type")
    if kind == "box":
        d = r.mapping(o, f, {"type", "center", "size", "height"}, {"yaw"})
        return BoxObstacle(r.vector(d["center"], 2, f"{f}.center"),  # type: ignore[arg-type]
                           r.vector(d["size"], 2, f"{f}.size", positive=True),  # type: ignore[arg-type]
                           r.angle(d.get("yaw", 0.0), f"{f}.yaw"),
                           r.number(d["height"], f"{f}.height", positive=True))
    if kind == "cylinder":
        d = r.mapping(o, f, {"type", "center", "radius", "height"}, set())
        return CylinderObstacle(r.vector(d["center"], 2, f"{f}.center"),  # type: ignore[arg-type]
                                r.number(d["radius"], f"{f}.radius", positive=True),
                                r.number(d["height"], f"{f}.height", positive=True))
    if kind == "polygon":
        d = r.mapping(o, f, {"type", "points", "height"}, set())
        pts = d["points"]
        if not isinstance(pts, list) or not 3 <= len(pts) <= MAX_POLYGON_POINTS:
            raise r.fail(f"{f}.points", pts, "must be a list of 3 to "
                         f"{MAX_POLYGON_POINTS} [x, y] points")
        points = tuple(r.vector(p, 2, f"{f}.points[{j}]") for j, p in enumerate(pts))
        area2 = sum(points[i][0] * points[(i + 1) % len(points)][1]
                    - points[(i + 1) % len(points)][0] * points[i][1] for i in range(len(points)))
        if abs(area2) < 1e-12:
            raise r.fail(f"{f}.points", pts, "polygon has zero area")
        if should_stop is not None and should_stop():  # GEOS's check: 0.06 s at 10 000 points
            raise Interrupted("reading the scene")
        ring = shapely.geometry.Polygon(points)
        if not ring.is_valid:
            raise r.fail(f"{f}.points", pts, "must be a simple polygon "
                         f"({shapely.validation.explain_validity(ring)})")
        return PolygonObstacle(points, r.number(d["height"], f"{f}.height",  # type: ignore[arg-type]
                                                positive=True))
    raise r.fail(f"{f}.type", kind, "must be 'box', 'cylinder' or 'polygon'")


def scene_path(path: str | Path) -> Path:
    """The file :func:`load_scene` reads: ``path``, or the shipped scene of that name.

    Raises:
        InputError: ``path`` is neither a ``str`` nor an ``os.PathLike``.
        SceneError: no such file nor shipped scene (the shipped ones are listed).
    """
    path = input_path(path)
    if not path.exists():
        shipped = shipped_scenes()
        if str(path) not in shipped:
            raise SceneError("path", str(path), "no such file, nor a shipped scene's name "
                             f"(shipped: {', '.join(shipped)})")
        path = shipped[str(path)]
    return path


def load_scene(path: str | Path, *, deadline: float | None = None) -> Scene:
    """Read and validate a scene file, or the shipped scene of that name (``"fig10"``).

    Raises:
        SceneError: no such file nor shipped scene (the shipped ones are listed), unreadable
            file, invalid YAML, unknown key, missing field, wrong type or bad value, naming
            the file, the field and the value.
        Interrupted: ``deadline`` (``time.monotonic()`` s, a time limit) came while the file
            was parsed (stopped early enough to have freed what was parsed by then,
            :func:`~pivot_ompl.fileio.parse_deadline`) or its obstacles read.
    """
    path = scene_path(path)
    if deadline is None:
        return scene_from_dict(load_yaml(path, error=SceneError), source=str(path))
    doc = load_yaml(path, error=SceneError, should_stop=parse_deadline(deadline))
    return scene_from_dict(doc, source=str(path),
                           should_stop=lambda: time.monotonic() >= deadline)


def scene_digest(scene: Scene) -> str:
    """SHA-256 (hex) of what a plan of ``scene`` depends on: its geometry, ends and pivoting.

    Not the name or the file: two files of one scene give one digest, and a plan records it
    (``scene_sha256``) so that a check against another scene says so first.
    """
    text = repr((scene.bounds, scene.obstacles, scene.model, scene.start, scene.goal,
                 scene.alpha_max, scene.turning_radius, scene.walk))
    return hashlib.sha256(text.encode()).hexdigest()


def check_pose(pose: Any, *, field: str) -> Pose:
    """An object pose given outside a scene file (``--start``), under the scene file's rules.

    Raises:
        InputError: a coordinate beyond +-:data:`MAX_COORD` m or a yaw beyond +-2 pi rad.
    """
    try:
        return _Reader("").pose(list(pose) if isinstance(pose, tuple) else pose, field)
    except SceneError as e:
        raise InputError(e.field, e.value, e.reason) from None


def default_scene(*, start: Pose = (0.0, 0.0, 0.0), goal: Pose = (0.0, 0.0, 0.0),
                  margin: float = 5.0) -> Scene:
    """The paper's obstacle-free set-up around ``start`` and ``goal`` (bounds with a margin)."""
    xs = (start[0], goal[0])
    ys = (start[1], goal[1])
    model = BoxGraspModel(DEFAULT_OBJECT_SIZE)
    return Scene("free", (min(xs) - margin, min(ys) - margin, max(xs) + margin,
                          max(ys) + margin), model, start, goal)

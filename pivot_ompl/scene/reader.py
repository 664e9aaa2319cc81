"""Scene documents read and validated: every error names the file, the field and the value.

See :mod:`pivot_ompl.scene` for the format and its limits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import shapely.geometry
import shapely.validation

from pivot_ompl.errors import InputError, Interrupted, SceneError
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, HumanoidProfile, profile_of
from pivot_ompl.scene.model import (
    DEFAULT_ALPHA_MAX,
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
)
from pivot_ompl.se2 import Pose, wrap_angle

#: Known robot models (the humanoid profiles' names).
ROBOT_MODELS = PROFILES


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
    model_name = robot.get("model", DEFAULT_MODEL)
    if model_name not in ROBOT_MODELS:
        raise r.fail("robot.model", model_name,
                     f"unknown robot model (known: {sorted(ROBOT_MODELS)})")
    rm = _robot_defaults(model_name)
    foot = (r.vector(robot["footprint"], 2, "robot.footprint", positive=True, lo=MIN_SIZE,
                     hi=MAX_SIZE)
            if "footprint" in robot else rm["footprint"])
    foot = PROFILES[model_name].cautious_footprint(foot)  # type: ignore[arg-type]
    standoff = (r.number(robot["standoff"], "robot.standoff", nonneg=True, hi=MAX_SIZE)
                if "standoff" in robot else rm["standoff"])
    walk = _walk(r, robot.get("walk", {}), PROFILES[model_name])
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
    model = BoxGraspModel(size, foot, standoff, rm["height"],  # type: ignore[arg-type]
                          model_name)
    start = r.pose(top["start"], "start")
    goal = r.pose(top["goal"], "goal")
    for fld, pose in (("start", start), ("goal", goal)):
        for x, y in model.object_corners(pose):
            if not (b[0] <= x <= b[2] and b[1] <= y <= b[3]):
                raise r.fail(fld, list(pose), f"the box footprint leaves bounds {list(b)}")
    return Scene(name, b, model, start, goal, tuple(obstacles), alpha_max,  # type: ignore[arg-type]
                 turning, model_name, source, walk=walk)


def _walk(r: _Reader, raw: Any, robot: HumanoidProfile) -> WalkParameters:
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
    return WalkParameters.of_profile(robot, **out)


def _robot_defaults(name: str) -> dict[str, Any]:
    """Footprint, standoff and height of a robot model (its profile's)."""
    p = profile_of(name)
    return {"footprint": p.footprint, "standoff": p.standoff, "height": p.height}


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


def check_pose(pose: Any, *, field: str) -> Pose:
    """An object pose given outside a scene file (``--start``), under the scene file's rules.

    Raises:
        InputError: a coordinate beyond +-:data:`MAX_COORD` m or a yaw beyond +-2 pi rad.
    """
    try:
        return _Reader("").pose(list(pose) if isinstance(pose, tuple) else pose, field)
    except SceneError as e:
        raise InputError(e.field, e.value, e.reason) from None

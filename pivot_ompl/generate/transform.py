"""Rigid copies of a scene: rotated by any angle about a point, or mirrored about a line.

The scene's bounds (an axis-aligned rectangle) cannot rotate, so the copy keeps the old
floor area as four thin walls round it (:data:`BOUND_WALL` thick, outside the old area) and
takes as bounds the axis-aligned rectangle holding them: the free space of the copy is the
free space of the original moved rigidly. Object poses keep their meaning (centre and yaw of
the box's local x axis); a mirror maps grasp ``k`` to ``-k mod 4`` (the robot's facing
direction is mirrored too), which planners choose for themselves.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from pivot_ompl.argcheck import guard
from pivot_ompl.errors import InputError, require_type
from pivot_ompl.scene import (
    MAX_COORD,
    BoxObstacle,
    CylinderObstacle,
    Obstacle,
    PolygonObstacle,
    Scene,
)
from pivot_ompl.se2 import Pose, wrap_angle

#: Thickness (m) of the walls that keep a transformed copy inside the original floor area.
BOUND_WALL = 0.2
#: Height (m) of those walls.
BOUND_WALL_HEIGHT = 2.0


def _walls_round(bounds: tuple[float, float, float, float]) -> list[Obstacle]:
    x0, y0, x1, y1 = bounds
    t = BOUND_WALL
    w, h = x1 - x0 + 2 * t, y1 - y0 + 2 * t
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return [BoxObstacle((cx, y0 - 0.5 * t), (w, t), 0.0, BOUND_WALL_HEIGHT),
            BoxObstacle((cx, y1 + 0.5 * t), (w, t), 0.0, BOUND_WALL_HEIGHT),
            BoxObstacle((x0 - 0.5 * t, cy), (t, h), 0.0, BOUND_WALL_HEIGHT),
            BoxObstacle((x1 + 0.5 * t, cy), (t, h), 0.0, BOUND_WALL_HEIGHT)]


def _map_point(p: tuple[float, float], c: float, s: float, about: tuple[float, float],
               mirror: bool) -> tuple[float, float]:
    """Rotate (``mirror=False``) or reflect about the line of direction angle ``a``.

    ``c, s = cos, sin`` of the rotation angle, or of ``2 a`` for a mirror.
    """
    dx, dy = p[0] - about[0], p[1] - about[1]
    if mirror:
        return (about[0] + c * dx + s * dy, about[1] + s * dx - c * dy)
    return (about[0] + c * dx - s * dy, about[1] + s * dx + c * dy)


@dataclass(frozen=True)
class RigidMap:
    """A rigid map of the floor.

    A rotation by ``angle`` (rad) about ``about``, or (``mirror``) a reflection about the
    line through ``about`` at direction ``angle``.
    """

    angle: float
    about: tuple[float, float]
    mirror: bool = False

    def __post_init__(self) -> None:
        guard("RigidMap", angle=(self.angle, None), about=(self.about, 2))
        if not isinstance(self.mirror, bool):
            raise InputError("RigidMap.mirror", self.mirror, "must be True or False")

    def point(self, p: tuple[float, float]) -> tuple[float, float]:
        """The image of a point (m)."""
        a = 2 * self.angle if self.mirror else self.angle
        return _map_point(p, math.cos(a), math.sin(a), self.about, self.mirror)

    def yaw(self, a: float) -> float:
        """The image of a direction (rad)."""
        return wrap_angle(2 * self.angle - a if self.mirror else a + self.angle)

    def pose(self, q: Pose) -> Pose:
        """The image of an object pose."""
        x, y = self.point((q[0], q[1]))
        return (x, y, self.yaw(q[2]))

    def grasp(self, k: int) -> int:
        """The grasp of the image state (a mirror reverses the grasps' order)."""
        return (-k) % 4 if self.mirror else k


def _transform(scene: Scene, angle: float, about: tuple[float, float], mirror: bool,
               name: str) -> Scene:
    return transform_scene(scene, RigidMap(angle, about, mirror), name=name)


def transform_scene(scene: Scene, f: RigidMap, *, name: str) -> Scene:
    """The image of ``scene`` under ``f`` (walled in its old floor area, see module doc).

    Raises:
        InputError: ``scene`` not a Scene, ``f`` not a :class:`RigidMap`, ``name`` not a
            non-empty string.
    """
    require_type(scene, Scene, "scene", "a Scene (pivot_ompl.load_scene(name) gives one)")
    require_type(f, RigidMap, "f", "a RigidMap")
    if not isinstance(name, str) or not name:
        raise InputError("name", name, "must be a non-empty string")
    pt, yaw, pose, mirror = f.point, f.yaw, f.pose, f.mirror

    out: list[Obstacle] = []
    for o in (*scene.obstacles, *_walls_round(scene.bounds)):
        if isinstance(o, BoxObstacle):
            out.append(BoxObstacle(pt(o.center), o.size, yaw(o.yaw), o.height))
        elif isinstance(o, CylinderObstacle):
            out.append(CylinderObstacle(pt(o.center), o.radius, o.height))
        else:
            pts = tuple(pt(p) for p in o.points)
            out.append(PolygonObstacle(pts[::-1] if mirror else pts, o.height))
    x0, y0, x1, y1 = scene.bounds
    t = BOUND_WALL
    corners = [pt((x, y)) for x in (x0 - t, x1 + t) for y in (y0 - t, y1 + t)]
    bounds = (min(p[0] for p in corners), min(p[1] for p in corners),
              max(p[0] for p in corners), max(p[1] for p in corners))
    return dataclasses.replace(scene, name=name, bounds=bounds, obstacles=tuple(out),
                               start=pose(scene.start), goal=pose(scene.goal), source="")


def _check_transform(scene: Any, angle: Any, angle_field: str, about: Any, name: Any) -> None:
    """Validate a transform's arguments, naming the one at fault."""
    require_type(scene, Scene, "scene", "a Scene (pivot_ompl.load_scene(name) gives one)")
    if isinstance(angle, bool) or not isinstance(angle, int | float) or \
            not abs(angle) <= 4.0 * math.pi:
        raise InputError(angle_field, angle, "must be a finite angle within +-4 pi rad")
    if about is not None:
        if isinstance(about, str | bytes) or not isinstance(about, tuple | list) or \
                len(about) != 2:
            raise InputError("about", about, "must be a point (x, y) or None")
        for i, v in enumerate(about):
            if isinstance(v, bool) or not isinstance(v, int | float) or \
                    not abs(v) <= MAX_COORD:
                raise InputError(f"about[{i}]", v, f"must be finite, within +-{MAX_COORD:g} m")
    if name is not None and (not isinstance(name, str) or not name):
        raise InputError("name", name, "must be a non-empty string or None")


def rotate_scene(scene: Scene, angle: float, *, about: tuple[float, float] | None = None,
                 name: str | None = None) -> Scene:
    """A copy of ``scene`` rotated by ``angle`` (rad) about ``about`` (default: its centre).

    Raises:
        InputError: a wrong argument (naming it).
    """
    _check_transform(scene, angle, "angle", about, name)
    if about is None:
        about = (0.5 * (scene.bounds[0] + scene.bounds[2]),
                 0.5 * (scene.bounds[1] + scene.bounds[3]))
    return _transform(scene, angle, about, False,
                      name or f"{scene.name}_rot{math.degrees(angle):.0f}")


def mirror_scene(scene: Scene, axis_angle: float = 0.0, *,
                 about: tuple[float, float] | None = None, name: str | None = None) -> Scene:
    """A copy of ``scene`` mirrored about the line through ``about`` at ``axis_angle`` (rad).

    Raises:
        InputError: a wrong argument (naming it).
    """
    _check_transform(scene, axis_angle, "axis_angle", about, name)
    if about is None:
        about = (0.5 * (scene.bounds[0] + scene.bounds[2]),
                 0.5 * (scene.bounds[1] + scene.bounds[3]))
    return _transform(scene, axis_angle, about, True,
                      name or f"{scene.name}_mirror{math.degrees(axis_angle):.0f}")

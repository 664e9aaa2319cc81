"""Static scene objects sent to a ``meshcat.Visualizer``: floor, obstacles, box, markers.

Node names (under the visualizer's path) are a contract used by the tests and notebooks:
``floor``, ``obstacles/<i>``, ``box``, ``robot``, ``rs_path``, ``pivots/<i>``,
``footsteps/<i>``, ``roadmap/<name>``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import meshcat
import meshcat.geometry as g
import numpy as np

from pivot_ompl.errors import InputError, require_type
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, PolygonObstacle, Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.viz.shapes import axis_angle, planar, prism_mesh, translation

FLOOR_COLOR = 0xd8d8d0
OBSTACLE_COLOR = 0x8a6f5a
BOX_COLOR = 0xc8a060
SIM_BOX_COLOR = 0x40a0c0
ROBOT_COLOR = 0x4f7fbf
PATH_COLOR = 0x20a040
PIVOT_COLOR = 0xd03030
FOOTSTEP_COLOR = 0x3050a0
FLOOR_THICKNESS = 0.01  # m, top face at z = 0


def css_colour(color: int) -> str:
    """``0xRRGGBB`` as the page's ``#rrggbb``."""
    return f"#{color:06x}"


#: What each shape of a replay is (the page's legend panel), by node.
LEGEND_TEXT = {
    "obstacles": (OBSTACLE_COLOR, "obstacles"),
    "box": (BOX_COLOR, "the box, leaning on its supporting edge while pivoted"),
    "sim_box": (SIM_BOX_COLOR, "translucent: the box as simulated (physics), beside the plan's"),
    "robot_volume": (ROBOT_COLOR, "the robot: its footprint plate and bounding volume"),
    "robot_urdf": (0xa0a8b8, "the robot drawn from its URDF's visual geometry (meshes, "
                             "decimated, where it has them; HRP-2's are boxes and cylinders)"),
    "rs_path": (PATH_COLOR, "line: the Reeds-Shepp path of the supporting edge's centre"),
    "walks": (ROBOT_COLOR, "line: a regrasp walk of the robot's centre"),
    "pivots": (PIVOT_COLOR, "spheres: the pivot corners (where the box turns)"),
    "footprints": (FOOTSTEP_COLOR, "rectangles: where the robot stands (footprint)"),
    "footsteps": (FOOTSTEP_COLOR, "rectangles: footsteps (soles)"),
    "zmp": (PIVOT_COLOR, "zigzag line: the planned ZMP, swaying over each support foot"),
}


def legend(keys: Iterable[str]) -> list[list[str]]:
    """The legend entries ``[colour, text]`` of the drawn ``keys`` (of :data:`LEGEND_TEXT`)."""
    return [[css_colour(LEGEND_TEXT[k][0]), LEGEND_TEXT[k][1]] for k in keys]


def _lambert(color: int, *, opacity: float = 1.0) -> g.MeshLambertMaterial:
    return g.MeshLambertMaterial(color=color, opacity=opacity)


#: Nodes a replay owns; cleared before a new replay is drawn into the same visualizer.
REPLAY_NODES = ("floor", "obstacles", "box", "robot", "rs_path", "walks", "pivots",
                "footsteps", "zmp", "sim_box")


def check_view(vis: Any = None, *, scene: Any = None, require_vis: bool = True,
               **values: tuple[Any, type]) -> None:
    """Check a view helper's arguments (an InputError naming the argument, not a crash).

    ``vis`` must be a visualizer (anything indexable by node name, as ``meshcat.Visualizer``
    and :func:`~pivot_ompl.viz.recording_visualizer`); ``scene`` a Scene or ``None``;
    ``values`` maps further argument names to ``(value, expected class)``.
    """
    if require_vis and not callable(getattr(vis, "__getitem__", None)):
        raise InputError("vis", type(vis).__name__, "must be a meshcat Visualizer (or "
                         "pivot_ompl.viz.recording_visualizer())")
    if scene is not None:
        require_type(scene, Scene, "scene", "a Scene (load_scene) or None")
    for name, (value, kind) in values.items():
        require_type(value, kind, name, f"a {kind.__name__}")


def clear(vis: meshcat.Visualizer, names: Sequence[str] = REPLAY_NODES) -> None:
    """Delete the named child nodes of ``vis`` (re-running a notebook cell starts afresh)."""
    for name in names:
        vis[name].delete()


def draw_floor(vis: meshcat.Visualizer, bounds: tuple[float, float, float, float]) -> None:
    """A thin slab covering ``bounds = (xmin, ymin, xmax, ymax)`` (m), top face at z = 0."""
    x0, y0, x1, y1 = bounds
    vis["floor"].set_object(g.Box([x1 - x0, y1 - y0, FLOOR_THICKNESS]), _lambert(FLOOR_COLOR))
    vis["floor"].set_transform(translation(0.5 * (x0 + x1), 0.5 * (y0 + y1),
                                           -0.5 * FLOOR_THICKNESS - 1e-3))


def draw_obstacle(vis: meshcat.Visualizer, obstacle: Obstacle) -> None:
    """One obstacle prism standing on the floor with its real height."""
    mat = _lambert(OBSTACLE_COLOR)
    if isinstance(obstacle, BoxObstacle):
        vis.set_object(g.Box([obstacle.size[0], obstacle.size[1], obstacle.height]), mat)
        vis.set_transform(planar((*obstacle.center, obstacle.yaw), 0.5 * obstacle.height))
    elif isinstance(obstacle, CylinderObstacle):
        # three.js cylinders run along their local y axis: turn it up.
        vis.set_object(g.Cylinder(obstacle.height, obstacle.radius), mat)
        vis.set_transform(translation(*obstacle.center, 0.5 * obstacle.height)
                          @ axis_angle((1.0, 0.0, 0.0), 0.5 * math.pi))
    elif isinstance(obstacle, PolygonObstacle):
        verts, faces = prism_mesh(obstacle.points, obstacle.height)
        vis.set_object(g.TriangularMeshGeometry(verts, faces), mat)
        vis.set_transform(np.eye(4))
    else:  # pragma: no cover - the scene reader only makes the three kinds
        raise TypeError(f"unknown obstacle {obstacle!r}")


def draw_scene(vis: meshcat.Visualizer, scene: Scene | None, *,
               bounds: tuple[float, float, float, float] | None = None) -> None:
    """Floor (scene bounds, else ``bounds``) and every obstacle of ``scene``."""
    if scene is not None:
        bounds = scene.bounds
    if bounds is not None:
        draw_floor(vis, bounds)
    if scene is not None:
        for i, obs in enumerate(scene.obstacles):
            draw_obstacle(vis[f"obstacles/{i}"], obs)


def draw_box(vis: meshcat.Visualizer, size: Sequence[float]) -> None:
    """The manipulated box ``(w, d, h)`` centred on its node's origin."""
    vis.set_object(g.Box(list(size)), _lambert(BOX_COLOR))


def draw_sim_box(vis: meshcat.Visualizer, size: Sequence[float]) -> None:
    """The simulated box ``(w, d, h)``, translucent, centred on its node's origin."""
    vis.set_object(g.Box(list(size)), _lambert(SIM_BOX_COLOR, opacity=0.55))


def draw_robot_volume(vis: meshcat.Visualizer, model: BoxGraspModel) -> None:
    """The robot's bounding volume (translucent) and its footprint plate, for plan replays.

    The node's origin is the robot's footprint centre on the floor, x along its heading.
    """
    depth, width = model.robot_footprint
    vis["footprint"].set_object(g.Box([depth, width, 0.02]), _lambert(ROBOT_COLOR))
    vis["footprint"].set_transform(translation(0.0, 0.0, 0.01))
    vis["body"].set_object(g.Box([depth, width, model.robot_height]),
                           _lambert(ROBOT_COLOR, opacity=0.35))
    vis["body"].set_transform(translation(0.0, 0.0, 0.5 * model.robot_height))
    vis["nose"].set_object(g.Box([0.08, 0.08, 0.08]), _lambert(0xffffff))
    vis["nose"].set_transform(translation(0.5 * depth - 0.04, 0.0, model.robot_height))


def draw_polyline(vis: meshcat.Visualizer, points: Sequence[Sequence[float]], *,
                  color: int = PATH_COLOR, z: float = 0.02) -> None:
    """A line through planar ``points`` (x, y[, ...]) drawn just above the floor."""
    p = np.asarray([[q[0], q[1], z] for q in points], dtype=np.float32)
    vis.set_object(g.Line(g.PointsGeometry(p.T), g.LineBasicMaterial(color=color)))


def draw_segments(vis: meshcat.Visualizer, segments: Iterable[tuple[Sequence[float],
                                                                     Sequence[float]]], *,
                  color: int = 0x808080, z: float = 0.015) -> None:
    """Independent line segments between planar points (one meshcat object)."""
    pts = [[a[0], a[1], z] for ab in segments for a in ab]
    if not pts:
        return
    p = np.asarray(pts, dtype=np.float32)
    vis.set_object(g.LineSegments(g.PointsGeometry(p.T), g.LineBasicMaterial(color=color)))


def draw_points(vis: meshcat.Visualizer, points: Iterable[Sequence[float]], *,
                color: int = PIVOT_COLOR, radius: float = 0.03, z: float = 0.0) -> int:
    """Small spheres at planar points, children ``0, 1, ...`` of ``vis``; returns the count."""
    n = 0
    for n, p in enumerate(points, start=1):  # noqa: B007
        node = vis[str(n - 1)]
        node.set_object(g.Sphere(radius), _lambert(color))
        node.set_transform(translation(p[0], p[1], z + radius))
    return n


def draw_footsteps(vis: meshcat.Visualizer, poses: Iterable[Pose], size: Sequence[float], *,
                   color: int = FOOTSTEP_COLOR, opacity: float = 0.45,
                   thickness: float = 0.006) -> int:
    """Flat boxes ``size = (length, width)`` at planar ``poses``; returns the count."""
    n = 0
    for n, pose in enumerate(poses, start=1):  # noqa: B007
        node = vis[str(n - 1)]
        node.set_object(g.Box([size[0], size[1], thickness]), _lambert(color, opacity=opacity))
        node.set_transform(planar(pose, 0.5 * thickness + 0.002))
    return n

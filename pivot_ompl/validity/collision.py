"""Collision and clearance with coal: obstacles as prisms, the box and the robot as boxes.

Obstacles are vertical prisms standing on the floor: a box obstacle is a ``coal.Box``, a
cylinder a ``coal.Cylinder``, a polygon is triangulated (GEOS's constrained Delaunay
triangulation, :func:`~pivot_ompl.se2.triangulate`, so non-convex polygons work) into
triangular prisms (``coal.Convex`` built from their faces, flat triangles of spikes thinner than
round-off included: a polygon collides exactly as shapely draws it). All obstacles live in one
``DynamicAABBTreeCollisionManager`` so a query costs one call; on floors of many pieces a
query goes through the tree of the pieces near it (:mod:`~pivot_ompl.validity.near_pieces`,
the whole floor's distances). The box is its 3-D shape standing
on the floor. The robot has two bodies:

* walking (:meth:`CollisionWorld.robot_distance`): its footprint rectangle grown by how far
  the links reach beyond it while walking (:meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`)
  x height;
* holding the box at grasp ``k`` (:meth:`CollisionWorld.held_distance`): one convex prism
  round the footprint, both arms from the shoulders to the grip points and the inclined box's
  overhang over the gap (:meth:`~pivot_ompl.grasp.BoxGraspModel.held_outline`, derived from
  the URDF and the grip conventions for the grasp and the box size).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import coal
import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, PolygonObstacle, Scene
from pivot_ompl.se2 import Pose, triangulate
from pivot_ompl.validity.merge import merge_boxes
from pivot_ompl.validity.near_pieces import NearPieces

#: Distance (m) the planner's bodies keep from obstacles: the whole-body motion's links and
#: box then keep >= 1 cm (the ``obstacles`` check of ``check-motion``).
KEEP_CLEARANCE = 0.01

#: Obstacle pieces from which distance queries go through the trees of the pieces near them
#: (:class:`~pivot_ompl.validity.near_pieces.NearPieces`: the whole floor's distances, 40 %
#: less time on the Willow Garage office's 5049 pieces); fewer: the one tree.
NEAR_FROM = 512

#: Scratch rotation and translation of :func:`_transform` (``coal.Transform3s`` copies them):
#: filling two arrays costs a third of building them, and this runs for every query.
_ROTATION = np.eye(3)
_TRANSLATION = np.zeros(3)


def _scratch(x: float, y: float, yaw: float, z: float) -> tuple[np.ndarray, np.ndarray]:
    """The scratch rotation and translation filled for ``(x, y, z)`` turned by ``yaw``."""
    c, s = math.cos(yaw), math.sin(yaw)
    r, t = _ROTATION, _TRANSLATION
    r[0, 0] = c
    r[0, 1] = -s
    r[1, 0] = s
    r[1, 1] = c
    t[0] = x
    t[1] = y
    t[2] = z
    return r, t


def placement(x: float, y: float, yaw: float, z: float) -> coal.Transform3s:
    """The placement at ``(x, y, z)`` (m) turned by ``yaw`` (rad) about the vertical.

    Filled through scratch arrays, copied by coal: every placement is its own.
    """
    return coal.Transform3s(*_scratch(x, y, yaw, z))


def place(obj: coal.CollisionObject, x: float, y: float, yaw: float, z: float) -> None:
    """Put ``obj`` at ``(x, y, z)`` (m) turned by ``yaw`` (rad): :func:`placement`'s transform.

    Sets the object's rotation and translation in place (no ``Transform3s`` built: a fifth
    of the cost, and every transfer check's query places a body).
    """
    r, t = _scratch(x, y, yaw, z)
    obj.setRotation(r)
    obj.setTranslation(t)


def _prism(points: list[tuple[float, float]], height: float) -> coal.Convex:
    verts = coal.StdVec_Vec3s()
    for z in (0.0, height):
        for x, y in points:
            verts.append(np.array([x, y, z]))
    return coal.Convex.convexHull(verts, False, "")


#: Faces of a triangular prism over the corners 0, 1, 2 (bottom) and 3, 4, 5 (top).
_TRIANGLE_PRISM_FACES = ((0, 2, 1), (3, 4, 5), (0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4),
                         (2, 0, 3), (2, 3, 5))


def _triangle_prism(corners: list[tuple[float, float]], height: float) -> coal.Convex:
    """The prism over a triangle, built from its faces.

    No convex hull (qhull crashed the process on triangles thinner than about 1e-8 m), and a
    flat triangle is a flat prism that coal still measures exactly.
    """
    verts = coal.StdVec_Vec3s()
    for z in (0.0, height):
        for x, y in corners:
            verts.append(np.array([x, y, z]))
    faces = coal.StdVec_Triangle()
    for f in _TRIANGLE_PRISM_FACES:
        faces.append(coal.Triangle(*f))
    return coal.Convex(verts, faces)


#: Triangles of a polygon built between two polls of ``should_stop``.
POLL_TRIANGLES = 500


def obstacle_objects(obstacle: Obstacle, should_stop: Callable[[], bool] | None = None
                     ) -> list[coal.CollisionObject]:
    """The coal collision objects of one obstacle (several for a non-convex polygon).

    Raises:
        Interrupted: ``should_stop()`` became true (polled while a polygon is triangulated
            and every :data:`POLL_TRIANGLES` of its triangles).
    """
    if isinstance(obstacle, BoxObstacle):
        shape = coal.Box(obstacle.size[0], obstacle.size[1], obstacle.height)
        return [coal.CollisionObject(shape, placement(*obstacle.center, obstacle.yaw,
                                                       0.5 * obstacle.height))]
    if isinstance(obstacle, CylinderObstacle):
        shape = coal.Cylinder(obstacle.radius, obstacle.height)
        return [coal.CollisionObject(shape, placement(*obstacle.center, 0.0,
                                                       0.5 * obstacle.height))]
    if isinstance(obstacle, PolygonObstacle):
        out = []
        tris = triangulate(obstacle.points, flat=True, should_stop=should_stop)
        for k, (a, b, c) in enumerate(tris):
            if should_stop is not None and k % POLL_TRIANGLES == POLL_TRIANGLES - 1 \
                    and should_stop():
                raise Interrupted("building the collision world")
            tri = [obstacle.points[a], obstacle.points[b], obstacle.points[c]]
            out.append(coal.CollisionObject(_triangle_prism(tri, obstacle.height),
                                            coal.Transform3s()))
        return out
    raise TypeError(f"unknown obstacle {obstacle!r}")


@dataclass
class CollisionWorld:
    """The scene's obstacles and the two moving bodies, with coal queries.

    Attributes:
        model: the box and robot geometry.
        bounds: floor area ``(xmin, ymin, xmax, ymax)``.
        clearance: distance (m) the bodies keep from obstacles: every obstacle distance
            returned is the true distance minus this, so ``> 0`` means at least this clear.
    """

    model: BoxGraspModel
    bounds: tuple[float, float, float, float]
    clearance: float = 0.0

    def __post_init__(self) -> None:
        """Create the body shapes."""
        w, d, h = self.model.object_size
        self._box_shape = coal.Box(w, d, h)
        ahead, behind, half_width = self.model.walking_extent()
        self._robot_shape = coal.Box(ahead + behind, 2.0 * half_width, self.model.robot_height)
        self._robot_ahead = 0.5 * (ahead - behind)  # the body's centre ahead of the pose
        self._robot_half = (0.5 * (ahead + behind), half_width)
        self._box = coal.CollisionObject(self._box_shape)
        self._robot = coal.CollisionObject(self._robot_shape)
        self._box_radius = 0.5 * math.hypot(w, d)
        self._robot_radius = self.model.robot_radius()
        height = max(self.model.robot_height, self.model.object_size[2])
        self._held = []
        self._held_points = []
        for g in range(4):
            outline = self.model.held_outline(g)
            self._held.append(coal.CollisionObject(_prism(list(outline), height)))
            self._held_points.append(np.array(outline).T)
        self._held_radius = [float(np.hypot(*p).max()) for p in self._held_points]
        self._disk_shape = coal.Cylinder(self.model.robot_radius(), self.model.robot_height)
        self._disk = coal.CollisionObject(self._disk_shape)
        self._disks: dict[float, coal.CollisionObject] = {}
        self._objects: list[coal.CollisionObject] = []
        #: the static obstacles added (:meth:`add_obstacle`); from :meth:`from_scene`, the
        #: scene's obstacles with touching boxes merged
        self.obstacles: list[Obstacle] = []
        self._manager = coal.DynamicAABBTreeCollisionManager()
        self._near: NearPieces | None = None  # made at the first query (many pieces)
        self._dcb = coal.DistanceCallBackDefault()
        self._dresult = self._dcb.data.result  # one wrapper of the callback's result, kept
        self._ccb = coal.CollisionCallBackDefault()
        self._req = coal.DistanceRequest()
        self._res = coal.DistanceResult()
        self.queries = 0

    @classmethod
    def from_scene(cls, scene: Scene, *, clearance: float = KEEP_CLEARANCE,
                   should_stop: Callable[[], bool] | None = None) -> CollisionWorld:
        """Build the world of a scene (bodies keep ``clearance`` m from obstacles).

        The world holds the scene's obstacles with touching boxes merged
        (:func:`~pivot_ompl.validity.merge.merge_boxes`: the same floor in fewer pieces, so a
        query near a wall cut into many boxes meets one): :attr:`obstacles` is that list, not
        ``scene.obstacles`` (whose indices reports name). Distances to the free side are the
        same either way; a penetration depth may be deeper in a merged box.

        Raises:
            Interrupted: ``should_stop()`` became true (polled while the boxes are merged,
                before every obstacle and while a polygon is built, :func:`obstacle_objects`).
        """
        world = cls(scene.model, scene.bounds, clearance)
        for o in merge_boxes(scene.obstacles, should_stop=should_stop):
            if should_stop is not None and should_stop():
                raise Interrupted("building the collision world")
            world.add_obstacle(o, should_stop)
        world.setup()
        return world

    def add_obstacle(self, obstacle: Obstacle,
                     should_stop: Callable[[], bool] | None = None) -> None:
        """Add a static obstacle (call :meth:`setup` after the last one).

        Raises:
            Interrupted: ``should_stop()`` became true (:func:`obstacle_objects`, then every
                :data:`POLL_TRIANGLES` objects registered); the world is then incomplete.
        """
        objects = obstacle_objects(obstacle, should_stop)
        self.obstacles.append(obstacle)
        self._near = None
        for i, obj in enumerate(objects):
            if should_stop is not None and i % POLL_TRIANGLES == POLL_TRIANGLES - 1 \
                    and should_stop():
                raise Interrupted("registering an obstacle's pieces")
            self._objects.append(obj)
            self._manager.registerObject(obj)

    def setup(self) -> None:
        """Build the broad-phase tree."""
        self._manager.setup()
        self._near = None

    @property
    def has_obstacles(self) -> bool:
        """Whether the world holds any obstacle."""
        return bool(self._objects)

    # -- queries -----------------------------------------------------------------------
    def _distance(self, obj: coal.CollisionObject, x: float, y: float, radius: float) -> float:
        """``obj``'s distance less the clearance; it lies within ``radius`` of ``(x, y)``."""
        self.queries += 1
        if not self._objects:
            return math.inf
        obj.computeAABB()
        if len(self._objects) >= NEAR_FROM:
            if self._near is None:
                self._near = NearPieces(self._objects)
            return self._near.distance(obj, self._manager, x, y, radius) - self.clearance
        result = self._dresult
        result.clear()
        self._manager.distance(obj, self._dcb)
        return result.min_distance - self.clearance

    def box_distance(self, obj: Pose) -> float:
        """Distance (m) from the box at object pose ``obj`` to the nearest obstacle (<= 0: hit)."""
        place(self._box, obj[0], obj[1], obj[2], 0.5 * self.model.object_size[2])
        return self._distance(self._box, obj[0], obj[1], self._box_radius)

    def robot_distance(self, robot: Pose) -> float:
        """Distance (m) from the walking robot at ``robot`` to the nearest obstacle.

        Its body: :meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`.
        """
        self._robot.setTransform(self._robot_transform(robot))
        a = self._robot_ahead
        return self._distance(self._robot, robot[0] + a * math.cos(robot[2]),
                              robot[1] + a * math.sin(robot[2]), math.hypot(*self._robot_half))

    def _robot_transform(self, robot: Pose) -> coal.Transform3s:
        a = self._robot_ahead
        return placement(robot[0] + a * math.cos(robot[2]), robot[1] + a * math.sin(robot[2]),
                          robot[2], 0.5 * self.model.robot_height)

    def held_distance(self, robot: Pose, grasp: int) -> float:
        """Distance (m) from the robot holding the box at ``grasp`` to the nearest obstacle.

        The robot stands at ``robot``; its body covers the arms and the inclined box's
        overhang (the box itself is :meth:`box_distance`); <= 0: hit.
        """
        obj = self._held[grasp]
        place(obj, robot[0], robot[1], robot[2], 0.0)
        return self._distance(obj, robot[0], robot[1], self._held_radius[grasp])

    def robot_box_distance(self, robot: Pose, obj: Pose) -> float:
        """Distance (m) between the robot at ``robot`` and the resting box at ``obj``."""
        self.queries += 1
        self._res.clear()
        return coal.distance(self._robot_shape, self._robot_transform(robot),
                             self._box_shape,
                             placement(obj[0], obj[1], obj[2], 0.5 * self.model.object_size[2]),
                             self._req, self._res)

    def turning_disk_distance(self, x: float, y: float) -> float:
        """Clearance (m) to the obstacles of the disk the robot sweeps turning in place.

        The disk is centred at ``(x, y)``.
        """
        self._disk.setTransform(placement(x, y, 0.0, 0.5 * self.model.robot_height))
        return self._distance(self._disk, x, y, self._robot_radius)

    def turning_disk_box_distance(self, x: float, y: float, obj: Pose) -> float:
        """Clearance (m) between that disk and the box resting at object pose ``obj``."""
        self.queries += 1
        self._res.clear()
        return coal.distance(self._disk_shape, placement(x, y, 0.0, 0.5 * self.model.robot_height),
                             self._box_shape,
                             placement(obj[0], obj[1], obj[2], 0.5 * self.model.object_size[2]),
                             self._req, self._res)

    def disk_distance(self, x: float, y: float, radius: float) -> float:
        """Clearance (m) to the obstacles of a vertical cylinder of ``radius`` at ``(x, y)``.

        The cylinder is as high as the robot: e.g. the disk inscribed in its footprint.
        """
        obj = self._disks.get(radius)
        if obj is None:
            obj = coal.CollisionObject(coal.Cylinder(radius, self.model.robot_height))
            self._disks[radius] = obj
        obj.setTransform(placement(x, y, 0.0, 0.5 * self.model.robot_height))
        return self._distance(obj, x, y, radius)

    # -- bounds ------------------------------------------------------------------------
    def bounds_margin(self, corners: list[tuple[float, float]]) -> float:
        """Smallest distance (m) of the corners to the bounds' sides (< 0: outside)."""
        x0, y0, x1, y1 = self.bounds
        return min(min(x - x0, x1 - x, y - y0, y1 - y) for x, y in corners)

    def robot_bounds_margin(self, robot: Pose) -> float:
        """:meth:`bounds_margin` of the walking body's corners at ``robot``, in closed form.

        The body is a rectangle: its corners reach ``L |cos| + W |sin|`` along x and
        ``L |sin| + W |cos|`` along y from its centre (half-length ``L``, half-width ``W``).
        """
        c, s = math.cos(robot[2]), math.sin(robot[2])
        a = self._robot_ahead
        cx, cy = robot[0] + a * c, robot[1] + a * s
        half_l, half_w = self._robot_half
        ex = half_l * abs(c) + half_w * abs(s)
        ey = half_l * abs(s) + half_w * abs(c)
        x0, y0, x1, y1 = self.bounds
        return min(cx - ex - x0, x1 - cx - ex, cy - ey - y0, y1 - cy - ey)

    def _inside(self, pose: Pose, half_diagonal: float) -> bool:
        """Quick accept: the circumscribed disk of a footprint lies inside the bounds."""
        x0, y0, x1, y1 = self.bounds
        return (x0 + half_diagonal <= pose[0] <= x1 - half_diagonal
                and y0 + half_diagonal <= pose[1] <= y1 - half_diagonal)

    def box_in_bounds(self, obj: Pose) -> bool:
        """Whether the box footprint at ``obj`` lies inside the bounds."""
        if self._inside(obj, self._box_radius):
            return True
        return self.bounds_margin(self.model.object_corners(obj)) >= 0.0

    def held_in_bounds(self, robot: Pose, grasp: int) -> bool:
        """Whether the holding robot's body (see :meth:`held_distance`) lies inside the bounds."""
        if self._inside(robot, self._held_radius[grasp]):
            return True
        c, s = math.cos(robot[2]), math.sin(robot[2])
        px, py = self._held_points[grasp]
        x, y = robot[0] + c * px - s * py, robot[1] + s * px + c * py
        x0, y0, x1, y1 = self.bounds
        return bool(min((x - x0).min(), (x1 - x).min(),
                        (y - y0).min(), (y1 - y).min()) >= 0.0)

    def robot_in_bounds(self, robot: Pose) -> bool:
        """Whether the walking body at ``robot`` lies inside the bounds."""
        if self._inside(robot, self._robot_radius):
            return True
        return self.robot_bounds_margin(robot) >= 0.0

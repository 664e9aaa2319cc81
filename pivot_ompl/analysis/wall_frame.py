"""The raster relaxations computed in the walls' frame: a turned floor costs what a square one does.

The raster covers (:mod:`~pivot_ompl.analysis.raster_cover`) lay their cells over the scene's
bounds, an axis-aligned rectangle. A row of rooms turned by an angle in the world fills only a
thin diagonal band of that rectangle: the cells grow with the square of the row's length
(a 32-room row turned by 40 deg: 11 500 m² of bounds, 1 400 m² in the walls' frame), and the
coarser cells a large floor gets lose the row's narrow passages. So the relaxations run on the
scene turned to its walls (:func:`~pivot_ompl.scene.walls.wall_yaw`, as the walk lattice is:
:mod:`pivot_ompl.transit.frame`) and cut to where its box can be (:func:`relaxed_scene`).
For the transfer lattice (``facing``), the walls' direction is that of the faces that look
onto the free floor (the floor's pieces holding the start or the goal), weighed by their
length there: the outer faces of walls round the floor, and walls shut off from it, do not
count. So a turned or reflected copy of a floor (which keeps its old floor as four long walls
round it) takes the direction the floor's own walls give the original, up to a quarter turn:
the walls that shape its routes. The relaxations keep every edge's direction (their bounds
on such copies are as strong in the old floor's frame: ``gen:walls:3``'s copies prove 3
regrasps there, 1 in the inner walls').

**Still a relaxation of every plan.** Turning the floor, its obstacles, start and goal together
is a rigid motion: every plan of the scene turned is a plan of the turned scene. The turned
scene's bounds cannot be the old rectangle (it is turned too), so:

* the old bounds become four walls just outside them (:data:`BOUND_WALL` thick, the checkers'
  clearance away: a body inside the bounds keeps that clearance from them), turned;
* the new bounds hold every body of every plan: in every state of a plan the box's centre lies
  inside the bounds and at least half the box's short side from every obstacle (the box
  around it overlaps none), so outside every obstacle grown by :data:`GROW`, and moves
  continuously, so it stays in the connected piece of the free floor (the bounds less the
  obstacles' pieces, subsets of the obstacles, grown by :data:`GROW`) holding the start (or
  the goal), and every body lies within the assembly's reach of it. The new bounds are the
  turned pieces' box grown by that reach, :data:`MARGIN` and :data:`GROW`.

Nothing a plan does is cut, so every bound computed there is one of the scene's (the route
length and the regrasps are the same in any frame), and a place found there (where the held
box cannot turn) is turned back. A floor whose walls run along the world's axes, or whose turned
box is not smaller than its bounds (:data:`WORTH`), is relaxed as it is. Callers:
:func:`~pivot_ompl.analysis.bound_cache.lower_bound` (the regrasp and route bounds) and
:class:`~pivot_ompl.analysis.late_proof.LateProof` (the raster's place to turn).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from pivot_ompl.analysis.bound_levels import CELLS
from pivot_ompl.analysis.raster_cover import floor_raster
from pivot_ompl.analysis.regrasp_bound import held_bodies
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, Obstacle, Scene
from pivot_ompl.scene.shared import scene_shared
from pivot_ompl.scene.walls import turned_obstacle, wall_yaw
from pivot_ompl.se2 import rotate_about
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

log = logging.getLogger(__name__)

#: Thickness (m) of the walls standing for the old bounds in the turned scene.
BOUND_WALL = 0.5
#: Margin (m) of the turned scene's bounds beyond the assembly's reach round the free floor.
MARGIN = 0.5
#: The turned scene is relaxed when its bounds' area is at most this share of the scene's (a
#: smaller floor gets finer levels within the same estimated time: not worth it for a little).
WORTH = 0.5
#: Obstacle pieces beyond which no frame is tried (the free floor's union costs about 0.1 s
#: per thousand pieces: at most about 2 s, the stop asked every :data:`UNION_CHUNK` pieces).
MAX_PIECES = 20_000
#: Obstacle pieces united by one GEOS call (not polled: about 0.1 s) when the free floor is found.
UNION_CHUNK = 1000
#: A box is square to the frame's axes when ``|sin 2 yaw|`` is below this.
AXIS = 1e-6
#: Obstacles are grown by this much (m; at most a tenth of the box's short side) before the
#: free floor's pieces are found: walls that touch edge to edge or at a corner close the floor
#: between them even where rounding (a turned scene's) leaves them a hair apart. Sound: the
#: box's centre stays half the box's short side from every obstacle, farther than this (and
#: than the mitred corners, at most five times this).
GROW = 1e-3
#: Points along each wall edge at which :func:`wall_frame` asks whether it borders the free floor.
FACE_SAMPLES = 8


@dataclass(frozen=True)
class WallFrame:
    """A scene turned by ``-yaw`` about ``centre`` and cut to its free floor (module docstring).

    Attributes:
        yaw: the walls' direction in the scene (rad).
        centre: the point turned about (the scene's bounds' centre).
        scene: the turned scene (its own bounds, the old bounds as walls).
    """

    yaw: float
    centre: tuple[float, float]
    scene: Scene

    def point_out(self, p: tuple[float, float]) -> tuple[float, float]:
        """A point of the turned scene, in the scene."""
        x, y, _ = rotate_about((p[0], p[1], 0.0), self.centre, self.yaw)
        return x, y

    def point_in(self, p: tuple[float, float]) -> tuple[float, float]:
        """A point of the scene, in the turned scene (:meth:`point_out`'s inverse)."""
        x, y, _ = rotate_about((p[0], p[1], 0.0), self.centre, -self.yaw)
        return x, y

    def arc_out(self, arc: tuple[float, float]) -> tuple[float, float]:
        """An arc of yaws (degrees, ``low <= high``) of the turned scene, in the scene."""
        low, high = arc
        if high - low >= 360.0:
            return low, high
        d = math.degrees(self.yaw)
        shift = 360.0 * math.floor((low + d + 180.0) / 360.0)  # low back in [-180, 180)
        return low + d - shift, high + d - shift


def wall_frame(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
               should_stop: Callable[[], bool] | None = None, worth: float | None = None,
               floor_grid: float | None = None, facing: bool = False) -> WallFrame | None:
    """The scene turned to its walls and cut to its free floor, when that is worth it.

    The direction: the walls' (:func:`~pivot_ompl.scene.walls.wall_yaw`); with ``facing``,
    counting each edge's share that borders the free floor (module docstring). ``None`` when
    the walls (all their edges, or those counted) run along the axes, when the turned scene's
    bounds are not smaller than ``worth`` (default :data:`WORTH`) of the scene's, when the
    scene has over :data:`MAX_PIECES` obstacle pieces, or when ``should_stop`` said stop.
    ``clearance``: what the checkers keep every body from the obstacles (m; the old bounds'
    walls stand that far out). ``floor_grid``: a grid spacing (m); the turned bounds' lower
    corner then lies a whole number of it below the free floor's (a floor drawn in the walls'
    frame has its bounds' corner there: a grid from it is the one the floor's own would be);
    default: the corner aligned to the raster's cells (most wall edges on cell edges).
    """
    yaw = wall_yaw(scene.obstacles)
    if yaw == 0.0:
        return None
    x0, y0, x1, y1 = scene.bounds
    centre = (0.5 * (x0 + x1), 0.5 * (y0 + y1))
    floor = _free_floor(scene, should_stop)
    if floor is None:
        return None
    if facing:
        faced = walls_facing(scene, should_stop)
        if not faced:  # along the axes, or stopped
            return None
        yaw = faced
    reach = _reach(scene)
    if floor_grid is not None:  # the grid's lines through the free floor's corner
        reach = floor_grid * math.ceil(reach / floor_grid)
    bounds = _turned_box(scene, floor, yaw, centre, reach)
    area = (bounds[2] - bounds[0]) * (bounds[3] - bounds[1])
    if area > (WORTH if worth is None else worth) * (x1 - x0) * (y1 - y0):
        return None
    obstacles = tuple(turned_obstacle(o, -yaw, centre) for o in scene.obstacles)
    if floor_grid is None:
        bounds = _aligned(bounds, obstacles, floor_raster(bounds, CELLS[0]).cell)
    t, k = BOUND_WALL, clearance
    w, h = x1 - x0, y1 - y0
    walls = [BoxObstacle((centre[0], y0 - k - 0.5 * t), (w + 2 * (t + k), t), 0.0, 2.0),
             BoxObstacle((centre[0], y1 + k + 0.5 * t), (w + 2 * (t + k), t), 0.0, 2.0),
             BoxObstacle((x0 - k - 0.5 * t, centre[1]), (t, h + 2 * (t + k)), 0.0, 2.0),
             BoxObstacle((x1 + k + 0.5 * t, centre[1]), (t, h + 2 * (t + k)), 0.0, 2.0)]
    turned = dataclasses.replace(
        scene, bounds=bounds,
        obstacles=obstacles + tuple(turned_obstacle(o, -yaw, centre) for o in walls),
        start=rotate_about(scene.start, centre, -yaw), goal=rotate_about(scene.goal, centre, -yaw))
    log.debug("walls' frame: turned %.2f deg, bounds %.0f -> %.0f m2", math.degrees(yaw),
              w * h, area)
    return WallFrame(yaw, centre, turned)


def floor_bounds(scene: Scene, yaw: float, centre: tuple[float, float], *,
                 should_stop: Callable[[], bool] | None = None
                 ) -> tuple[float, float, float, float] | None:
    """Where every body of a plan lies in the scene turned by ``-yaw`` about ``centre`` (m).

    The box round the free floor's pieces holding the start or the goal, turned, grown by
    the held assembly's reach and :data:`MARGIN` (the new bounds of :func:`wall_frame`,
    whatever their area); ``None`` where the free floor is not found (or stopped).
    """
    floor = _free_floor(scene, should_stop)
    return None if floor is None else _turned_box(scene, floor, yaw, centre, _reach(scene))


def _reach(scene: Scene) -> float:
    """The held assembly's reach round the box's centre, and :data:`MARGIN` (m)."""
    return max(p.reach for g in (0, 1) for p in held_bodies(scene, g)) + MARGIN


def _turned_box(scene: Scene, floor: shapely.Geometry, yaw: float, centre: tuple[float, float],
                reach: float) -> tuple[float, float, float, float]:
    """The box round ``floor`` turned by ``-yaw`` about ``centre``, grown by ``reach`` (m)."""
    pts = shapely.get_coordinates(floor)
    c, s = math.cos(-yaw), math.sin(-yaw)
    dx, dy = pts[:, 0] - centre[0], pts[:, 1] - centre[1]
    tx, ty = centre[0] + c * dx - s * dy, centre[1] + s * dx + c * dy
    # the floor found lies GROW inside the obstacles' faces: its box grown back by that
    g = _grow(scene) + reach
    return (float(tx.min()) - g, float(ty.min()) - g, float(tx.max()) + g, float(ty.max()) + g)


def facing_yaw(scene: Scene, *, should_stop: Callable[[], bool] | None = None) -> float | None:
    """The direction of the walls that face the free floor, as :func:`wall_frame` takes it.

    Exactly 0.0 where all the walls' edges run along the axes (nothing computed); ``None``
    where the free floor is not found (over :data:`MAX_PIECES` pieces, or stopped): the
    caller keeps the direction of all the edges.
    """
    if wall_yaw(scene.obstacles) == 0.0:
        return 0.0
    floor = _free_floor(scene, should_stop)
    return None if floor is None else _facing_yaw(scene, floor)


def walls_facing(scene: Scene, should_stop: Callable[[], bool] | None = None) -> float | None:
    """:func:`facing_yaw` of ``scene``, computed once per scene geometry in the process."""
    return scene_shared(scene, ("walls facing",),
                        lambda: facing_yaw(scene, should_stop=should_stop))


def relaxed_scene(scene: Scene, *, should_stop: Callable[[], bool] | None = None) -> Scene:
    """The scene the raster relaxations run on: :func:`wall_frame`'s, else ``scene`` itself."""
    frame = wall_frame(scene, should_stop=should_stop)
    return scene if frame is None else frame.scene


def _aligned(bounds: tuple[float, float, float, float], obstacles: tuple[Obstacle, ...],
             cell: float) -> tuple[float, float, float, float]:
    """``bounds`` grown by less than ``cell`` so that most wall edges lie on cell edges.

    The raster's cells start at the bounds' lower corner; a wall whose edges fall between
    cell edges loses a row of wholly covered cells, and the passage beside it looks a cell
    wider. Per axis, the edges of the boxes square to the axes are weighed by their length;
    the corner moves down to the residue (modulo ``cell``) most length has.
    """
    weights: list[dict[float, float]] = [{}, {}]
    for o in obstacles:
        if not isinstance(o, BoxObstacle) or abs(math.sin(2.0 * o.yaw)) > AXIS:
            continue
        across = abs(math.cos(o.yaw)) < 0.5  # turned a quarter: its sides swap axes
        size = (o.size[1], o.size[0]) if across else o.size
        for axis in (0, 1):
            length = size[1 - axis]
            for edge in (o.center[axis] - 0.5 * size[axis], o.center[axis] + 0.5 * size[axis]):
                key = round(edge % cell, 7) % round(cell, 7)
                weights[axis][key] = weights[axis].get(key, 0.0) + length
    low = []
    for axis in (0, 1):
        start = bounds[axis]
        if weights[axis]:
            r = max(weights[axis], key=lambda k: weights[axis][k])
            start = r + cell * math.floor((start - r) / cell)
        low.append(start)
    return (low[0], low[1], bounds[2], bounds[3])


def _free_floor(scene: Scene, should_stop: Callable[[], bool] | None
                ) -> shapely.Geometry | None:
    """The pieces of the free floor holding the start or the goal (``None``: none, or stopped).

    Computed once per scene geometry in the process (the checker's walls, the lattice's
    frame and the route field's frame ask it of the same scene).
    """
    return scene_shared(scene, ("free floor",), lambda: _floor(scene, should_stop))


def _floor(scene: Scene, should_stop: Callable[[], bool] | None) -> shapely.Geometry | None:
    """:func:`_free_floor`, computed."""
    try:
        pieces = obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))
    except Interrupted:
        return None
    if len(pieces) > MAX_PIECES or (should_stop is not None and should_stop()):
        return None
    grown = shapely.buffer([shapely.Polygon(p) for p in pieces], _grow(scene),
                           join_style="mitre")
    parts = []
    for i in range(0, len(grown), UNION_CHUNK):
        parts.append(shapely.union_all(grown[i:i + UNION_CHUNK]))
        if should_stop is not None and should_stop():
            return None
    solid = shapely.union_all(parts)
    free = shapely.box(*scene.bounds).difference(solid)
    ends = shapely.points([scene.start[:2], scene.goal[:2]])
    kept = [g for g in getattr(free, "geoms", [free])
            if not g.is_empty and shapely.intersects(g, ends).any()]
    return shapely.MultiPolygon(kept) if kept else None


def _facing_yaw(scene: Scene, floor: shapely.Geometry) -> float:
    """The walls' direction counting each edge's share that borders ``floor``."""
    return wall_yaw(scene.obstacles, facing=_facing(floor, 2.0 * _grow(scene)))


def _facing(floor: shapely.Geometry, off: float) -> Callable[[np.ndarray], np.ndarray]:
    """The share of each edge ``(n, 4)`` that borders ``floor`` (:func:`wall_frame`'s weights).

    Sampled at :data:`FACE_SAMPLES` points along the edge, each ``off`` (m) to either side:
    a point counts where either lies on the floor. The faces of a wall that look onto the
    free floor count, not those outside it (the far faces of a turned copy's old bounds).
    """
    shapely.prepare(floor)

    def share(e: np.ndarray) -> np.ndarray:
        d = e[:, 2:4] - e[:, 0:2]
        length = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)
        normal = np.column_stack([-d[:, 1], d[:, 0]]) / length[:, None]
        t = (np.arange(FACE_SAMPLES) + 0.5) / FACE_SAMPLES
        pts = e[:, None, 0:2] + t[None, :, None] * d[:, None, :]  # (n, k, 2)
        seen = np.zeros(pts.shape[:2], dtype=bool)
        for side in (-1.0, 1.0):
            q = pts + side * off * normal[:, None, :]
            seen |= shapely.contains_xy(floor, q[..., 0], q[..., 1])
        return seen.mean(axis=1)

    return share


def _grow(scene: Scene) -> float:
    """How much (m) the obstacles are grown when the free floor is found (:data:`GROW`)."""
    return min(GROW, 0.1 * min(scene.model.object_size[0], scene.model.object_size[1]))

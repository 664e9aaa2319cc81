"""The walk lattice's frame: turned to the floor's walls, so corridors lie along its axes.

The lattice's headings and grid are exact along its own axes: a side step square to a
heading ends on a grid position. A corridor 1-3 cm wider than the walking body is walked
by side-stepping along its axis with the body square to it (0.6 m deep across 0.87-0.89 m),
and only a heading within a few degrees of square to the corridor fits its doors: on a floor
turned by an angle off the lattice's 16 headings no such walk exists on the lattice. So the
walk planner plans in a frame turned to the walls (:func:`~pivot_ompl.scene.walls.wall_yaw`:
the direction, modulo a quarter turn, that the obstacles' straight edges take most, weighted
by their length) and
maps its walks back (:class:`LatticeFrame`); the walks are certified again against the
scene's own obstacles and bounds, so the frame's rounding never reaches a plan.

A floor whose walls run along the world's axes has frame yaw exactly 0: nothing is turned.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, Obstacle
from pivot_ompl.scene.walls import turned_obstacle, wall_yaw
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.assembly_field import least_boxes
from pivot_ompl.validity.cell_stencil import grid_origin
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_pieces

#: Thickness (m) of the walls that stand for the scene's bounds in the turned frame.
BOUND_WALL = 0.5


@dataclass(frozen=True)
class LatticeFrame:
    """A turn of the floor by ``-yaw`` about ``centre``: the lattice's view of the scene.

    Yaws are shifted without wrapping, so a walk mapped in and back keeps its yaws continuous.
    """

    yaw: float
    centre: tuple[float, float]

    @property
    def identity(self) -> bool:
        """Nothing is turned."""
        return self.yaw == 0.0

    def _turn(self, p: Pose, angle: float) -> Pose:
        c, s = math.cos(angle), math.sin(angle)
        dx, dy = p[0] - self.centre[0], p[1] - self.centre[1]
        return (self.centre[0] + c * dx - s * dy, self.centre[1] + s * dx + c * dy, p[2] + angle)

    def into(self, p: Pose) -> Pose:
        """A scene pose in the lattice's frame."""
        return self._turn(p, -self.yaw)

    def out(self, p: Pose) -> Pose:
        """A pose of the lattice's frame in the scene."""
        return self._turn(p, self.yaw)

    def obstacle(self, o: Obstacle) -> Obstacle:
        """``o`` in the lattice's frame."""
        return turned_obstacle(o, -self.yaw, self.centre)

    def world(self, world: CollisionWorld, should_stop: Callable[[], bool] | None = None, *,
              within: tuple[float, float, float, float] | None = None) -> CollisionWorld:
        """``world`` in the lattice's frame: its obstacles turned, its bounds four walls.

        The walls stand just outside the bounds (as far out as the world's kept clearance),
        so the walking body keeps from them what it keeps from the bounds; the frame's
        bounds hold them, cut to ``within`` (m, in this frame) where given: where the
        walking body may be (walks are certified in the scene, so the cut only narrows
        what is searched).

        Raises:
            Interrupted: ``should_stop()`` became true (polled before every obstacle).
        """
        x0, y0, x1, y1 = world.bounds
        t, k = BOUND_WALL, world.clearance
        cx, cy, w, h = 0.5 * (x0 + x1), 0.5 * (y0 + y1), x1 - x0, y1 - y0
        walls = [BoxObstacle((cx, y0 - k - 0.5 * t), (w + 2 * (t + k), t), 0.0, 2.0),
                 BoxObstacle((cx, y1 + k + 0.5 * t), (w + 2 * (t + k), t), 0.0, 2.0),
                 BoxObstacle((x0 - k - 0.5 * t, cy), (t, h + 2 * (t + k)), 0.0, 2.0),
                 BoxObstacle((x1 + k + 0.5 * t, cy), (t, h + 2 * (t + k)), 0.0, 2.0)]
        corners = [self.into((x, y, 0.0)) for x in (x0 - t - k, x1 + t + k)
                   for y in (y0 - t - k, y1 + t + k)]
        xs, ys = [c[0] for c in corners], [c[1] for c in corners]
        turned = []
        for o in [*world.obstacles, *walls]:
            if should_stop is not None and should_stop():
                raise Interrupted("turning the floor to the walk lattice's frame")
            turned.append(self.obstacle(o))
        box = (min(xs), min(ys), max(xs), max(ys))
        if within is not None:
            box = (max(box[0], within[0]), max(box[1], within[1]),
                   min(box[2], within[2]), min(box[3], within[3]))
        low = _on_grid((box[0], box[1]), turned)
        out = CollisionWorld(world.model, (*low, box[2], box[3]), world.clearance)
        for o in turned:
            if should_stop is not None and should_stop():
                raise Interrupted("turning the floor to the walk lattice's frame")
            out.add_obstacle(o, should_stop)
        out.setup()
        return out


def _on_grid(low: tuple[float, float], obstacles: list[Obstacle]) -> tuple[float, float]:
    """``low`` moved down onto the lines of the map grid the turned boxes lie on, if any.

    A map turned by its own angle has its boxes on a grid in this frame, but not through
    the frame's corner: a floor grid from a corner on its lines meets them by a stencil's
    dilation (:func:`~pivot_ompl.validity.cell_stencil.cell_dilation`) instead of a sum
    per box. The bounds only grow (by less than a cell).
    """
    grid = grid_origin(obstacle_pieces(obstacles), least=least_boxes(1))
    if grid is None:
        return low
    origin, cell = grid
    return (origin[0] + cell * math.floor((low[0] - origin[0]) / cell),
            origin[1] + cell * math.floor((low[1] - origin[1]) / cell))


def frame_of(world: CollisionWorld, *, yaw: float | None = None) -> LatticeFrame:
    """The lattice frame of ``world``: turned to its walls, about its bounds' centre.

    ``yaw``: the walls' direction when the caller knows it better (the walls facing the free
    floor: :func:`~pivot_ompl.analysis.wall_frame.facing_yaw`); default: that of all their
    edges (:func:`~pivot_ompl.scene.walls.wall_yaw`).
    """
    b = world.bounds
    return LatticeFrame(wall_yaw(world.obstacles) if yaw is None else yaw,
                        (0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])))

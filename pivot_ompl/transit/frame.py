"""The walk lattice's frame: turned to the floor's walls, so corridors lie along its axes.

The lattice's headings and grid are exact along its own axes: a side step square to a
heading ends on a grid position. A corridor 1-3 cm wider than the walking body is walked
by side-stepping along its axis with the body square to it (0.6 m deep across 0.87-0.89 m),
and only a heading within a few degrees of square to the corridor fits its doors: on a floor
turned by an angle off the lattice's 16 headings no such walk exists on the lattice. So the
walk planner plans in a frame turned to the walls (:func:`wall_yaw`: the direction, modulo a
quarter turn, that the obstacles' straight edges take most, weighted by their length) and
maps its walks back (:class:`LatticeFrame`); the walks are certified again against the
scene's own obstacles and bounds, so the frame's rounding never reaches a plan.

A floor whose walls run along the world's axes has frame yaw exactly 0: nothing is turned.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, PolygonObstacle
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.collision import CollisionWorld

#: Width (rad) of the bins in which edge directions are summed (0.5 deg).
BIN = math.radians(0.5)
#: A dominant direction closer than this (rad) to the world's axes is taken as 0.
AXIS_TOLERANCE = 1e-9
#: Thickness (m) of the walls that stand for the scene's bounds in the turned frame.
BOUND_WALL = 0.5


def _edges(o: Obstacle) -> Iterable[tuple[float, float]]:
    """``(direction, length)`` of the obstacle's straight edges (none for a cylinder)."""
    if isinstance(o, BoxObstacle):
        yield o.yaw, 2.0 * o.size[0]
        yield o.yaw + 0.5 * math.pi, 2.0 * o.size[1]
    elif isinstance(o, PolygonObstacle):
        pts = o.points
        for (ax, ay), (bx, by) in zip(pts, pts[1:] + pts[:1], strict=True):
            length = math.hypot(bx - ax, by - ay)
            if length > 0.0:
                yield math.atan2(by - ay, bx - ax), length


def wall_yaw(obstacles: Iterable[Obstacle]) -> float:
    """The walls' direction modulo a quarter turn, in ``[-pi/4, pi/4)`` (rad).

    Edge directions (modulo pi/2) are summed by length in bins of :data:`BIN`; of the edges
    in the heaviest bin and its neighbours, the direction most length takes (to 1e-6 rad:
    parallel walls, to rounding) is the answer.
    Exactly 0.0 when that is within :data:`AXIS_TOLERANCE` of the axes, and for a floor
    without straight edges.
    """
    quarter = 0.5 * math.pi
    dirs, weights = [], []
    for o in obstacles:
        for d, w in _edges(o):
            dirs.append(d % quarter)
            weights.append(w)
    if not dirs:
        return 0.0
    a, wt = np.asarray(dirs), np.asarray(weights)
    n = round(quarter / BIN)
    bins = np.minimum((a / BIN).astype(int), n - 1)
    hist = np.bincount(bins, weights=wt, minlength=n)
    best = int(np.argmax(hist))
    near = np.isin(bins, [(best - 1) % n, best, (best + 1) % n])
    # of those, the direction most length takes exactly (parallel walls to rounding)
    exact: dict[float, float] = {}
    for d, w in zip(a[near].tolist(), wt[near].tolist(), strict=True):
        key = round(d, 7) % round(quarter, 7)
        exact[key] = exact.get(key, 0.0) + w
    top = max(exact, key=lambda k: exact[k])
    mask = near & (np.abs(((a - top + 0.25 * quarter) % quarter) - 0.25 * quarter) < 1e-6)
    z = np.sum(wt[mask] * np.exp(4j * a[mask]))  # a quarter turn is a full turn of 4 a
    yaw = float(np.angle(z)) / 4.0
    yaw = (yaw + 0.25 * math.pi) % quarter - 0.25 * math.pi
    return 0.0 if abs(yaw) < AXIS_TOLERANCE else yaw


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
        if isinstance(o, BoxObstacle):
            x, y, yaw = self.into((o.center[0], o.center[1], o.yaw))
            return BoxObstacle((x, y), o.size, yaw, o.height)
        if isinstance(o, CylinderObstacle):
            x, y, _ = self.into((o.center[0], o.center[1], 0.0))
            return CylinderObstacle((x, y), o.radius, o.height)
        return PolygonObstacle(tuple(self.into((px, py, 0.0))[:2] for px, py in o.points),
                               o.height)

    def world(self, world: CollisionWorld, should_stop: Callable[[], bool] | None = None
              ) -> CollisionWorld:
        """``world`` in the lattice's frame: its obstacles turned, its bounds four walls.

        The walls stand just outside the bounds (as far out as the world's kept clearance),
        so the walking body keeps from them what it keeps from the bounds; the frame's
        bounds hold them.

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
        out = CollisionWorld(world.model, (min(xs), min(ys), max(xs), max(ys)), world.clearance)
        for o in [*world.obstacles, *walls]:
            if should_stop is not None and should_stop():
                raise Interrupted("turning the floor to the walk lattice's frame")
            out.add_obstacle(self.obstacle(o), should_stop)
        out.setup()
        return out


def frame_of(world: CollisionWorld) -> LatticeFrame:
    """The lattice frame of ``world``: turned to its walls, about its bounds' centre."""
    b = world.bounds
    return LatticeFrame(wall_yaw(world.obstacles), (0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])))

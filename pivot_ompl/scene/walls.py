"""The floor's walls: the direction they run in, and obstacles turned about a point.

Most floors are drawn square to their walls; a floor turned by some angle in the world (a map
read at a yaw, a generated building turned) has its corridors off the world's axes. Planners
and relaxations that are exact along their own axes (the walk lattice, the raster covers of
the regrasp bound) turn the floor by :func:`wall_yaw` first (:func:`turned_obstacle`), so that
its corridors lie along their axes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

import numpy as np

from pivot_ompl.scene.model import BoxObstacle, CylinderObstacle, Obstacle, PolygonObstacle
from pivot_ompl.se2 import rotate_about

#: Width (rad) of the bins in which edge directions are summed (0.5 deg).
BIN = math.radians(0.5)
#: A dominant direction closer than this (rad) to the world's axes is taken as 0.
AXIS_TOLERANCE = 1e-9
#: An edge within this (rad) of a direction or square to it runs along it
#: (:func:`aligned_share`).
ALIGNED_TOLERANCE = math.radians(1.0)


def wall_edges(o: Obstacle) -> list[tuple[float, float, float, float, float]]:
    """The obstacle's straight edges ``(ax, ay, bx, by, direction)`` (m, rad; none for a cylinder).

    A box's edges run along its yaw and a quarter turn from it (exactly those directions).
    """
    if isinstance(o, BoxObstacle):
        c, s = math.cos(o.yaw), math.sin(o.yaw)
        hx, hy = 0.5 * o.size[0], 0.5 * o.size[1]
        pts = [(o.center[0] + c * u - s * v, o.center[1] + s * u + c * v)
               for u, v in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]
        dirs = [o.yaw, o.yaw + 0.5 * math.pi] * 2
        return [(*a, *b, d) for a, b, d in zip(pts, pts[1:] + pts[:1], dirs, strict=True)]
    if isinstance(o, PolygonObstacle):
        pts = list(o.points)
        return [(ax, ay, bx, by, math.atan2(by - ay, bx - ax))
                for (ax, ay), (bx, by) in zip(pts, pts[1:] + pts[:1], strict=True)
                if (ax, ay) != (bx, by)]
    return []


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


def wall_yaw(obstacles: Iterable[Obstacle],
             facing: Callable[[np.ndarray], np.ndarray] | None = None) -> float:
    """The walls' direction modulo a quarter turn, in ``[-pi/4, pi/4)`` (rad).

    Edge directions (modulo pi/2) are summed by length in bins of :data:`BIN`; of the edges
    in the heaviest bin and its neighbours, the direction most length takes (to 1e-6 rad:
    parallel walls, to rounding) is the answer. ``facing``: given the edges ``(n, 4)``
    (``ax, ay, bx, by``, m, :func:`wall_edges`), the share (0 to 1) of each that counts;
    default: all of every edge.
    Exactly 0.0 when that is within :data:`AXIS_TOLERANCE` of the axes, and for a floor
    without straight edges (or none that counts).
    """
    quarter = 0.5 * math.pi
    if facing is None:
        dirs, weights = [], []
        for o in obstacles:
            for d, w in _edges(o):
                dirs.append(d % quarter)
                weights.append(w)
        a, wt = np.asarray(dirs), np.asarray(weights)
    else:
        e = np.asarray([seg for o in obstacles for seg in wall_edges(o)], dtype=float)
        e = e.reshape(-1, 5)
        a = e[:, 4] % quarter
        wt = np.hypot(e[:, 2] - e[:, 0], e[:, 3] - e[:, 1]) * np.asarray(facing(e[:, :4]),
                                                                         dtype=float)
    if not np.any(wt > 0.0):
        return 0.0
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


def aligned_share(obstacles: Iterable[Obstacle], yaw: float, *,
                  tolerance: float = ALIGNED_TOLERANCE) -> float:
    """The share (0 to 1) of the straight edges' length that runs along ``yaw`` or square to it.

    Within ``tolerance`` (rad); 0.0 for a floor without straight edges.
    """
    quarter = 0.5 * math.pi
    total = along = 0.0
    for o in obstacles:
        for d, w in _edges(o):
            off = (d - yaw) % quarter
            total += w
            along += w if min(off, quarter - off) <= tolerance else 0.0
    return along / total if total > 0.0 else 0.0


def turned_obstacle(o: Obstacle, angle: float, about: tuple[float, float]) -> Obstacle:
    """``o`` turned by ``angle`` (rad, counter-clockwise) about the point ``about``."""
    if isinstance(o, BoxObstacle):
        x, y, yaw = rotate_about((o.center[0], o.center[1], o.yaw), about, angle)
        return BoxObstacle((x, y), o.size, yaw, o.height)
    if isinstance(o, CylinderObstacle):
        x, y, _ = rotate_about((o.center[0], o.center[1], 0.0), about, angle)
        return CylinderObstacle((x, y), o.radius, o.height)
    return PolygonObstacle(tuple(rotate_about((px, py, 0.0), about, angle)[:2]
                                 for px, py in o.points), o.height)

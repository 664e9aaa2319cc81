"""What the scene families share: building a scene, free rectangles to walls, retries."""

from __future__ import annotations

import numpy as np

from pivot_ompl.scene import BoxObstacle, Obstacle, Scene, scene_from_dict
from pivot_ompl.se2 import Pose

#: The box of the regrasp paper's Fig. 10 (m): its 0.4 m side passes slots the robot cannot.
BOX = (0.8, 0.4, 1.0)
#: Height of walls and baffles (m).
WALL_HEIGHT = 2.0
#: How far (m) the held face stays short of a slot's wall when the box is pushed into it: the
#: arms reach the grip points on the box's sides, so they must stay out of a tight slot
#: (the kept 1 cm plus 0.5 cm of margin).
HELD_FACE_BACK = 0.015


class Retry(Exception):  # noqa: N818 - a layout to draw again, never escapes generate()
    """A layout that does not hold: draw another."""


def make_scene(name: str, bounds: tuple[float, float, float, float], obstacles: list[Obstacle],
           start: Pose, goal: Pose) -> Scene:
    """A scene of the generated families' box and robot (HRP-2 defaults)."""
    doc = {"name": name, "bounds": list(bounds), "object": {"size": list(BOX)},
           "start": list(start), "goal": list(goal)}
    sc = scene_from_dict(doc, source="<generated>")
    return Scene(sc.name, sc.bounds, sc.model, sc.start, sc.goal, tuple(obstacles),
                 sc.alpha_max, sc.turning_radius, sc.robot_model, "")


def uniform(rng: np.random.Generator, r: tuple[float, float]) -> float:
    """A uniform draw in ``r`` (:class:`Retry` if it is empty)."""
    if r[1] < r[0]:
        raise Retry(f"empty range {r}")
    return float(rng.uniform(r[0], r[1]))


def free_complement(bounds: tuple[float, float, float, float],
                     free: list[tuple[float, float, float, float]]) -> list[Obstacle]:
    """Axis-aligned boxes covering ``bounds`` less the union of the ``free`` rectangles.

    The cells between the rectangles' coordinates are joined into runs along x, and a run
    into the one below it when both span the same x: a wall is one box per solid stretch,
    however many other rectangles' edges cross its height (otherwise a floor of N rooms
    holds of the order of N^2 pieces, each a slice of a wall).
    """
    xs = sorted({bounds[0], bounds[2], *(r[0] for r in free), *(r[2] for r in free)})
    ys = sorted({bounds[1], bounds[3], *(r[1] for r in free), *(r[3] for r in free)})
    boxes: list[tuple[float, float, float, float]] = []
    open_runs: dict[tuple[float, float], float] = {}  # x extent -> the y it starts at
    for j in range(len(ys) - 1):
        y0, y1 = ys[j], ys[j + 1]
        runs = set(_blocked_runs(xs, 0.5 * (y0 + y1), free))
        for xr in [r for r in open_runs if r not in runs]:
            boxes.append((xr[0], open_runs.pop(xr), xr[1], y0))
        for xr in runs:
            open_runs.setdefault(xr, y0)
    boxes += [(xr[0], ys0, xr[1], ys[-1]) for xr, ys0 in open_runs.items()]
    return [BoxObstacle((0.5 * (a + c), 0.5 * (b + d)), (c - a, d - b), 0.0, WALL_HEIGHT)
            for a, b, c, d in sorted(boxes, key=lambda r: (r[1], r[0]))]


def _blocked_runs(xs: list[float], cy: float,
                  free: list[tuple[float, float, float, float]]) -> list[tuple[float, float]]:
    """The x intervals of the cells at height ``cy`` that no ``free`` rectangle holds."""
    out: list[tuple[float, float]] = []
    run: float | None = None
    for i in range(len(xs)):
        blocked = False
        if i < len(xs) - 1:
            cx = 0.5 * (xs[i] + xs[i + 1])
            blocked = not any(r[0] <= cx <= r[2] and r[1] <= cy <= r[3] for r in free)
        if blocked and run is None:
            run = xs[i]
        elif not blocked and run is not None:
            out.append((run, xs[i]))
            run = None
    return out



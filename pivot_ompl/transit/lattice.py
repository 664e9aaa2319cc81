"""The walking robot's state lattice: headings, motion primitives and their costs.

States are ``(ix, iy, h)``: a floor grid position (spacing ``resolution``) and one of 16
headings. The headings are the directions of the 16 integer vectors
``(1, 0), (2, 1), (1, 1), (1, 2), (0, 1), ...`` (0, 26.6, 45, 63.4, 90 deg, ...), so a step
along a heading, or square to it, or against it, ends exactly on a grid position: walking
forward, sideways and backward are exact lattice motions. Primitives from heading ``h``:

* forward, one grid vector along ``h`` (0.14 to 0.22 m), keeping the heading or turning to
  the next heading either way while walking (the yaw changes linearly along the step);
* a side step left or right, and a back step, keeping the heading;
* a turn in place to the next heading either way.

Each primitive is a straight motion of the robot's centre with its yaw interpolated linearly:
exactly a segment of a ``pivot-plan/1`` walk. Costs (:func:`motion_cost`) are in metres of
forward walking (:class:`~pivot_ompl.scene.WalkParameters`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import GRID_HEADING_YAWS, GRID_HEADINGS, Pose, wrap_angle

#: Grid directions of the 16 headings (counter-clockwise from +x), their number and yaws.
HEADING_VECTORS, N_HEADINGS, HEADING_YAWS = GRID_HEADINGS, len(GRID_HEADINGS), GRID_HEADING_YAWS


def motion_cost(a: Pose, b: Pose, walk: WalkParameters) -> float:
    """Cost (m of forward walking) of the straight motion ``a -> b`` with linear yaw.

    The displacement is split, in the robot frame at the middle yaw, into its forward or
    backward part ``dx`` and its sideways part ``dy``; with the yaw change ``dth`` the cost is
    ``hypot(dx, side_cost dy, turn_cost dth)`` (``back_cost`` instead of 1 backward). With the
    default costs (ratios of the step limits) it is ``step_forward`` times the number of steps
    the whole-body walk takes, whose steps lie in the ellipsoid of the step limits. Every
    weight is at least the forward one, so a walk costs at least
    ``hypot(length, turn_cost * |heading change|)``: the A* heuristic of
    :mod:`pivot_ompl.transit.planner` is admissible.
    """
    dyaw = wrap_angle(b[2] - a[2])
    mid = a[2] + 0.5 * dyaw
    ex, ey = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(mid), math.sin(mid)
    dx, dy = c * ex + s * ey, -s * ex + c * ey
    fx = dx if dx >= 0.0 else walk.back_cost * dx
    return math.hypot(fx, walk.side_cost * dy, walk.turn_cost * dyaw)


def chain_cost(poses: np.ndarray, walk: WalkParameters) -> float:
    """Total :func:`motion_cost` of the straight motions between consecutive rows of ``poses``.

    ``poses``: an ``(n, 3)`` array of ``x, y, yaw``; the same sum as :func:`motion_cost` pose
    by pose (to rounding), vectorised: a Dubins walk sampled every few centimetres has tens of
    motions.
    """
    d = np.diff(poses, axis=0)
    dyaw = (d[:, 2] + math.pi) % (2.0 * math.pi) - math.pi
    mid = poses[:-1, 2] + 0.5 * dyaw
    c, s = np.cos(mid), np.sin(mid)
    dx = c * d[:, 0] + s * d[:, 1]
    dy = c * d[:, 1] - s * d[:, 0]
    fx = np.where(dx >= 0.0, dx, walk.back_cost * dx)
    return float(np.sqrt(fx * fx + (walk.side_cost * dy) ** 2
                         + (walk.turn_cost * dyaw) ** 2).sum())


#: Cost (m) by which :func:`forward_chain_cost_bound` stays below what it bounds, for the
#: round-off of OMPL's Dubins curves (their lengths and sampled poses agree to ~1e-7 m).
DUBINS_SLACK = 1e-6


def forward_chain_cost_bound(length: float, pieces: int, turn: float, radius: float,
                             walk: WalkParameters) -> float:
    """Lower bound of :func:`chain_cost` of a forward curve cut into equal pieces.

    The curve (a Dubins walk: curvature at most ``1 / radius``, yaw along its tangent) is
    ``length`` long, sampled at ``pieces`` equal arc lengths, and its yaw changes by ``turn``
    (mod 2 pi) end to end. Each piece's chord is at least the chord of a circle of that
    radius over the same arc length (Schur's comparison), the pieces' turns add up to at
    least ``|wrap(turn)|``, and every motion costs at least ``hypot(w |displacement|,
    turn_cost |dyaw|)`` with ``w`` the smallest walking weight; the triangle inequality
    gathers the pieces. Lets a shortcut be refused without sampling its curve. Less
    :data:`DUBINS_SLACK`: a Dubins curve's length and its sampled poses agree only to OMPL's
    precision (a turn of 8e-7 rad in place is given an arc of 2.4e-7 m, sampled as none).
    """
    step = length / max(1, pieces)
    if step <= math.pi * radius:
        chords = 2.0 * radius * pieces * math.sin(step / (2.0 * radius))
    else:
        chords = 0.0
    w = min(1.0, walk.side_cost, walk.back_cost)
    return max(0.0, math.hypot(w * chords, walk.turn_cost * abs(wrap_angle(turn))) - DUBINS_SLACK)


@dataclass(frozen=True)
class Primitive:
    """One lattice motion from heading ``h``: grid offset, heading change and cost (m)."""

    dix: int
    diy: int
    dh: int
    cost: float
    kind: str


def primitives(resolution: float, walk: WalkParameters,
               step: float = 0.2) -> tuple[tuple[Primitive, ...], ...]:
    """The motion primitives of each heading (see the module docstring).

    Args:
        resolution: grid spacing (m).
        walk: walking costs.
        step: nominal length of one lattice step (m); a grid vector is repeated to about it.
    """
    def vec(h: int) -> tuple[int, int]:
        vx, vy = HEADING_VECTORS[h % N_HEADINGS]
        k = max(1, round(step / (resolution * math.hypot(vx, vy))))
        return k * vx, k * vy

    out = []
    for h in range(N_HEADINGS):
        yaw = HEADING_YAWS[h]
        prims = []
        moves = [(vec(h), dh, "forward") for dh in (0, -1, 1)]
        moves += [(vec(h + 4), 0, "left"), (vec(h - 4), 0, "right"), (vec(h + 8), 0, "back")]
        moves += [((0, 0), 1, "turn"), ((0, 0), -1, "turn")]
        for (dix, diy), dh, kind in moves:
            b = (dix * resolution, diy * resolution,
                 yaw + wrap_angle(HEADING_YAWS[(h + dh) % N_HEADINGS] - yaw))
            prims.append(Primitive(dix, diy, dh, motion_cost((0.0, 0.0, yaw), b, walk), kind))
        out.append(tuple(prims))
    return tuple(out)


def nearest_headings(yaw: float, count: int = 2) -> list[int]:
    """The ``count`` headings nearest to ``yaw``."""
    return sorted(range(N_HEADINGS), key=lambda h: abs(wrap_angle(HEADING_YAWS[h] - yaw)))[:count]

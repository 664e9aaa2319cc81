"""A whole turn in place as one chain of rotations: fewer pivots than equal spin pieces.

A spin's equal pieces (:func:`~pivot_ompl.pivoting.piece_search.spin_step`) each land on the
spin path, so each is the one three-rotation solution that turns the car by its share and
brings it back to its place: a quarter, a half and a quarter of the share, a little more at
the ends. Where two pieces meet, their outer rotations sum just over the bound unless the
shares are small, so a 135 degree turn at ``alpha_max = pi/8`` takes 9 rotations and a half
turn 11, where rotations alternating corners at the bound would take about 7 and 9.

:func:`spin_chain` makes that chain: ``k - 3`` rotations alternating corners, a half share
``c / 2`` then full shares ``c = turn / (k - 1)`` (all turning one way, each within the
bound), then the three rotations (:func:`~pivot_ompl.pivoting.kinematics.solve_piece`, merged
into the chain's last rotation where they turn about its corner) that close the turn exactly
at the goal. The car strays from its place by a few centimetres (about ``l alpha_max / 2``)
on the way, within the steering's small-time neighbourhood of a spin. The fewest ``k`` that
solves is taken (a few tried, from the rotation count the turn needs); the caller keeps the
chain only where it makes fewer rotations than the equal pieces.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.pivoting.kinematics import ANGLE_TOL, LEFT, Rotation, solve_piece
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["CHAIN_TRIES", "spin_chain", "whole_spin"]

#: Chain lengths tried, from the fewest rotations the turn needs plus one.
CHAIN_TRIES = 3


def _rotate(car: Pose, end: int, angle: float, ell: float) -> Rotation:
    """The rotation of the edge at ``car`` by ``angle`` about its end ``end``."""
    x, y, h = car
    sign = 1.0 if end == LEFT else -1.0
    px, py = x - sign * ell * math.sin(h), y + sign * ell * math.cos(h)
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = x - px, y - py
    return Rotation(end, (px, py), angle, (px + c * dx - s * dy, py + s * dx + c * dy, h + angle))


def _chain(start: Pose, goal: Pose, ell: float, alpha_max: float, k: int,
           first: int) -> list[Rotation] | None:
    """The chain of ``k`` rotations (before merging) from ``start`` about ``first`` first."""
    turn = wrap_angle(goal[2] - start[2])
    share = turn / (k - 1)
    rots: list[Rotation] = []
    car, end = start, first
    for i in range(k - 3):
        r = _rotate(car, end, 0.5 * share if i == 0 else share, ell)
        rots.append(r)
        car, end = r.car, 1 - end
    ok, tail = solve_piece(car, goal, ell, alpha_max, previous=rots[-1] if rots else None)
    if not ok or not tail:
        return None
    for r in tail:
        if rots and rots[-1].end == r.end and \
                abs(rots[-1].angle + r.angle) <= alpha_max + ANGLE_TOL:
            prev = rots.pop()
            rots.append(Rotation(r.end, prev.pivot, prev.angle + r.angle, r.car))
        else:
            rots.append(r)
    return rots


def _strays(rots: list[Rotation], place: Pose, ell: float) -> float:
    """How far (m) the car strays from ``place``: each pose reached plus its arc's sagitta."""
    return max((math.hypot(r.car[0] - place[0], r.car[1] - place[1])
                + ell * (1.0 - math.cos(0.5 * r.angle)) for r in rots), default=0.0)


def spin_chain(start: Pose, goal: Pose, ell: float, alpha_max: float, *,
               max_deviation: float) -> tuple[Rotation, ...] | None:
    """The fewest rotations of a chain turning the car from ``start`` to ``goal`` in place.

    Args:
        start: the car pose (supporting-edge centre and heading) where the turn starts.
        goal: the car pose at the same place, turned (a spin's goal).
        ell: half-length of the supporting edge (m).
        alpha_max: bound on each rotation (rad).
        max_deviation: bound (m) on how far the car strays from its place on the way.

    Returns:
        The rotations (each within the bound, the last reaching ``goal`` up to round-off,
        none about the corner of the one before it where the two would merge), or ``None``
        where no chain of the lengths tried solves within ``max_deviation``.
    """
    turn = abs(wrap_angle(goal[2] - start[2]))
    if turn <= 0.0:
        return None
    fewest = math.ceil(turn / alpha_max - 1e-9) + 1
    best: list[Rotation] | None = None
    for k in range(max(3, fewest), max(3, fewest) + CHAIN_TRIES):
        for first in (LEFT, 1 - LEFT):
            rots = _chain(start, goal, ell, alpha_max, k, first)
            if rots is None or any(abs(r.angle) > alpha_max + ANGLE_TOL for r in rots) or \
                    _strays(rots, start, ell) > max_deviation:
                continue
            if best is None or len(rots) < len(best):
                best = rots
        if best is not None:
            break
    return None if best is None else tuple(best)


_Solved = tuple[Pose, tuple[Rotation, ...]]


def whole_spin(solve: Callable[[float], _Solved | None], step: float, start: Pose, goal: Pose,
               ell: float, alpha_max: float,
               max_deviation: float) -> tuple[Rotation, ...] | None:
    """:func:`spin_chain`'s rotations where they are fewer than the equal pieces' (else ``None``).

    ``solve`` and ``step`` are the steering's: its piece solver from ``start`` and the
    parameter step of the spin's equal pieces (:func:`~.piece_search.spin_step`), whose
    rotations count ``n`` pieces' rotations less one per junction where two merge.
    """
    n = round(1.0 / step)
    res = solve(step)
    if res is None or not res[1]:
        return None
    rots = res[1]
    joined = n > 1 and rots[-1].end == rots[0].end and \
        abs(rots[-1].angle + rots[0].angle) <= alpha_max + ANGLE_TOL
    equal = n * len(rots) - (n - 1 if joined else 0)
    chain = spin_chain(start, goal, ell, alpha_max, max_deviation=max_deviation)
    return chain if chain is not None and len(chain) < equal else None

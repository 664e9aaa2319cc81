"""A whole turn in place as one chain of rotations: fewer pivots than equal spin pieces.

A spin's equal pieces (:func:`~pivot_ompl.pivoting.piece_search.spin_step`) each land on the
spin path, so each is the one three-rotation solution that turns the car by its share and
brings it back to its place: a quarter, a half and a quarter of the share, a little more at
the ends. Where two pieces meet, their outer rotations sum just over the bound unless the
shares are small, so a 135 degree turn at ``alpha_max = pi/8`` takes 9 rotations and a half
turn 11, where rotations alternating corners near the bound take about 7 and 9.

:func:`spin_chain` makes such a chain: ``m`` rotations alternating corners, all turning one
way, a first one of ``f c`` then ``c`` each (``c`` a share of the bound,
:data:`CHAIN_SHARES`, ``f`` in :data:`CHAIN_FIRST`), then the three rotations
(:func:`~pivot_ompl.pivoting.kinematics.solve_piece`, merged into the chain's last rotation
where they turn about its corner within the bound) that close the turn exactly at the goal.
The car strays from its place by a few centimetres on the way (the sweep checks decide
whether there is room), within the steering's small-time neighbourhood of a spin. Of the
prefix lengths around what the turn needs (shortest first) and the shares (smallest first,
the first one's share tried in turn), the chain of fewest rotations is taken, the one
straying least among those, or the first found of one rotation over what the turn needs.
The caller keeps it only where it makes fewer rotations than the equal pieces
(:func:`whole_spin`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.pivoting.kinematics import ANGLE_TOL, LEFT, Rotation, edge_turn, solve_piece
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["CHAIN_FIRST", "CHAIN_SHARES", "rotate_edge", "spin_chain", "whole_spin"]

#: The chain's rotations before its closing three: shares of the bound tried,
CHAIN_SHARES = (0.7, 0.8, 0.9, 0.96, 1.0)
#: and the first one's share of those.
CHAIN_FIRST = (0.5, 0.6, 0.75, 1.0)


def rotate_edge(car: Pose, end: int, angle: float, ell: float) -> Rotation:
    """The rotation of the edge at ``car`` by ``angle`` about its end ``end``."""
    px, py, reached = edge_turn(*car, end, ell, angle, math.cos(angle), math.sin(angle))
    return Rotation(end, (px, py), angle, reached)


def _chain(start: Pose, goal: Pose, ell: float, alpha_max: float, m: int, c: float,
           first_share: float, first: int) -> list[Rotation] | None:
    """``m`` rotations of ``c`` (the first ``first_share c``), then the closing ones, merged.

    The first turns about the corner ``first``; ``None`` where the closing does not solve.
    """
    rots: list[Rotation] = []
    car, end = start, first
    for i in range(m):
        r = rotate_edge(car, end, first_share * c if i == 0 else c, ell)
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
    signed = wrap_angle(goal[2] - start[2])
    turn = abs(signed)
    if turn <= 0.0:
        return None
    need = math.ceil(turn / alpha_max - 1e-9)
    best: tuple[int, float, list[Rotation]] | None = None
    for m in range(max(1, need - 3), need + 2):
        for share in CHAIN_SHARES:
            c = math.copysign(share * alpha_max, signed)
            for first_share in CHAIN_FIRST:
                for first in (LEFT, 1 - LEFT):
                    rots = _chain(start, goal, ell, alpha_max, m, c, first_share, first)
                    if rots is None or \
                            any(abs(r.angle) > alpha_max + ANGLE_TOL for r in rots):
                        continue
                    strays = _strays(rots, start, ell)
                    if strays <= max_deviation and \
                            (best is None or (len(rots), strays) < best[:2]):
                        best = (len(rots), strays, rots)
            if best is not None and best[0] <= need + 1:  # one over what the turn needs:
                return tuple(best[2])  # the closing rotations return the car, few do better
    return None if best is None else tuple(best[2])


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
    if equal <= math.ceil(abs(wrap_angle(goal[2] - start[2])) / alpha_max - 1e-9) + 1:
        return None  # the equal pieces are as few as chains make
    chain = spin_chain(start, goal, ell, alpha_max, max_deviation=max_deviation)
    return chain if chain is not None and len(chain) < equal else None

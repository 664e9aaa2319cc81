"""The search along a Reeds-Shepp path for where a piece of (at most three) rotations ends.

:class:`~pivot_ompl.pivoting.steering.PivotSteering` converts a path piece by piece; these
functions choose each piece's end: the farthest parameter three rotations reach
(:func:`longest`), or a shorter piece that adds fewer rotations (:func:`fewer_pivots`); a
spin's pieces are equal, as many as make the fewest rotations (:func:`spin_step`).
``solve(t)`` is the steering's: the piece's target pose and rotations, or ``None``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.pivoting.kinematics import ANGLE_TOL, Rotation
from pivot_ompl.se2 import Pose

__all__ = ["FEWER_PIVOTS_GAIN", "GALLOP", "LONGEST_TOLERANCE", "SPIN_TRIES", "fewer_pivots",
           "longest", "merges", "spin_step"]

#: The search for the longest piece stops when the bracket ``[t_ok, t_fail]`` is shorter
#: than this fraction of the piece found (pieces are within this of the longest).
LONGEST_TOLERANCE = 0.125

#: Growth of the trial piece while galloping along the path.
GALLOP = 2.0

_Solved = tuple[Pose, tuple[Rotation, ...]]

#: A piece whose first rotation merges into the previous one is preferred to the longest
#: piece when it advances along the path at least this share farther per rotation added.
FEWER_PIVOTS_GAIN = 1.02


def merges(previous: Rotation, first: Rotation, alpha_max: float) -> bool:
    """Whether ``first`` merges into ``previous`` (same corner, sum within the bound)."""
    return first.end == previous.end and \
        abs(previous.angle + first.angle) <= alpha_max + ANGLE_TOL


def fewer_pivots(solve: Callable[[float], _Solved | None], previous: Rotation,
                  alpha_max: float, t0: float, t_long: float,
                  long: _Solved) -> tuple[float, _Solved]:
    """The longest piece, or a shorter one that adds fewer rotations per length of path.

    The longest piece from ``t0`` (to ``t_long``, three rotations none of which merges into
    ``previous``) against the longest piece whose first rotation merges into ``previous``
    (two rotations added): on a Reeds-Shepp arc the second alternates corners with unequal
    rotations, as a car turning does, where the longest needs three per piece. Asked only
    where the longest piece starts about ``previous``'s corner but turns it too far to
    merge (the arc's pattern; elsewhere a merging piece seldom wins). Only pieces
    long enough to win are tried (at least :data:`FEWER_PIVOTS_GAIN` x two thirds of the
    longest): one solve where none merges, a few bisection steps where one does.
    """

    def merging(t: float) -> _Solved | None:
        res = solve(t)
        return res if res is not None and res[1] and merges(previous, res[1][0],
                                                            alpha_max) else None

    span = t_long - t0
    t_ok = t0 + FEWER_PIVOTS_GAIN * 2.0 / 3.0 * span
    if t_ok >= t_long:
        return t_long, long
    best = merging(t_ok)
    if best is None:
        return t_long, long
    t_fail = t_long
    while t_fail - t_ok > LONGEST_TOLERANCE * span:
        t = 0.5 * (t_ok + t_fail)
        res = merging(t)
        if res is not None:
            t_ok, best = t, res
        else:
            t_fail = t
    # advance per rotation added, (t_ok - t0) / (n - 1) against span / len(long), multiplied
    # out: a merging piece of one rotation adds none and always wins
    if (t_ok - t0) * len(long[1]) >= FEWER_PIVOTS_GAIN * span * (len(best[1]) - 1):
        return t_ok, best
    return t_long, long


def longest(solve: Callable[[float], _Solved | None], t0: float, t_end: float, step: float,
             min_step: float, failure: Callable[[float], Exception]) -> tuple[float, _Solved]:
    """The farthest parameter ``t`` in ``(t0, t_end]`` that ``solve`` reaches, and its result.

    Gallops forwards from ``t0 + step`` (the last piece's length) while pieces solve, or
    halves back until one does (raising ``failure(t0)`` below ``min_step``), then bisects
    between the last success and the first failure down to :data:`LONGEST_TOLERANCE`.
    """
    t_ok, best = t0, None
    t_fail = t_end + 1.0
    t = t0 + step
    while True:
        res = solve(t)
        if res is not None:
            t_ok, best = t, res
            if t >= t_end or t_fail <= t_end:
                break
            t = min(t_end, t0 + (t - t0) * GALLOP)
        else:
            t_fail = t
            if best is not None:
                break
            if t - t0 <= min_step:
                raise failure(t0)
            t = t0 + 0.5 * (t - t0)
    while t_fail <= t_end and t_fail - t_ok > LONGEST_TOLERANCE * (t_ok - t0):
        t = 0.5 * (t_ok + t_fail)
        res = solve(t)
        if res is not None:
            t_ok, best = t, res
        else:
            t_fail = t
    assert best is not None
    return t_ok, best


#: Piece counts a spin tries, from a lower bound of the fewest that solve.
SPIN_TRIES = 4


def spin_step(solve: Callable[[float], _Solved | None], alpha_max: float,
              turn: float) -> float | None:
    """The parameter step of a spin's equal pieces that make the fewest rotations.

    A spin's pieces are alike (each turns the car by the same angle about its place): ``n``
    pieces of three rotations make ``3 n``, or ``2 n + 1`` where a piece's last and first
    rotations turn about one corner and sum within the bound (they merge at every junction).
    The longest pieces' outer rotations are each a little over a quarter of the piece's
    turn, so they just miss; one piece more may merge. Of the fewest equal pieces that
    ``solve`` (``solve(t)`` from the spin's start, ``turn`` its angle in rad) and one more,
    the count making fewer rotations; ``None`` if none of :data:`SPIN_TRIES` counts solves.
    """
    first = max(1, math.floor(turn / (2.2 * alpha_max)))  # a piece turns < 2.1 alpha_max
    best: tuple[int, int] | None = None
    for n in range(first, first + SPIN_TRIES):
        res = solve(1.0 / n)
        if res is None or not res[1]:
            if best is not None:
                break
            continue
        rots = res[1]
        joined = n > 1 and merges(rots[-1], rots[0], alpha_max)
        count = n * len(rots) - (n - 1 if joined else 0)
        if best is None or count < best[0]:
            best = (count, n)
        if n > best[1]:  # the fewest that solve and one more: tried
            break
    return None if best is None else 1.0 / best[1]

"""Pivot kinematics of the supporting edge (controllability paper, Sections III-IV).

The supporting edge is a segment of length ``2l``. Its configuration is the *car pose*
``(x, y, h)`` of :mod:`pivot_ompl.grasp`: the segment's centre and the heading ``h`` normal to
it, so the segment's own direction is ``phi = h - pi/2`` and its ends are

* ``A = centre + l (-sin h, cos h)`` (left end seen from the robot),
* ``B = centre - l (-sin h, cos h)`` (right end).

A rotation by ``alpha`` (rad, counter-clockwise) about an end keeps that end fixed. Three
rotations alternating ends (``A, B, A`` or ``B, A, B``) reach any small displacement: a planar
3R arm whose inverse kinematics is solved here in closed form with ``atan2`` and every candidate
verified with the forward map (the printed formula of the paper leaves ``phi`` undefined).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from pivot_ompl.errors import UnreachableError
from pivot_ompl.se2 import Pose, wrap_angle

#: Tolerance on the forward-map verification of an inverse-kinematics candidate (m and rad).
IK_VERIFY_TOL = 1e-9

#: Round-off allowed on the rotation bound (rad): a rotation of exactly alpha_max must pass.
ANGLE_TOL = 1e-12

#: Overshoot of the bound (rad) by round-off of an ill-conditioned candidate that is clamped
#: (at least; more where the ends' round-off over their distance ``d`` says so, see
#: :func:`_candidates_within`).
CLAMP_TOL = 1e-7

#: Rotations smaller than this (rad) are dropped from solutions.
ZERO_ANGLE = 1e-12

LEFT, RIGHT = 0, 1  # indices of the pivot ends A and B


class Rotation(NamedTuple):
    """One pivot rotation (a named tuple: it is created in the steering's inner loop).

    Attributes:
        end: ``0`` for end ``A`` (left), ``1`` for end ``B`` (right).
        pivot: world position of the pivot corner (m).
        angle: signed rotation angle (rad, counter-clockwise positive).
        car: car pose after the rotation.
    """

    end: int
    pivot: tuple[float, float]
    angle: float
    car: Pose


@dataclass(frozen=True)
class ThreeRotationResult:
    """Result of the three-rotation local steering.

    Attributes:
        reachable: whether the goal is reachable with every ``|alpha_i| <= alpha_max``.
        rotations: the (at most three) non-zero rotations, in order; empty if unreachable or
            if start and goal coincide.
        total_angle: sum of ``|alpha_i|`` (rad); ``inf`` if unreachable.
    """

    reachable: bool
    rotations: tuple[Rotation, ...]
    total_angle: float

    def raise_if_unreachable(self, start: Pose, goal: Pose, alpha_max: float) -> None:
        """Raise :class:`UnreachableError` if the goal was not reachable."""
        if not self.reachable:
            raise UnreachableError(start, goal, alpha_max)


def end_point(car: Pose, half_length: float, end: int) -> tuple[float, float]:
    """World position of end ``A`` (``end=0``) or ``B`` (``end=1``) of the edge at ``car``."""
    px, py, _ = edge_turn(car[0], car[1], car[2], end, half_length, 0.0, 1.0, 0.0)
    return px, py


def edge_turn(x: float, y: float, h: float, end: int, ell: float, angle: float, c: float,
              s: float) -> tuple[float, float, Pose]:
    """The edge at car pose ``(x, y, h)`` turned by ``angle`` about its end ``end``, as floats.

    The one formula of a rotation about a corner: :func:`end_point`, :func:`forward` and the
    steering's searches turn the edge with it (:func:`solve_piece`'s inner loop writes its
    arithmetic out; a test holds the two equal).

    Args:
        x: the car pose's x (the supporting edge's centre, m),
        y: its y (m),
        h: and its heading (rad).
        end: the corner turned about (``LEFT`` or the other).
        ell: half-length of the supporting edge (m).
        angle: the turn (rad),
        c: its cosine
        s: and its sine (a search turning many poses by the same angles computes them once).

    Returns:
        The pivot ``(px, py)`` (m) and the car pose reached. No :class:`Rotation` record:
        :func:`~pivot_ompl.pivoting.spin_chain.rotate_edge` is the form that builds one.
    """
    sign = 1.0 if end == LEFT else -1.0
    px, py = x - sign * ell * math.sin(h), y + sign * ell * math.cos(h)
    dx, dy = x - px, y - py
    return px, py, (px + c * dx - s * dy, py + s * dx + c * dy, h + angle)


def forward(car: Pose, half_length: float, first_end: int,
            angles: tuple[float, float, float]) -> Pose:
    """Forward map: the car pose after three rotations.

    The rotations are about ``first_end``, the other end, then ``first_end``.
    """
    end = first_end
    for a in angles:
        _, _, car = edge_turn(car[0], car[1], car[2], end, half_length, a, math.cos(a),
                              math.sin(a))
        end = 1 - end
    return car


def _candidates_within(start: Pose, goal: Pose, ell: float,
                       alpha_max: float) -> list[tuple[float, int, float, float, float]]:
    """Closed-form candidates ``(total, first_end, a1, a2, a3)`` within the bound, best first.

    Let ``P0`` be the first pivot and ``u(a)`` the unit vector of angle ``a``. With ``psi`` the
    direction from ``P0`` to the other end, after the first two rotations the first end sits at
    ``P0 + 2l (u(psi+a1) - u(psi+a1+a2))``, which must equal the goal's first end. Its distance
    ``d`` to ``P0`` gives ``|a2| = 2 asin(d / 4l)``; ``atan2`` of the difference gives ``a1``;
    ``a3`` closes the heading. Callers verify candidates with the forward map.
    """
    sx, sy, sh = start
    gx, gy, gh = goal
    # the ends' offsets from the centres, l (-sin h, cos h): A at +, B at - (negation and
    # a subtraction of a negation are exact, so these are the products the formula takes)
    lsh, lch = ell * math.sin(sh), ell * math.cos(sh)
    lsg, lcg = ell * math.sin(gh), ell * math.cos(gh)
    limit = 4.0 * ell * math.sin(0.5 * alpha_max) + 1e-12
    # both first ends' distances first: most trial targets of a piece search reach neither
    dxa, dya = (gx - lsg) - (sx - lsh), (gy + lcg) - (sy + lch)
    dxb, dyb = (gx + lsg) - (sx + lsh), (gy - lcg) - (sy - lch)
    da, db = math.hypot(dxa, dya), math.hypot(dxb, dyb)
    found: list[tuple[float, int, float, float, float]] = []
    if da > limit and db > limit:
        return found
    for first, sign, dx, dy, d in ((LEFT, 1.0, dxa, dya, da), (RIGHT, -1.0, dxb, dyb, db)):
        if d > limit:
            continue
        p0x, p0y = sx - sign * lsh, sy + sign * lch
        p2x, p2y = gx - sign * lsg, gy + sign * lcg
        # direction from the first end to the other end: h - pi/2 for A, h + pi/2 for B
        psi0 = start[2] - sign * 0.5 * math.pi
        dpsi = goal[2] - start[2]
        cands = []
        if d < IK_VERIFY_TOL:  # (nearly) a pure rotation about the first end: one or two
            # halves, which arrive within d of the goal (the verification's tolerance)
            cands = [(wrap_angle(dpsi), 0.0, 0.0), (0.5 * wrap_angle(dpsi), 0.0,
                                                    0.5 * wrap_angle(dpsi))]
        if d >= 1e-12:
            half = math.asin(min(1.0, d / (4.0 * ell)))
            bearing = math.atan2(dy, dx)
            for a2 in (2.0 * half, -2.0 * half):
                a = bearing - 0.5 * a2 + (0.5 * math.pi if a2 > 0 else -0.5 * math.pi)
                a1 = wrap_angle(a - psi0)
                a3 = wrap_angle(dpsi - a1 - a2)
                cands.append((a1, a2, a3))
        bound = alpha_max + ANGLE_TOL  # round-off of asin/atan2 at the bound itself
        # a tiny middle rotation leaves a1 and a3 ill-conditioned: the bearing of the ends'
        # difference (length d) carries the round-off of their coordinates over d (3e-7 rad
        # for a2 ~ 1e-9); an angle that overshoots the bound by less than that is put on it,
        # and the forward-map verification decides
        scale = 1.0 + abs(p0x) + abs(p0y) + abs(p2x) + abs(p2y)
        clamp = alpha_max + max(CLAMP_TOL, min(1e-4, 8.0 * sys.float_info.epsilon * scale / d)) \
            if d > 0.0 else alpha_max + CLAMP_TOL
        for cand in cands:
            a1, a2, a3 = cand
            if bound < abs(a3) <= clamp:  # the heading closes on a1
                a3 = math.copysign(alpha_max, a3)
                a1 = wrap_angle(dpsi - a2 - a3)
            if bound < abs(a1) <= clamp:
                a1 = math.copysign(alpha_max, a1)
                a3 = wrap_angle(dpsi - a1 - a2)
            if abs(a1) <= bound and abs(a2) <= bound and abs(a3) <= bound:
                found.append((abs(a1) + abs(a2) + abs(a3), first, a1, a2, a3))
    found.sort()
    return found


def chord_distance(px: float, py: float, start: Pose, goal: Pose) -> float:
    """Distance (m) of the point ``(px, py)`` to the segment from ``start`` to ``goal``."""
    ux, uy = goal[0] - start[0], goal[1] - start[1]
    vx, vy = px - start[0], py - start[1]
    n2 = ux * ux + uy * uy
    t = 0.0 if n2 <= 0.0 else min(1.0, max(0.0, (vx * ux + vy * uy) / n2))
    return math.hypot(vx - t * ux, vy - t * uy)


def _merged_count(cand: tuple[float, int, float, float, float], previous: Rotation | None,
                  alpha_max: float) -> int:
    """Rotations a candidate adds once its first rotation is merged into ``previous``."""
    _total, first, *angles = cand
    n = sum(1 for a in angles if abs(a) > ZERO_ANGLE)
    a1 = angles[0]
    if previous is not None and abs(a1) > ZERO_ANGLE and previous.end == first and \
            abs(previous.angle + a1) <= alpha_max + ANGLE_TOL:
        n -= 1
    return n


def solve_piece(start: Pose, goal: Pose, ell: float, alpha_max: float, *,
                max_deviation: float = math.inf,
                previous: Rotation | None = None) -> tuple[bool, tuple[Rotation, ...]]:
    """Inner loop of the steering: ``(reachable, rotations)`` of the best verified candidate.

    The closed-form candidates (:func:`_candidates_within`), best first; the rotation records
    are built while verifying each candidate with the forward map, and the first candidate
    that reaches the goal and stays within ``max_deviation`` is returned.

    Args:
        start: car pose where the rotations start.
        goal: car pose to reach.
        ell: half-length of the supporting edge (m).
        alpha_max: bound on each rotation (rad).
        max_deviation: bound (m) on how far the car's centre strays from the segment
            ``start -> goal`` while rotating: the distance of every intermediate car position
            plus the sagitta ``l (1 - cos(|a|/2))`` of each rotation's arc (an upper bound of
            the whole sweep's deviation). This is the small-time property: a piece's
            rotations stay in a neighbourhood of the piece that the caller shrinks with it.
        previous: the rotation before the piece: candidates are ranked by the rotations
            they add once their first rotation is merged into it, then by total angle, so
            that consecutive pieces of a push alternate corners without a break.
    """
    if abs(wrap_angle(goal[2] - start[2])) > 3.0 * alpha_max + ANGLE_TOL:
        return False, ()
    found = _candidates_within(start, goal, ell, alpha_max)
    if not found:
        return False, ()
    if previous is not None and len(found) > 1:
        found.sort(key=lambda c: (_merged_count(c, previous, alpha_max), c[0]))
    bounded = math.isfinite(max_deviation)
    sin, cos, hypot = math.sin, math.cos, math.hypot
    # chord_distance's segment, once: the arithmetic is that function's
    sx, sy = start[0], start[1]
    ux, uy = goal[0] - sx, goal[1] - sy
    n2 = ux * ux + uy * uy
    for _total, first, a1, a2, a3 in found:
        x, y, h = start
        sign = 1.0 if first == LEFT else -1.0
        end = first
        rots = []
        worst = prev = 0.0
        for a in (a1, a2, a3):
            if abs(a) > ZERO_ANGLE:
                # edge_turn's arithmetic, written out: the steering's inner loop (a call per
                # rotation cost about a tenth of this function's time)
                px, py = x - sign * ell * sin(h), y + sign * ell * cos(h)
                c, s_ = cos(a), sin(a)
                dx, dy = x - px, y - py
                x, y, h = px + c * dx - s_ * dy, py + s_ * dx + c * dy, h + a
                rots.append(Rotation(end, (px, py), a, (x, y, h)))
                if bounded:  # an arc is within its ends' distance plus its sagitta
                    vx, vy = x - sx, y - sy
                    t = 0.0 if n2 <= 0.0 else min(1.0, max(0.0, (vx * ux + vy * uy) / n2))
                    d = hypot(vx - t * ux, vy - t * uy)
                    worst = max(worst, max(prev, d) + ell * (1.0 - cos(0.5 * a)))
                    if worst > max_deviation:  # refused whatever follows
                        break
                    prev = d
            sign = -sign
            end = 1 - end
        if worst > max_deviation:
            continue
        if (abs(x - goal[0]) <= IK_VERIFY_TOL and abs(y - goal[1]) <= IK_VERIFY_TOL
                and abs(wrap_angle(h - goal[2])) <= IK_VERIFY_TOL):
            return True, tuple(rots)
    return False, ()


def solve_three_rotations(start: Pose, goal: Pose, *, half_length: float,
                          alpha_max: float) -> ThreeRotationResult:
    """Join two car poses by three alternating pivot rotations, each ``|alpha| <= alpha_max``.

    Both sequences (``A, B, A`` and ``B, A, B``) and both elbow branches are tried; every
    candidate within the bound is verified with :func:`forward`, smallest total ``|alpha|``
    first, and the first one that reaches the goal is returned. Rotations of zero angle are dropped.

    Args:
        start: car pose (m, m, rad) of the supporting edge before the rotations.
        goal: car pose to reach.
        half_length: half-length ``l`` of the supporting edge (m).
        alpha_max: bound on each rotation (rad).
    """
    ok, rotations = solve_piece(start, goal, half_length, alpha_max)
    if not ok:
        return ThreeRotationResult(False, (), math.inf)
    return ThreeRotationResult(True, rotations, sum(abs(r.angle) for r in rotations))


def vector_fields(car: Pose, half_length: float) -> tuple[np.ndarray, np.ndarray]:
    """Vector fields of rotation about ``A`` and ``B`` at ``car`` in (x, y, h) coordinates.

    Returns ``(L, R)`` where ``L = d/de rotate_about(car, A, e)`` at ``e = 0`` (and ``R`` for
    ``B``): ``L = (l cos h, l sin h, 1)`` and ``R = (-l cos h, -l sin h, 1)``, the paper's
    ``(-l sin th, l cos th, 1)`` and ``(l sin th, -l cos th, 1)`` with ``th = h - pi/2``.
    """
    c, s = math.cos(car[2]), math.sin(car[2])
    ell = half_length
    return np.array([ell * c, ell * s, 1.0]), np.array([-ell * c, -ell * s, 1.0])

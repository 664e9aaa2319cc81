"""A transfer phase's pivot rotations, runs of them replaced by fewer where the checks pass.

The steering converts each route edge on its own, piece by piece, each piece of up to three
rotations landing on the edge's Reeds-Shepp path. Where the path turns (a turn in place, an
arc, the junction of a push and a turn), the pieces' outer rotations often turn about one
corner one after the other and sum over the bound, so they do not merge: a push that closes
on the pose where a turn in place starts, then the turn's first rotation about the same
corner, took three rotations and one more where two would do.

:func:`shorten` slides a window over a phase's rotations (merged as the plan writes them;
at each position the shortest window first, up to :data:`WINDOW`) and joins the pose before
the window to the pose at its end by fewer rotations: three solved rotations
(:func:`~pivot_ompl.pivoting.kinematics.solve_piece`), or, for a window of more than four,
one fewer than the window with the leading ones on a grid of angles (:data:`GRID` steps of
the bound, alternating corners; up to :data:`FREE_LEAD` of them at any angle of the grid,
as an arc's rotations alternate in sign; more only at the grid's two largest angles turning
the way the window turns, as in a turn in place) and three solved after them. A
replacement counts once merged into the rotations before and after the window, and is kept
only where its rotations pass the same checks as the steering's (inside the bounds, every
sweep certified free: :meth:`~pivot_ompl.checking.rotation_sweeps.RotationSweeps.rotations`).
The window's end pose is kept exactly, so the phase ends where it did, and the plan's
physics are those of any checked pivot sequence.

Passes over the phase repeat until one replaces nothing, so the result is a fixed point of
the replacements (no window of it can be shortened), not the trace of one greedy pass:
a replacement can open another one behind it, anywhere before it in the phase.

Only windows where the box turns are tried (two consecutive rotations turning the same way):
a run of rotations alternating in sign is a push, whose rotations the checks or the bound
already make as large as they may be (a slot's small rotations), and trying it would spend
checks for nothing. At most :data:`WINDOW_CHECKS` sweep checks per window and
:data:`CHECKS` per phase (counts, so a seed gives the same plan on any machine).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterator, Sequence

from pivot_ompl.checking.rotation_sweeps import RotationSweeps
from pivot_ompl.pivoting.kinematics import ANGLE_TOL, Rotation, edge_turn, solve_piece
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["CHECKS", "FREE_LEAD", "GRID", "WINDOW", "WINDOW_CHECKS", "shorten"]

log = logging.getLogger(__name__)

#: The longest run of rotations replaced at once.
WINDOW = 10
#: Replacements with up to this many leading rotations try every angle of the grid for them.
FREE_LEAD = 2
#: The leading rotations of a replacement of more than three turn by multiples of
#: ``alpha_max / GRID``.
GRID = 8
#: Sweep checks one window may spend on replacements (its first ones), so that a phase's
#: budget is rarely what ends its passes.
WINDOW_CHECKS = 4
#: Sweep checks a phase may spend on replacements.
CHECKS = 400
#: A replacement's rotations keep the car within this share of the window's span (its
#: chord, or the arc its edge's ends trace turning) of the chord.
DEVIATION_RATIO = 0.5


def _merges(a: Rotation, b: Rotation, alpha_max: float) -> bool:
    return a.end == b.end and abs(a.angle + b.angle) <= alpha_max + ANGLE_TOL


def _merged(rotations: Sequence[Rotation], alpha_max: float) -> list[Rotation]:
    """``rotations`` with consecutive ones about one corner merged within the bound."""
    out: list[Rotation] = []
    for r in rotations:
        if out and _merges(out[-1], r, alpha_max):
            prev = out.pop()
            if abs(prev.angle + r.angle) > 1e-12:
                out.append(Rotation(r.end, prev.pivot, prev.angle + r.angle, r.car))
        else:
            out.append(r)
    return out


def _turns(rotations: Sequence[Rotation]) -> bool:
    """Whether two consecutive rotations turn the same way."""
    return any(a.angle * b.angle > 0.0 for a, b in zip(rotations, rotations[1:], strict=False))


def _replacements(p: Pose, q: Pose, ell: float, alpha_max: float, n: int,
                  before: Rotation | None, deviation: float) -> Iterator[list[Rotation]]:
    """Rotations from ``p`` to ``q``: ``n - 3`` on the grid (none if ``n <= 3``), three solved.

    Up to :data:`FREE_LEAD` leading rotations take every angle of the grid (an arc's
    rotations alternate in sign, a turn in place's keep it); more take the grid's two
    largest angles turning the way the window turns (``q``'s heading from ``p``'s). A lead
    from which the rotations left cannot reach ``q`` (each moves the car by at most
    ``2 ell sin(alpha_max / 2)`` and turns it by at most ``alpha_max``) is not followed.
    """
    lead = max(0, n - 3)
    if lead == 0:
        ok, solved = solve_piece(p, q, ell, alpha_max, max_deviation=deviation,
                                 previous=before)
        if ok and solved:
            yield list(solved)
        return
    turn = wrap_angle(q[2] - p[2])
    angles = [alpha_max * j / GRID for j in range(-GRID, GRID + 1)
              if j and (lead <= FREE_LEAD or (j * turn > 0.0 and abs(j) >= GRID - 1))]
    turns = [(a, math.cos(a), math.sin(a)) for a in angles]
    step = 2.0 * ell * math.sin(0.5 * alpha_max)
    hypot = math.hypot
    qx, qy, qh = q

    def grow(x: float, y: float, h: float, end: int,
             leads: list[tuple[int, float, float, float, Pose]]) -> Iterator[list[Rotation]]:
        left = n - len(leads)  # rotations left to reach q from (x, y, h)
        if hypot(qx - x, qy - y) > left * step + 1e-9 or \
                abs(wrap_angle(qh - h)) > left * (alpha_max + ANGLE_TOL):
            return
        if len(leads) == lead:  # the leads as records: (corner, angle, pivot, car reached)
            rots = [Rotation(e, (px, py), a, car) for e, a, px, py, car in leads]
            ok, tail = solve_piece(rots[-1].car, q, ell, alpha_max, max_deviation=deviation,
                                   previous=rots[-1])
            if ok and tail:
                yield rots + list(tail)
            return
        for a, c, s in turns:
            px, py, car = edge_turn(x, y, h, end, ell, a, c, s)
            yield from grow(*car, 1 - end, [*leads, (end, a, px, py, car)])

    for first in (0, 1):
        yield from grow(p[0], p[1], p[2], first, [])


def shorten(sweeps: RotationSweeps, start: Pose, rotations: Sequence[Rotation], grasp: int,
            *, half_length: float, alpha_max: float, checks: int = CHECKS,
            should_stop: Callable[[], bool] | None = None) -> tuple[Rotation, ...]:
    """The phase's rotations from car pose ``start``, runs replaced by fewer where they pass.

    Args:
        sweeps: the scene's rotation checks (the robot holding the box at ``grasp``).
        start: the car pose where the phase starts.
        rotations: the phase's rotations in order, merged (each about a corner of the car
            the one before it reached, within ``alpha_max``).
        grasp: the phase's grasp.
        half_length: half-length of the supporting edge at ``grasp`` (m).
        alpha_max: bound on each rotation (rad).
        checks: sweep checks the replacements may spend.
        should_stop: polled once per window; when true, what was replaced so far is kept.

    Returns:
        Rotations reaching every pose the given ones reach at a window's end, the last
        exactly; never more of them.
    """
    rots = list(rotations)
    spent = 0
    failed: set[tuple] = set()
    while True:  # passes until one replaces nothing: the result is a fixed point
        count = len(rots)
        rots, spent = _pass(sweeps, start, rots, grasp, half_length=half_length,
                            alpha_max=alpha_max, spent=spent, checks=checks,
                            failed=failed, should_stop=should_stop)
        if len(rots) == count or spent >= checks or (should_stop is not None
                                                     and should_stop()):
            break
    if len(rots) < len(rotations):
        log.debug("phase at grasp %d: %d rotations -> %d (%d checks)", grasp, len(rotations),
                  len(rots), spent)
    return tuple(rots)


def _pass(sweeps: RotationSweeps, start: Pose, rots: list[Rotation], grasp: int, *,
          half_length: float, alpha_max: float, spent: int, checks: int, failed: set[tuple],
          should_stop: Callable[[], bool] | None) -> tuple[list[Rotation], int]:
    """One pass of windows over ``rots``: ``(rotations, checks spent)``.

    At each position the shortest window first; after a replacement the pass steps back two
    rotations (the joins changed there), else it moves on by one. A window whose every
    replacement was tried and refused is added to ``failed`` (with its neighbours, which
    decide the merges) and not tried again: its replacements and their checks would be the
    same.
    """
    i = 0
    while i < len(rots) and spent < checks:
        if should_stop is not None and should_stop():
            break
        done = False
        for w in range(2, min(WINDOW, len(rots) - i) + 1):
            before = rots[i - 1] if i else None
            after = rots[i + w] if i + w < len(rots) else None
            around = ([before] if before else []) + rots[i:i + w] + ([after] if after else [])
            key = (before, *rots[i:i + w], after)
            if key in failed or not _turns(around):
                continue
            p = before.car if before else start
            q = rots[i + w - 1].car
            span = max(math.hypot(q[0] - p[0], q[1] - p[1]),
                       half_length * abs(wrap_angle(q[2] - p[2])))
            deviation = DEVIATION_RATIO * span + 1e-12
            tried = 0
            for n in sorted({3, w - 1}):
                if n >= w:
                    continue
                for new in _replacements(p, q, half_length, alpha_max, n, before, deviation):
                    last = new[-1]
                    new[-1] = Rotation(last.end, last.pivot, last.angle, q)
                    joined = _merged(([before] if before else []) + new +
                                     ([after] if after else []), alpha_max)
                    if len(joined) >= len(around) or spent >= checks:
                        continue
                    if tried >= WINDOW_CHECKS:
                        break
                    tried += 1
                    spent += 1
                    db, dr = sweeps.start(p, grasp, True)
                    why, _ = sweeps.rotations(p, tuple(new), grasp, True, db, dr)
                    if why:
                        continue
                    rots = rots[:max(0, i - 1)] + joined + rots[i + w + 1:]
                    done = True
                    break
                if done:
                    break
            if done:
                break
            if spent < checks:
                failed.add(key)
        i = max(0, i - 2) if done else i + 1
    return rots, spent

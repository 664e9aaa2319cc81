"""Certified swept-volume checks from clearance (distance) queries.

A motion ``pose(s)``, ``s`` in [0, 1], moves no point of a body by more than ``M |s - s'|``
(``M``: the motion's Lipschitz bound, e.g. ``r_max |alpha|`` for a rotation by ``alpha`` about a
pivot at most ``r_max`` from the body). If the clearances ``d(a)`` and ``d(b)`` at two samples
satisfy ``d(a) + d(b) > M (b - a)``, no point can reach an obstacle in between, so the whole
interval is collision-free with no further query. Otherwise the interval is bisected. An
interval is also accepted once ``M (b - a) <= 2 * tolerance`` with both ends collision-free:
then no point is farther than ``tolerance`` from a checked sample (the stated tolerance).

That acceptance lets a body dip into an obstacle by up to ``tolerance`` between two samples,
and another sampling of the same motion (another check, or the same sweep split in two and
checked piece by piece) can land on the dip. ``exact=True`` accepts an interval only by the
clearance test, with :data:`EXACT_MARGIN` on each side (``d(a) + d(b) > M (b - a) +
2 EXACT_MARGIN``: the body keeps that much clearance between the samples, beyond the distance
queries' round-off); an interval the test does not pass is bisected below the tolerance, down to
``tolerance / EXACT_REFINE``, and one not passed there is reported as not certified: a motion
certified so is free at every parameter, so no sampling of it (nor of any part of it) finds a
collision. It accepts every motion that keeps a clearance above ``tolerance / EXACT_REFINE +
EXACT_MARGIN`` (its last intervals pass the test): a walk or rotation that passes a gap with a
millimetre to spare is certified, not refused for coming within the tolerance.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

#: Default tolerance of swept checks (m): the largest unchecked motion of any point.
SWEEP_TOLERANCE = 0.002
#: Clearance (m) an exact certificate keeps between samples: above the distance queries'
#: round-off (coal's GJK answers within about a micrometre), so that another query of a pose
#: between two samples cannot find it touching.
EXACT_MARGIN = 1e-6
#: How much finer than the tolerance an exact certificate bisects an interval before it
#: refuses it (the finest span is ``2 tolerance / EXACT_REFINE`` of motion).
EXACT_REFINE = 16


@dataclass(frozen=True)
class SweepResult:
    """Outcome of :func:`certify`.

    Attributes:
        valid: the whole motion is collision-free (to the tolerance).
        first_collision: a sampled parameter found in collision, searching left first
            (1.0 if valid).
        queries: number of clearance queries made.
    """

    valid: bool
    first_collision: float
    queries: int


def certify(clearance: Callable[[float], float], lipschitz: float, *,
            tolerance: float = SWEEP_TOLERANCE, d0: float | None = None,
            d1: float | None = None, exact: bool = False) -> SweepResult:
    """Certify that ``clearance(s) > 0`` along ``s`` in [0, 1] (see the module docstring).

    Args:
        clearance: distance (m) from the moving body at parameter ``s`` to the obstacles.
        lipschitz: bound ``M`` (m) on any point's displacement over the whole motion.
        tolerance: accepted unchecked displacement (m).
        d0: clearance at ``s = 0`` if already known.
        d1: clearance at ``s = 1`` if already known.
        exact: accept an interval only by the clearance test (see the module docstring); an
            interval not certified at ``tolerance / EXACT_REFINE`` is then reported at its
            middle.
    """
    queries = 0
    if d0 is None:
        d0 = clearance(0.0)
        queries += 1
    if d0 <= 0:
        return SweepResult(False, 0.0, queries)
    if d1 is None:
        d1 = clearance(1.0)
        queries += 1
    if d1 <= 0:
        return SweepResult(False, 1.0, queries)
    stack = [(0.0, d0, 1.0, d1)]
    slack = 2.0 * EXACT_MARGIN if exact else 0.0
    while stack:
        a, da, b, db = stack.pop()
        span = lipschitz * (b - a)
        if da + db > span + slack:
            continue
        m = 0.5 * (a + b)
        if span <= 2.0 * tolerance:
            if not exact:
                continue
            if span <= 2.0 * tolerance / EXACT_REFINE:
                return SweepResult(False, m, queries)
        dm = clearance(m)
        queries += 1
        if dm <= 0:
            return SweepResult(False, m, queries)
        stack.append((m, dm, b, db))
        stack.append((a, da, m, dm))
    return SweepResult(True, 1.0, queries)

"""Where a motion's seconds go, and the :class:`~pivot_ompl.planfile.DurationModel` it implies.

:func:`duration_breakdown` splits a generated motion by plan element from its own ``phase``
and ``step`` labels: each pivot step's seconds (the ticks labelled with it, from the middle of
the double support before its first step to the middle of the one after its last, plus the
rest at the end of a walk), each transfer phase's remainder (reach, tilt, set down, release,
a walk to the phase start) and each transit's seconds. :func:`fit_duration_model` fits the
model's coefficients to it by least squares: ``pivot = per_pivot + per_radian * |angle|``
over the pivots, ``transit = per_transit + per_walk_m * length`` over the transits (the
coefficients kept non-negative), ``per_transfer`` the mean remainder.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import DurationModel, Plan, TransferPhase, TransitPhase


@dataclass
class DurationBreakdown:
    """Seconds of a motion per plan element.

    Attributes:
        total: the motion's duration (s).
        pivots: (``|angle|`` (rad), seconds) of every pivot step, in plan order.
        transfer_rest: seconds of each transfer phase outside its pivot steps.
        transits: (length (m), seconds) of every transit phase.
    """

    total: float
    pivots: list[tuple[float, float]] = field(default_factory=list)
    transfer_rest: list[float] = field(default_factory=list)
    transits: list[tuple[float, float]] = field(default_factory=list)

    @property
    def per_pivot_mean(self) -> float:
        """Mean seconds of a pivot step."""
        return float(np.mean([s for _, s in self.pivots])) if self.pivots else 0.0


def duration_breakdown(motion: Motion, plan: Plan) -> DurationBreakdown:
    """Seconds of ``motion`` per pivot step, transfer remainder and transit of ``plan``.

    Raises:
        InputError: the motion has no phase labels or not the plan's phases.
    """
    if motion.phase is None or int(motion.phase.max()) + 1 != len(plan.phases):
        raise InputError("plan.phases", len(plan.phases), "is not the motion's plan")
    dt = motion.dt
    phase = motion.phase
    step = motion.step if motion.step is not None else np.full(len(phase), -1)
    out = DurationBreakdown(total=motion.duration)
    for p, ph in enumerate(plan.phases):
        in_phase = phase == p
        seconds = float(np.count_nonzero(in_phase)) * dt
        if isinstance(ph, TransitPhase):
            out.transits.append((ph.length, seconds))
            continue
        assert isinstance(ph, TransferPhase)
        labels = step[in_phase]
        counts = np.bincount(labels[labels >= 0], minlength=len(ph.steps))
        for st, n in zip(ph.steps, counts, strict=False):
            out.pivots.append((abs(st.angle), float(n) * dt))
        out.transfer_rest.append(seconds - float(counts.sum()) * dt)
    return out


def _line(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares ``y = a + b x`` with ``a, b >= 0`` (one of them zero if needed)."""
    if len(x) >= 2 and np.ptp(x) > 1e-9:
        b, a = np.polyfit(x, y, 1)
        if a >= 0 and b >= 0:
            return float(a), float(b)
    a0 = max(float(np.mean(y)), 0.0)
    b0 = max(float(np.dot(x, y) / np.dot(x, x)), 0.0) if np.dot(x, x) > 0 else 0.0
    err_a = float(np.sum((y - a0) ** 2))
    err_b = float(np.sum((y - b0 * x) ** 2))
    return (a0, 0.0) if err_a <= err_b else (0.0, b0)


def fit_duration_model(breakdown: DurationBreakdown) -> DurationModel:
    """The :class:`DurationModel` that fits ``breakdown`` (see the module docstring).

    Coefficients without data (no pivot or no transit) keep the model's defaults.
    """
    d = DurationModel()
    per_pivot, per_radian = d.per_pivot, d.per_radian
    per_transit, per_walk_m = d.per_transit, d.per_walk_m
    if breakdown.pivots:
        a = np.array(breakdown.pivots)
        per_pivot, per_radian = _line(a[:, 0], a[:, 1])
    if breakdown.transits:
        a = np.array(breakdown.transits)
        per_transit, per_walk_m = _line(a[:, 0], a[:, 1])
    per_transfer = (float(np.mean(breakdown.transfer_rest)) if breakdown.transfer_rest
                    else d.per_transfer)
    return DurationModel(per_transfer=per_transfer, per_pivot=per_pivot,
                         per_radian=per_radian, per_transit=per_transit,
                         per_walk_m=per_walk_m)

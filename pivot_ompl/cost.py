"""What a plan costs: the seconds of its whole-body execution plus a price per regrasp.

One model, used by the regrasp planner's search and its path optimiser alike, and reported by
the plan's quality block:

* :class:`DurationModel`: seconds of HRP-2 whole-body motion per plan element, fitted to the
  whole-body generator (:func:`pivot_ompl.wholebody.durations.fit_duration_model`);
* :class:`CostModel`: those seconds plus :attr:`CostModel.regrasp` seconds per regrasp, the
  price of releasing the box and taking it again on a real robot beyond the time it takes
  (the default, :data:`REGRASP_COST`, is justified there).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Protocol

#: Default price of one regrasp (s), beyond its execution time. A release and re-grasp is the
#: riskiest moment of the task on a real humanoid: the box is set down and tilted again, the
#: hands leave it and must find it again after a walk whose end pose drifts by centimetres,
#: and a missed grasp costs a recovery (perceive the box again, re-plan, retry, often with an
#: operator) of a quarter to half an hour. With a failure rate of 10-20 % per re-grasp the
#: expected loss is about 2-6 minutes; we take 300 s, so a plan trades up to five minutes of
#: pivoting (a half turn of robot and box in place costs about one) for one regrasp less, and
#: never adds a regrasp to save less. ``--regrasp-cost`` sets it per plan.
REGRASP_COST = 300.0


class _Turn(Protocol):
    """A pivot rotation, as far as its price is concerned."""

    @property
    def angle(self) -> float:
        """Signed rotation angle (rad)."""


class _Turns(Protocol):
    """A pivot sequence, as far as its price is concerned."""

    @property
    def rotations(self) -> Iterable[_Turn]:
        """The rotations in order."""


@dataclass(frozen=True)
class DurationModel:
    """Seconds of whole-body motion per plan element (the HRP-2 generator's defaults).

    The defaults are produced by ``python benchmarks/duration_model.py`` (scenes ``fig10``,
    ``slot`` and ``door``, seed 0; rounded to 0.1 s): it plans the scenes, makes their motions
    with :mod:`pivot_ompl.wholebody` (default timing, the scene's walk model) and fits
    :func:`pivot_ompl.wholebody.durations.fit_duration_model` (least squares per pivot step
    and per transit, the transfer remainder's mean) to the three motions at once.
    ``tests/wholebody/test_duration_model.py`` holds each plan's estimate within 5 % of its
    motion (fig10 673 s for 675.3 s, slot 289 for 295.9, door 502 for 507.7). The
    robot walks the pivot steps of a transfer continuously, two or three steps a pivot, so a
    rotation costs mostly by itself and little by its angle; a metre walked alone costs 10 s
    because the planned walks are often sideways or backward. Pivots that move the robot
    farther than its step (a deeper box: the 0.6 m of ``corridor``) take a step more, which
    the model does not see (``corridor``'s motion is 268 s, its estimate 244 s).

    Attributes:
        per_transfer: a transfer phase's fixed part: reaching, tilting, setting down,
            releasing (s).
        per_pivot: one pivot rotation's fixed part (s).
        per_radian: per radian turned (s/rad).
        per_transit: a transit's fixed part: starting and stopping the walk (s).
        per_walk_m: one metre walked alone (s/m).
    """

    per_transfer: float = 5.1
    per_pivot: float = 2.6
    per_radian: float = 0.0
    per_transit: float = 0.0
    per_walk_m: float = 10.4

    def seconds(self, *, transfers: int, pivots: int, turned: float, transits: int,
                walked: float) -> float:
        """Seconds of a plan of ``transfers`` and ``transits`` phases.

        ``pivots`` rotations turning ``turned`` rad in all, ``walked`` m walked alone.
        """
        return (self.per_transfer * transfers + self.per_pivot * pivots
                + self.per_radian * turned + self.per_transit * transits
                + self.per_walk_m * walked)


@dataclass(frozen=True)
class CostModel:
    """Seconds of execution (:class:`DurationModel`) plus a price per regrasp.

    Attributes:
        regrasp: price of one regrasp (s) on top of its execution seconds
            (:data:`REGRASP_COST`).
        durations: the execution seconds of each plan element.
    """

    regrasp: float = REGRASP_COST
    durations: DurationModel = field(default_factory=DurationModel)

    def rotations(self, angles: Iterable[float]) -> float:
        """Seconds of a sequence of pivot rotations (angles in rad)."""
        d = self.durations
        n, turned = 0, 0.0
        for a in angles:
            n += 1
            turned += abs(a)
        return d.per_pivot * n + d.per_radian * turned

    def sequence(self, sequence: _Turns) -> float:
        """Seconds of a transfer's pivot sequence (:meth:`rotations` of its angles)."""
        return self.rotations(r.angle for r in sequence.rotations)

    def plan_cost(self, seconds: float, regrasps: int) -> float:
        """The cost of a plan of ``seconds`` of execution and ``regrasps`` regrasps (s)."""
        return seconds + self.regrasp * regrasps

    def push_rate(self, half_length: float, alpha_max: float) -> float:
        """Seconds per metre of a straight push by full alternating rotations.

        Each rotation of ``alpha_max`` moves the supporting edge's centre by
        ``2 l sin(alpha_max / 2)`` (``l``: the edge's half-length).
        """
        d = self.durations
        return (d.per_pivot + d.per_radian * alpha_max) / (
            2.0 * half_length * math.sin(0.5 * alpha_max))

    def transfer_estimate(self, length: float, half_length: float, alpha_max: float) -> float:
        """Estimated seconds of a transfer along a Reeds-Shepp path ``length`` m long."""
        return length * self.push_rate(half_length, alpha_max)

    def transfer_bound(self, distance: float, turn: float, half_length: float,
                       alpha_max: float) -> float:
        """Fewest seconds of any transfer moving the edge's centre by ``distance`` (m).

        The edge also turns by ``turn`` (rad). A rotation by ``a`` moves the centre by at most
        ``2 l sin(|a|/2) <= l |a|`` and turns it by ``|a| <= alpha_max``: at least
        ``max(distance / (2 l sin(alpha_max/2)), |turn| / alpha_max)`` rotations, turning
        ``max(distance / l, |turn|)`` rad in all.
        """
        d = self.durations
        pivots = max(distance / (2.0 * half_length * math.sin(0.5 * alpha_max)),
                     abs(turn) / alpha_max)
        radians = max(distance / half_length, abs(turn))
        return d.per_pivot * pivots + d.per_radian * radians

    def spin_estimate(self, turn: float, alpha_max: float) -> float:
        """Estimated seconds of a spin (a turn in place) by ``turn`` rad.

        Pieces of at most ``2 alpha_max``, each solved by three rotations turning ``|turn|``
        rad in all (:mod:`pivot_ompl.pivoting.steering`).
        """
        d = self.durations
        pieces = math.ceil(abs(turn) / (2.0 * alpha_max) - 1e-12)
        return d.per_pivot * 3 * pieces + d.per_radian * abs(turn)

    def regrasp_seconds(self, walk_length: float) -> float:
        """The cost of one regrasp whose walk is ``walk_length`` m long (s).

        The price, the walk (fixed part and metres) and the new transfer phase's fixed part.
        """
        d = self.durations
        return self.regrasp + d.per_transit + d.per_transfer + d.per_walk_m * walk_length

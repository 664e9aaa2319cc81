"""The pivoting steering method: a Reeds-Shepp path turned into bounded pivot rotations.

From the controllability paper (Section IV-B): try to join the two ends of the Reeds-Shepp
path by three rotations; if that fails, split the path at mid-length (poses taken on the
*original* path with OMPL's ``interpolate``) and recurse. Each piece is solved from the pose
actually reached, so no error accumulates and the goal is reached exactly (round-off only).
Consecutive rotations about the same corner are merged when the sum stays within the bound,
which removes the redundant rotation at every junction of two pieces.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from pivot_ompl.errors import InputError, Interrupted, SteeringError
from pivot_ompl.pivoting.kinematics import Rotation, solve_piece
from pivot_ompl.pivoting.reeds_shepp import ReedsShepp
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

#: Deepest dichotomy level before giving up (a piece of 2**-40 of the path).
MAX_DEPTH = 40


@dataclass(frozen=True)
class PivotSequence:
    """A Reeds-Shepp path converted to pivot rotations.

    Attributes:
        start: car pose at the start.
        goal: car pose requested.
        rotations: the rotations in order; ``rotations[-1].car`` is the goal up to round-off.
        rs_length: length of the Reeds-Shepp path (m).
        pieces: number of path pieces solved by three rotations.
    """

    start: Pose
    goal: Pose
    rotations: tuple[Rotation, ...]
    rs_length: float
    pieces: int

    @property
    def end(self) -> Pose:
        """The car pose actually reached."""
        return self.rotations[-1].car if self.rotations else self.start

    @property
    def max_abs_angle(self) -> float:
        """Largest ``|angle|`` over the rotations (rad)."""
        return max((abs(r.angle) for r in self.rotations), default=0.0)


@dataclass
class PivotSteering:
    """Converts Reeds-Shepp paths between car poses into pivot rotations.

    Args:
        turning_radius: Reeds-Shepp minimum turning radius (m).
        alpha_max: bound on each rotation (rad), in (0, pi/2].
        merge: merge consecutive rotations about the same corner when within ``alpha_max``.
    """

    turning_radius: float
    alpha_max: float
    merge: bool = True
    rs: ReedsShepp = field(init=False, repr=False)

    def __post_init__(self) -> None:
        """Validate the parameters and build the OMPL Reeds-Shepp space."""
        if not (self.turning_radius > 0 and math.isfinite(self.turning_radius)):
            raise InputError("turning_radius", self.turning_radius, "must be > 0 m")
        if not (0 < self.alpha_max <= 0.5 * math.pi):
            raise InputError("alpha_max", self.alpha_max, "must be in (0, pi/2] rad")
        self.rs = ReedsShepp(turning_radius=self.turning_radius)

    def convert(self, start: Pose, goal: Pose, *, half_length: float,
                should_stop: Callable[[], bool] | None = None) -> PivotSequence:
        """Convert the Reeds-Shepp path ``start -> goal`` (car poses) into pivot rotations.

        Args:
            start: car pose (supporting-edge centre, heading) at the start.
            goal: car pose to reach.
            half_length: half-length ``l`` of the supporting edge (m).
            should_stop: termination condition, polled once per path piece.

        Raises:
            SteeringError: the dichotomy did not converge (pieces shorter than 2**-40 of the path).
            Interrupted: ``should_stop()`` became true.
        """
        rotations: list[Rotation] = []
        pieces = 0
        for r, last_of_piece in self.iter_rotations(start, goal, half_length=half_length,
                                                    should_stop=should_stop):
            if r is not None:
                self._append(rotations, r)
            pieces += last_of_piece
        return PivotSequence(start, goal, tuple(rotations), self.rs.distance(start, goal), pieces)

    def iter_rotations(self, start: Pose, goal: Pose, *, half_length: float,
                       should_stop: Callable[[], bool] | None = None,
                       ) -> Iterator[tuple[Rotation | None, bool]]:
        """The dichotomy as a generator, so that a checker can stop at the first collision.

        Yields ``(rotation, ends_piece)`` pairs; a piece solved with no rotation (start and
        target equal) yields ``(None, True)``. Rotations are *not* merged here.

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per path piece).
        """
        if not (half_length > 0):
            raise InputError("half_length", half_length, "must be > 0 m")
        rs = self.rs
        amax = self.alpha_max
        current = start
        # a rotation moves the edge centre by at most l*|alpha|: a cheap necessary condition
        reach = 3.0 * half_length * amax + 1e-9
        # stack of pieces (t0, t1, pose at t1, depth) of the original path, last popped first
        stack: list[tuple[float, float, Pose, int]] = [(0.0, 1.0, goal, 0)]
        while stack:
            if should_stop is not None and should_stop():
                raise Interrupted("pivot steering")
            t0, t1, target, depth = stack.pop()
            if math.hypot(target[0] - current[0], target[1] - current[1]) <= reach:
                ok, rots = solve_piece(current, target, half_length, amax)
                if ok:
                    if not rots:
                        yield None, True
                    for k, r in enumerate(rots):
                        yield r, k == len(rots) - 1
                    if rots:
                        current = rots[-1].car
                    continue
            if depth >= MAX_DEPTH:
                raise SteeringError(start, goal, f"no convergence at t={t0:.6g}..{t1:.6g}")
            mid = 0.5 * (t0 + t1)
            stack.append((mid, t1, target, depth + 1))
            stack.append((t0, mid, rs.interpolate(start, goal, mid), depth + 1))

    def _append(self, rotations: list[Rotation], r: Rotation) -> None:
        """Append ``r``, merged into the previous rotation when both turn about one corner."""
        if self.merge and rotations and rotations[-1].end == r.end:
            prev = rotations[-1]
            total = prev.angle + r.angle
            if abs(total) <= self.alpha_max:
                rotations.pop()
                if abs(total) > 1e-12:
                    rotations.append(Rotation(r.end, prev.pivot, total, r.car))
                return
        rotations.append(r)

"""The pivoting steering method: a Reeds-Shepp path turned into bounded pivot rotations.

From the controllability paper (Section IV-B): join poses of the Reeds-Shepp path by three
rotations, each piece solved from the pose actually reached (so no error accumulates and the
goal is reached exactly, round-off only). Pieces are the **longest** that three rotations
reach: from the pose reached at parameter ``t0`` the steering gallops along the path (the
previous piece's length, then doubling) and bisects back to the farthest parameter ``t1``
solvable by three rotations, so a straight push runs at the ideal alternating rate
``2 l sin(alpha/2)`` per rotation. Poses are taken on the *original* path with OMPL's
``interpolate``.

Small-time property: a piece's rotations must keep the car's centre within
``deviation_ratio`` times the piece's length of the piece's chord (:func:`solve_piece`'s
``max_deviation``); a solution that strays further is refused and the piece shortened. The
pivot path therefore stays in a neighbourhood of the Reeds-Shepp path that shrinks with the
path (controllability paper: small-time local controllability), however short the move.

Consecutive rotations about the same corner are merged when the sum stays within the bound,
which removes the redundant rotation at every junction of two pieces.

Between two car poses at the same position the reference path is a **spin**, a turn in place
(:class:`~pivot_ompl.pivoting.curves.CarPaths`): three rotations solve each piece of it too
(``a/4`` about one end, ``a/2`` about the other, ``a/4`` about the first: the car turns by
``a`` and comes back to its place), so the box swings round with the robot wherever the
assembly has room, as the regrasp paper's robot did with "backward and forward manipulation".
A whole spin is converted as one piece, a chain of rotations closed at the car's place
(:func:`~pivot_ompl.pivoting.spin_chain.whole_spin`), where that takes fewer rotations than
its equal pieces (a local refinement's spin stretch is cut into pieces as before).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field
from typing import NamedTuple

from pivot_ompl.errors import InputError, Interrupted, SteeringError
from pivot_ompl.pivoting.curves import CarPaths
from pivot_ompl.pivoting.kinematics import ANGLE_TOL, Rotation, solve_piece
from pivot_ompl.pivoting.piece_search import fewer_pivots, longest, merges, spin_step
from pivot_ompl.pivoting.spin_chain import whole_spin
from pivot_ompl.se2 import Pose, wrap_angle

log = logging.getLogger(__name__)

#: Deepest halving of a piece before giving up (a piece of 2**-40 of the path).
MAX_DEPTH = 40

#: A piece's rotations keep the car within this fraction of the piece's length of its chord.
DEVIATION_RATIO = 0.5

#: Where the path left after the longest piece is shorter than this share of that piece,
#: the piece and the rest are made two equal pieces (no piece of near-zero rotations). Only
#: in a whole path's conversion: a local refinement's pieces are chosen by its checks.
TAIL_SHARE = 0.5


#: What a local refinement sends back to :meth:`PivotSteering.iter_pieces`: the pose reached,
#: the last rotation and, optionally, the path's parameter reached.
Sent = tuple[Pose, Rotation | None] | tuple[Pose, Rotation | None, float]


class Piece(NamedTuple):
    """One piece of a Reeds-Shepp path solved by (at most three) rotations, or a whole spin.

    Attributes:
        t0, t1: the piece's parameters on the path (fractions of its length).
        start: the car pose actually reached at ``t0`` (where the rotations start).
        target: the path's pose at ``t1`` (reached by the rotations up to round-off).
        rotations: the rotations, unmerged (empty when ``start`` already is ``target``;
            a whole spin's chain, :func:`~pivot_ompl.pivoting.spin_chain.whole_spin`).
    """

    t0: float
    t1: float
    start: Pose
    target: Pose
    rotations: tuple[Rotation, ...]


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


#: Path lengths and span-end poses :class:`PivotSteering` keeps (then it starts afresh).
KEPT_PATHS = 4096

#: Largest car-pose coordinate magnitude accepted (m).
MAX_CAR_COORD = 1.0e6


def car_pose(value: object, field: str) -> Pose:
    """``value`` as a car pose ``(x, y, heading)`` of finite numbers.

    Raises:
        InputError: not a sequence of three numbers, one not finite or beyond
            :data:`MAX_CAR_COORD` (naming ``field``).
    """
    if type(value) is tuple and len(value) == 3 and type(value[0]) is float and \
            type(value[1]) is float and type(value[2]) is float and \
            abs(value[0]) <= MAX_CAR_COORD and abs(value[1]) <= MAX_CAR_COORD and \
            abs(value[2]) <= MAX_CAR_COORD:
        return value  # already a pose of finite floats (the steering's own, every piece)
    if isinstance(value, str | bytes) or not hasattr(value, "__len__") or \
            not hasattr(value, "__getitem__"):
        raise InputError(field, type(value).__name__, "must be a pose (x, y, heading)")
    if len(value) != 3:
        raise InputError(field, value, "must be a pose of 3 numbers (x, y, heading)")
    out = []
    for i in range(3):
        v = value[i]
        if isinstance(v, bool) or not isinstance(v, int | float) and \
                type(v).__module__ != "numpy":
            raise InputError(f"{field}[{i}]", v, "must be a number")
        try:
            x = float(v)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"{field}[{i}]", v, "must be a number") from None
        if not abs(x) <= MAX_CAR_COORD:
            raise InputError(f"{field}[{i}]", v, f"must be finite, within +-{MAX_CAR_COORD:g}")
        out.append(x)
    return (out[0], out[1], out[2])


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
    paths: CarPaths = field(init=False, repr=False)
    #: the paths' lengths and the poses at a refinement's span ends, by path (and fraction):
    #: a refinement converts one path's stretch again at several rotation bounds
    _lengths: dict[tuple[Pose, Pose], float] = field(init=False, repr=False, compare=False,
                                                     default_factory=dict)
    _poses: dict[tuple[Pose, Pose, float], Pose] = field(init=False, repr=False, compare=False,
                                                         default_factory=dict)

    def __post_init__(self) -> None:
        """Validate the parameters and build the OMPL Reeds-Shepp space."""
        for name in ("turning_radius", "alpha_max"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise InputError(name, type(v).__name__, "must be a number")
        if not isinstance(self.merge, bool):
            raise InputError("merge", self.merge, "must be True or False")
        if not (self.turning_radius > 0 and math.isfinite(self.turning_radius)):
            raise InputError("turning_radius", self.turning_radius, "must be > 0 m")
        if not (0 < self.alpha_max <= 0.5 * math.pi):
            raise InputError("alpha_max", self.alpha_max, "must be in (0, pi/2] rad")
        self.paths = CarPaths(turning_radius=self.turning_radius)

    def convert(self, start: Pose, goal: Pose, *, half_length: float,
                should_stop: Callable[[], bool] | None = None) -> PivotSequence:
        """Convert the Reeds-Shepp path ``start -> goal`` (car poses) into pivot rotations.

        Args:
            start: car pose (supporting-edge centre, heading) at the start.
            goal: car pose to reach.
            half_length: half-length ``l`` of the supporting edge (m).
            should_stop: termination condition, polled once per path piece.

        Raises:
            SteeringError: no piece solvable from some pose (pieces shorter than 2**-40).
            Interrupted: ``should_stop()`` became true.
        """
        rotations: list[Rotation] = []
        pieces = 0
        for piece in self.iter_pieces(start, goal, half_length=half_length,
                                      should_stop=should_stop):
            for r in piece.rotations:
                self.append_merged(rotations, r)
            pieces += 1
        return PivotSequence(start, goal, tuple(rotations), self.paths.distance(start, goal),
                             pieces)

    def iter_rotations(self, start: Pose, goal: Pose, *, half_length: float,
                       should_stop: Callable[[], bool] | None = None,
                       ) -> Iterator[tuple[Rotation | None, bool]]:
        """The pieces' rotations one by one, so that a checker can stop at the first collision.

        Yields ``(rotation, ends_piece)`` pairs; a piece solved with no rotation (start and
        target equal) yields ``(None, True)``. Rotations are *not* merged here.

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per path piece).
        """
        for piece in self.iter_pieces(start, goal, half_length=half_length,
                                      should_stop=should_stop):
            if not piece.rotations:
                yield None, True
            for k, r in enumerate(piece.rotations):
                yield r, k == len(piece.rotations) - 1

    def iter_pieces(self, start: Pose, goal: Pose, *, half_length: float,
                    should_stop: Callable[[], bool] | None = None,
                    span: tuple[float, float] = (0.0, 1.0), origin: Pose | None = None,
                    alpha_max: float | None = None, previous: Rotation | None = None,
                    ) -> Generator[Piece, Sent | None, None]:
        """The longest pieces of the Reeds-Shepp path ``start -> goal``, in order.

        Args:
            start: car pose at the start of the Reeds-Shepp path.
            goal: car pose at its end.
            half_length: half-length ``l`` of the supporting edge (m).
            should_stop: termination condition, polled once per piece.
            span: the parameters ``(t0, t1)`` of the part of the path to convert (a local
                refinement converts one piece's part again).
            origin: the car pose actually reached at ``span[0]`` (default: the path's pose).
            alpha_max: bound on each rotation (rad), at most the steering's (default: it).
            previous: the rotation made just before ``origin`` (a local refinement's
                rotations so far): the first piece prefers rotations that merge into it.

        A caller that replaces a piece by its own rotations (a local refinement) sends the
        generator ``(pose reached, last rotation)`` back, or ``(pose reached, last rotation,
        parameter reached)`` (the parameter at the piece's end or past it: a refinement's
        last sub-piece may run on); the next piece starts there.

        Raises:
            SteeringError: no piece solvable from some pose (pieces shorter than 2**-40).
            Interrupted: ``should_stop()`` became true.
        """
        start, goal = car_pose(start, "start"), car_pose(goal, "goal")
        origin = None if origin is None else car_pose(origin, "origin")
        if isinstance(half_length, bool) or not isinstance(half_length, int | float) or \
                not (0 < half_length < math.inf):
            raise InputError("half_length", half_length, "must be > 0 m")
        if should_stop is not None and not callable(should_stop):
            raise InputError("should_stop", type(should_stop).__name__, "must be callable")
        if (not isinstance(span, tuple | list) or len(span) != 2
                or not all(isinstance(t, int | float) and not isinstance(t, bool) for t in span)
                or not 0.0 <= span[0] <= span[1] <= 1.0):
            raise InputError("span", span, "must be (t0, t1) with 0 <= t0 <= t1 <= 1")
        if previous is not None and not isinstance(previous, Rotation):
            raise InputError("previous", type(previous).__name__, "must be a Rotation or None")
        amax = self.alpha_max if alpha_max is None else alpha_max
        if isinstance(amax, bool) or not isinstance(amax, int | float) or \
                not (0 < amax <= self.alpha_max):
            raise InputError("alpha_max", amax, f"must be in (0, {self.alpha_max}] rad")
        rs = self.paths
        ell = half_length
        t0, t_end = span
        length = self._length(start, goal)
        # the small-time neighbourhood scales with the path's length; a spin's with the arc
        # the edge's ends trace
        scale = ell * abs(wrap_angle(goal[2] - start[2])) if rs.is_spin(start, goal) \
            else length
        current = origin if origin is not None else (
            start if t0 == 0.0 else self._pose_at(start, goal, t0))
        end_pose = goal if t_end == 1.0 else self._pose_at(start, goal, t_end)
        spin = rs.is_spin(start, goal)
        plain = origin is None and span == (0.0, 1.0)  # not a local refinement
        # a rotation moves the edge centre by at most 2 l sin(alpha/2): a necessary condition
        reach = 6.0 * ell * math.sin(0.5 * amax) + 1e-9
        # first guess: the ideal push's piece (two full rotations)
        step = (4.0 * ell * math.sin(0.5 * amax) / length) if length > 0 else 1.0
        min_step = (t_end - t0) * 2.0 ** -MAX_DEPTH

        point = rs.along(start, goal)

        def solve(t: float) -> tuple[Pose, tuple[Rotation, ...]] | None:
            target = end_pose if t >= t_end else point(t)
            if math.hypot(target[0] - current[0], target[1] - current[1]) > reach:
                return None
            ok, rots = solve_piece(current, target, ell, amax,
                                   max_deviation=DEVIATION_RATIO * (t - t0) * scale + 1e-12,
                                   previous=previous)
            return (target, rots) if ok else None

        # a whole spin's pieces: equal, as many as make the fewest rotations (spin_step);
        # else the search for a piece that merges into the previous one (on Reeds-Shepp arcs,
        # and on a refined spin's stretch, whose longest pieces' outer rotations, a little
        # over a quarter of the turn each, sum to just over the bound at a junction)
        even = spin_step(solve, amax, abs(wrap_angle(goal[2] - start[2]))) \
            if spin and plain and self.merge else None
        arc = self.merge and even is None
        if even is not None:
            chain = whole_spin(solve, even, current, end_pose, ell, amax,
                               DEVIATION_RATIO * scale)
            if chain is not None:  # one piece: the whole turn, fewer rotations
                yield Piece(t0, t_end, current, end_pose, chain)
                return
        while t0 < t_end:
            if should_stop is not None and should_stop():
                raise Interrupted("pivot steering")
            step = min(max(step, min_step), t_end - t0)
            t_even = t_end if even is None or t_end - t0 < 1.5 * even else t0 + even
            solved = solve(t_even) if even is not None else None
            if solved is not None:  # the spin's next equal piece
                t_ok, (target, rots) = t_even, solved
            else:
                t_ok, (target, rots) = longest(solve, t0, t_end, step, min_step,
                                                lambda t: SteeringError(
                                                    start, goal, f"no convergence at t={t:.6g}"))
            if solved is None and arc and previous is not None and len(rots) == 3 and \
                    rots[0].end == previous.end and not merges(previous, rots[0], amax):
                t_ok, (target, rots) = fewer_pivots(solve, previous, amax, t0, t_ok,
                                                     (target, rots))
            if solved is None and t_ok < t_end and t_end - t_ok < TAIL_SHARE * (t_ok - t0) \
                    and plain:
                # a short rest would be a piece of near-zero rotations: halve what is left
                halved = solve(t0 + 0.5 * (t_end - t0))
                if halved is not None:
                    t_ok, (target, rots) = t0 + 0.5 * (t_end - t0), halved
            sent = yield Piece(t0, t_ok, current, target, rots)
            if sent is not None:  # the caller replaced the piece (a local refinement)
                current, previous = sent[0], sent[1]
                step = t_ok - t0
                t0 = max(t_ok, min(t_end, sent[2])) if len(sent) == 3 else t_ok
                continue
            if rots:
                current = rots[-1].car
                previous = rots[-1]
            step = t_ok - t0
            t0 = t_ok

    def _length(self, start: Pose, goal: Pose) -> float:
        """``paths.distance(start, goal)``, kept (:data:`KEPT_PATHS` paths and poses)."""
        key = (start, goal)
        known = self._lengths.get(key)
        if known is None:
            if len(self._lengths) >= KEPT_PATHS:
                self._lengths.clear()
            known = self._lengths[key] = self.paths.distance(start, goal)
        return known

    def _pose_at(self, start: Pose, goal: Pose, t: float) -> Pose:
        """``paths.interpolate(start, goal, t)``, kept as :meth:`_length` keeps lengths."""
        key = (start, goal, t)
        known = self._poses.get(key)
        if known is None:
            if len(self._poses) >= KEPT_PATHS:
                self._poses.clear()
            known = self._poses[key] = self.paths.interpolate(start, goal, t)
        return known

    def append_merged(self, rotations: list[Rotation], r: Rotation) -> None:
        """Append ``r``, merged into the previous rotation when both turn about one corner."""
        if self.merge and rotations and rotations[-1].end == r.end:
            prev = rotations[-1]
            total = prev.angle + r.angle
            if abs(total) <= self.alpha_max + ANGLE_TOL:  # round-off of two halves
                rotations.pop()
                if abs(total) > 1e-12:
                    rotations.append(Rotation(r.end, prev.pivot, total, r.car))
                return
        rotations.append(r)

"""Curvature-bounded curves from OMPL's SE(2) spaces, behind one small wrapper.

:class:`ReedsShepp` (forward and backward, the pivoting car) and :class:`Dubins` (forward
only, the robot walking forward) share it: only the OMPL space differs.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

from ompl import base as ob

from pivot_ompl.se2 import Pose, wrap_angle


class Curves:
    """Shortest curves of one OMPL SE(2) space with a minimum turning radius.

    Args:
        turning_radius: minimum turning radius (m).
    """

    #: The OMPL space class (a constructor taking the turning radius).
    space_class: ClassVar[Any]

    def __init__(self, *, turning_radius: float) -> None:
        self.turning_radius = float(turning_radius)
        self.space = self.space_class(self.turning_radius)
        bounds = ob.RealVectorBounds(2)
        bounds.setLow(-1e6)
        bounds.setHigh(1e6)
        self.space.setBounds(bounds)
        self._a = self.space.allocState()
        self._b = self.space.allocState()
        self._out = self.space.allocState()
        self._pair: tuple[Pose, Pose] | None = None  # the poses the states hold

    def _set(self, a: Pose, b: Pose) -> None:
        pair = self._pair
        if pair is not None and pair[0] is a and pair[1] is b:
            return  # the same tuples (immutable): a piece search asks one path many times
        # only tuples are remembered: a list or an array may be changed in place
        self._pair = (a, b) if type(a) is tuple and type(b) is tuple else None
        self._a.setXY(a[0], a[1])
        self._a.setYaw(a[2])
        self._b.setXY(b[0], b[1])
        self._b.setYaw(b[2])

    def distance(self, a: Pose, b: Pose) -> float:
        """Length of the shortest curve from ``a`` to ``b`` (m)."""
        self._set(a, b)
        return float(self.space.distance(self._a, self._b))

    def interpolate(self, a: Pose, b: Pose, t: float) -> Pose:
        """The pose at fraction ``t`` in [0, 1] of the curve's length along ``a -> b``."""
        self._set(a, b)
        out = self._out
        self.space.interpolate(self._a, self._b, t, out)
        return (out.getX(), out.getY(), out.getYaw())

    def sample(self, a: Pose, b: Pose, ts: list[float]) -> list[Pose]:
        """Poses at each fraction of ``ts`` along the curve ``a -> b``."""
        self._set(a, b)
        out = self._out
        res = []
        for t in ts:
            self.space.interpolate(self._a, self._b, t, out)
            res.append((out.getX(), out.getY(), out.getYaw()))
        return res


class ReedsShepp(Curves):
    """Reeds-Shepp curves (forward and backward): OMPL's ``ReedsSheppStateSpace``."""

    space_class = ob.ReedsSheppStateSpace


class Dubins(Curves):
    """Dubins curves (forward only): OMPL's ``DubinsStateSpace``."""

    space_class = ob.DubinsStateSpace


#: Two car poses closer than this (m) share their position: the path between them is a spin.
SPIN_TOL = 1e-9
#: A spin's length is the arc a point this far from the car (m, about a supporting edge's
#: half-length) traces: it only sets how densely cheap tests sample a spin.
SPIN_RADIUS = 0.3


class CarPaths:
    """The pivoting car's reference paths: Reeds-Shepp curves, and spins (turns in place).

    Pivoting is small-time controllable: rotations about the two ends of the supporting
    edge, turning the same way in turn, spin the car about its own position (the box swings
    round with the robot: "backward and forward manipulation"), which no Reeds-Shepp curve
    of a positive turning radius does. Where two car poses share their position (within
    :data:`SPIN_TOL`), the path between them is the spin: the position fixed, the heading
    turned linearly the short way round (by exactly pi: clockwise, as :func:`wrap_angle`
    maps pi to -pi). Elsewhere it is the Reeds-Shepp curve.

    Args:
        turning_radius: the Reeds-Shepp curves' turning radius (m).
    """

    def __init__(self, *, turning_radius: float) -> None:
        """The curves of this turning radius."""
        self.rs = ReedsShepp(turning_radius=turning_radius)

    @staticmethod
    def is_spin(a: Pose, b: Pose) -> bool:
        """Whether the path ``a -> b`` is a spin (same position, another heading)."""
        return abs(b[0] - a[0]) <= SPIN_TOL and abs(b[1] - a[1]) <= SPIN_TOL and \
            abs(wrap_angle(b[2] - a[2])) > 0.0

    def distance(self, a: Pose, b: Pose) -> float:
        """Length of the path ``a -> b`` (m; a spin's by :data:`SPIN_RADIUS`)."""
        if self.is_spin(a, b):
            return SPIN_RADIUS * abs(wrap_angle(b[2] - a[2]))
        return self.rs.distance(a, b)

    def interpolate(self, a: Pose, b: Pose, t: float) -> Pose:
        """The pose at fraction ``t`` in [0, 1] of the path ``a -> b``."""
        if self.is_spin(a, b):
            return (a[0], a[1], wrap_angle(a[2] + t * wrap_angle(b[2] - a[2])))
        return self.rs.interpolate(a, b, t)

    def along(self, a: Pose, b: Pose) -> Callable[[float], Pose]:
        """:meth:`interpolate` on the path ``a -> b`` as a function of ``t`` (spin told once)."""
        if self.is_spin(a, b):
            turn = wrap_angle(b[2] - a[2])
            return lambda t: (a[0], a[1], wrap_angle(a[2] + t * turn))
        rs = self.rs
        return lambda t: rs.interpolate(a, b, t)

    def sample(self, a: Pose, b: Pose, ts: list[float]) -> list[Pose]:
        """Poses at each fraction of ``ts`` along the path ``a -> b``."""
        if self.is_spin(a, b):
            turn = wrap_angle(b[2] - a[2])
            return [(a[0], a[1], wrap_angle(a[2] + t * turn)) for t in ts]
        return self.rs.sample(a, b, ts)

"""Curvature-bounded curves from OMPL's SE(2) spaces, behind one small wrapper.

:class:`ReedsShepp` (forward and backward, the pivoting car) and :class:`Dubins` (forward
only, the robot walking forward) share it: only the OMPL space differs.
"""

from __future__ import annotations

from typing import Any, ClassVar

from ompl import base as ob

from pivot_ompl.se2 import Pose


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

    def _set(self, a: Pose, b: Pose) -> None:
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

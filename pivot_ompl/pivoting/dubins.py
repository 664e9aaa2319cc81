"""Dubins curves (forward-only, curvature-bounded) from OMPL's ``DubinsStateSpace``."""

from __future__ import annotations

from ompl import base as ob

from pivot_ompl.se2 import Pose


class Dubins:
    """A thin wrapper over one ``ompl.base.DubinsStateSpace``.

    Args:
        turning_radius: minimum turning radius (m).
    """

    def __init__(self, *, turning_radius: float) -> None:
        self.turning_radius = float(turning_radius)
        self.space = ob.DubinsStateSpace(self.turning_radius)
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
        """Length of the shortest Dubins path from ``a`` to ``b`` (m)."""
        self._set(a, b)
        return self.space.distance(self._a, self._b)

    def sample(self, a: Pose, b: Pose, ts: list[float]) -> list[Pose]:
        """Poses at each fraction of ``ts`` along the shortest Dubins path ``a -> b``."""
        self._set(a, b)
        out = self._out
        res = []
        for t in ts:
            self.space.interpolate(self._a, self._b, t, out)
            res.append((out.getX(), out.getY(), out.getYaw()))
        return res

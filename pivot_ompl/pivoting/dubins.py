"""Dubins curves (forward-only, curvature-bounded) from OMPL's ``DubinsStateSpace``."""

from __future__ import annotations

from pivot_ompl.pivoting.curves import Dubins

__all__ = ["Dubins"]

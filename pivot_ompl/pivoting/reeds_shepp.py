"""Reeds-Shepp curves from OMPL's ``ReedsSheppStateSpace`` (never hand-written here)."""

from __future__ import annotations

from pivot_ompl.pivoting.curves import ReedsShepp

__all__ = ["ReedsShepp"]

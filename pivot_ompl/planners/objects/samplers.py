"""Uniform box poses: the random source of every sampler of the object roadmap.

Two distributions: :meth:`PoseSampler.uniform` over the floor's bounds (the bridge test
needs poses in collision too), and :meth:`PoseSampler.reachable` over the box centres the
box could reach from the start at all. A valid box holds the disk of radius half its narrow
side round its centre, so its centre keeps that far (plus the clearance, less the swept
checks' tolerance) from every obstacle and inside the bounds; the positions that do, in the
connected piece holding the start, contain every box position a plan can visit. On a floor
whose bounds hold much that no plan reaches (a rotated building, rooms closed off) the
roadmap then grows only where it can serve.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.footprints import disk_clear, region_vertices

#: Most vertices of the grown obstacles for which :meth:`PoseSampler.reachable` computes its
#: region (GEOS's union, not interruptible: 0.4 s at 42 000 vertices, 17 s at 1.4 M); beyond,
#: it samples the whole floor.
REGION_MAX_VERTICES = 50_000


class Focus(Protocol):
    """A part of the floor to draw positions in (e.g. :class:`~.floor_band.BandRegion`)."""

    @property
    def area(self) -> float:
        """Its area (m^2)."""

    def sample(self, rng: np.random.Generator) -> tuple[float, float]:
        """A uniform position in it."""


class PoseSampler:
    """Uniform object poses in the floor bounds, yaw in ``[-yaw_range, yaw_range)``.

    Args:
        checker: the scene's bounds and the box's validity.
        rng: the planner's generator (the only source of randomness).
        yaw_range: half-width of the yaw interval (rad).
        max_rejects: draws of :meth:`reachable` rejected in a row before it falls back to
            :meth:`uniform` (a sliver of a region;
            :attr:`~pivot_ompl.planners.sampling_config.SamplingConfig.max_rejects`).
    """

    def __init__(self, checker: PivotChecker, rng: np.random.Generator, *,
                 yaw_range: float, max_rejects: int, start: Pose | None = None) -> None:
        """Sample over ``checker``'s floor (:meth:`reachable`: from ``start``)."""
        b = checker.world.bounds
        self.checker = checker
        self.rng = rng
        self.yaw_range = yaw_range
        self.max_rejects = max_rejects
        self.start = start
        self._lo = (b[0], b[1])
        self._hi = (b[2], b[3])
        self._region: BaseGeometry | None = None
        self._region_done = False
        self._region_box: tuple[float, float, float, float] | None = None
        self._focus: Focus | None = None

    def focus(self, area: Focus | None) -> None:
        """Draw :meth:`reachable`'s positions in ``area`` (``None``: over the region again)."""
        self._focus = area

    @property
    def focus_area(self) -> float | None:
        """The area (m^2) positions are drawn in, if focused (:meth:`focus`)."""
        return None if self._focus is None else self._focus.area

    def region(self) -> BaseGeometry | None:
        """The box centres reachable from the start (module docstring); ``None``: the floor.

        The floor when there is no start, or obstacles of more than
        :data:`REGION_MAX_VERTICES` vertices.
        """
        if not self._region_done and self.start is not None:
            self._region_done = True
            ck = self.checker
            if region_vertices(ck.world.obstacles) > REGION_MAX_VERTICES:
                return None
            x0, y0, x1, y1 = ck.world.bounds
            free = disk_clear(ck.world.bounds, ck.world.obstacles,
                              radius=0.5 * min(ck.model.object_size[:2]),
                              clearance=ck.world.clearance - SWEEP_TOLERANCE)
            here = shapely.Point(self.start[0], self.start[1])
            parts = [g for g in getattr(free, "geoms", [free]) if g.distance(here) < 1e-6]
            self._region = parts[0] if parts else shapely.box(x0, y0, x1, y1)
            shapely.prepare(self._region)
            self._region_box = self._region.bounds
        return self._region

    def reachable(self) -> Pose:
        """A uniform pose whose position may be reached from the start (x, y, then yaw).

        Focused (:meth:`focus`): a uniform position of the focus area, then the yaw.
        """
        if self._focus is not None:
            x, y = self._focus.sample(self.rng)
            return (x, y, float(self.rng.uniform(-self.yaw_range, self.yaw_range)))
        region = self.region()
        if region is None or self._region_box is None:
            return self.uniform()
        x0, y0, x1, y1 = self._region_box
        for _ in range(self.max_rejects):
            x, y = float(self.rng.uniform(x0, x1)), float(self.rng.uniform(y0, y1))
            if shapely.contains_xy(region, x, y):
                return (x, y, float(self.rng.uniform(-self.yaw_range, self.yaw_range)))
        return self.uniform()

    def uniform(self) -> Pose:
        """A uniform pose (x, y, then yaw drawn in that order)."""
        return (float(self.rng.uniform(self._lo[0], self._hi[0])),
                float(self.rng.uniform(self._lo[1], self._hi[1])),
                float(self.rng.uniform(-self.yaw_range, self.yaw_range)))

    def box_valid(self, should_stop: Callable[[], bool], *, attempts: int = 1000) -> Pose | None:
        """A reachable pose where the box alone is free; ``None`` when ``should_stop`` says so.

        After ``attempts`` invalid draws the next uniform pose is returned unchecked (the
        visibility test refuses it).
        """
        for k in range(attempts):
            if k % 50 == 49 and should_stop():
                return None
            q = self.reachable()
            if self.checker.box_valid(q):
                return q
        return self.reachable()

"""The regrasp bound computed coarse to fine: the raster cover first, the polygons where needed.

Two sound relaxations of the same problem (:mod:`~pivot_ompl.analysis.raster_bound`, cells;
:mod:`~pivot_ompl.analysis.regrasp_bound`, exact polygons) give two lower bounds, the
raster's never above the polygons'. :func:`scaled_lower_bound` runs the raster (a second or
two on a 1500 m² map of 2000 boxes) and then the polygons only when both hold:

* the answer may depend on them: the raster's bound is below ``target`` (the regrasps of the
  plan to judge; with no target, always), and the raster did not already prove that no plan
  exists;
* they fit: their cost, estimated from the yaw bins and the obstacle pieces
  (:data:`SECONDS_PER_PIECE` per piece, bin and grasp, measured), is at most
  ``exhaustive_seconds`` (a small scene's polygons take about a second; a 2000-box map's
  about four minutes).

The result is the larger of the two bounds (both are proofs), marked ``exhaustive`` when the
polygons ran to the end.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable

from pivot_ompl.analysis.raster_bound import raster_lower_bound
from pivot_ompl.analysis.regrasp_bound import (
    RESOLUTION,
    RegraspBound,
    regrasp_lower_bound,
    yaw_bins,
)
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Scene

log = logging.getLogger(__name__)

#: Largest estimated time (s) of the polygon relaxation run after the raster's.
EXHAUSTIVE_SECONDS = 2.0
#: The polygon relaxation's cost (s) per obstacle piece, yaw bin and grasp (measured on fig10,
#: the house and the Nav2 warehouse maps: 0.22-0.39 ms; the upper end).
SECONDS_PER_PIECE = 4e-4


def exhaustive_estimate(scene: Scene, *, resolution: float = RESOLUTION) -> float:
    """Estimated time (s) of :func:`~pivot_ompl.analysis.regrasp_bound.regrasp_lower_bound`."""
    pieces = sum(1 if isinstance(o, BoxObstacle | CylinderObstacle) else len(o.points) - 2
                 for o in scene.obstacles)
    return 2 * yaw_bins(scene, resolution) * max(1, pieces) * SECONDS_PER_PIECE


def scaled_lower_bound(scene: Scene, *, target: int | None = None,
                       resolution: float = RESOLUTION,
                       exhaustive_seconds: float = EXHAUSTIVE_SECONDS,
                       should_stop: Callable[[], bool] | None = None) -> RegraspBound:
    """The fewest regrasps any plan of ``scene`` needs, coarse to fine (module docstring).

    Args:
        scene: the scene.
        target: the regrasps of a plan the bound is to judge (the polygons run only when the
            raster's bound is below it); ``None``: as exact as ``exhaustive_seconds`` allows.
        resolution: the polygon relaxation's yaw-bin erosion (m).
        exhaustive_seconds: largest estimated time (s) of the polygon relaxation
            (``math.inf``: always run it).
        should_stop: polled by both relaxations; stopped, the raster's result stands (or
            unknown when the raster itself was stopped).
    """
    t0 = time.perf_counter()
    fast = raster_lower_bound(scene, should_stop=should_stop)
    if fast.solvable is None or fast.solvable is False:
        return fast
    needed = target is None or (fast.regrasps is not None and fast.regrasps < target)
    estimate = exhaustive_estimate(scene, resolution=resolution)
    if not needed or estimate > exhaustive_seconds:
        log.debug("regrasp bound %s from the raster (polygons %s, estimated %.1f s)",
                  fast.regrasps, "not needed" if not needed else "skipped", estimate)
        return fast
    full = regrasp_lower_bound(scene, resolution=resolution, should_stop=should_stop)
    seconds = time.perf_counter() - t0
    if full.solvable is None:
        return dataclasses.replace(fast, seconds=seconds)
    if full.solvable is False:
        return dataclasses.replace(full, seconds=seconds)
    routes = [r for r in (fast.shortest_route, full.shortest_route) if r is not None]
    return dataclasses.replace(
        full, regrasps=max(fast.regrasps or 0, full.regrasps or 0), seconds=seconds,
        shortest_route=max(routes) if routes else None,
        complete=full.complete and fast.complete)

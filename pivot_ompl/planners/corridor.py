"""A lattice over the band of floor a one-grasp plan needs: round the floor's shortest route.

Where one grasp suffices, the held assembly's lattice (:class:`~.routes.lattice.TransferLattice`)
serves the regrasp-free lattice try (:mod:`.direct`) and the re-routing of the path found
(:mod:`.routes.refine`). Its assembly field is rasterised over the whole floor the box may
reach, and on a building of hundreds of wall pieces that field, its components and its floor
distances were most of a one-grasp plan (the small warehouse: 0.25 of 0.58 s of CPU). Both
uses ask routes from the start to the goal, and the route they find runs along the floor's
shortest way between them: the shortest path of the box's centre through the route bound's
free cells (:func:`~.route_field.free_route`, the disk relaxation's, which the followed
route computes anyway and the scene's plans share).

:func:`corridor_lattice` is a lattice whose region is the band of ``width`` m either side of
that way (within the region the box may reach): the field pays for the wall pieces round the
band alone. It is a guide like the whole lattice (every transfer of a route is certified by
the pivot checker), complete within the band; a caller whose try finds nothing in the band
tries the whole lattice (:func:`~.direct.direct_path` takes the lattices in turn). Where the
band covers most of the region (:data:`MOST`), or no way is known, there is none: the whole
lattice serves.
"""

from __future__ import annotations

from collections.abc import Callable

import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.route_field import free_route
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.se2 import Pose

__all__ = ["FIRST_AREA", "MOST", "band_first", "corridor_lattice", "corridor_region"]

Stop = Callable[[], bool]

#: A band covering more than this share of the region is not worth a field of its own.
MOST = 0.6
#: Largest band (m^2) whose lattice try comes before the RRT-Connect's (:func:`band_first`).
#: The band's try costs about 4 ms of CPU per m^2 (a 200 x 200 m hall's 550 m^2 band: 2 s),
#: the RRT-Connect's at most its checks (about 0.3 s where it fails on a building's floor,
#: at once on an open one): from a way of about 100 m the RRT-Connect goes first, and the
#: path it finds is re-routed without the band.
FIRST_AREA = 200.0


def corridor_region(checker: PivotChecker, start: Pose, goal: Pose, *, width: float,
                    region: BaseGeometry | None, should_stop: Stop) -> BaseGeometry | None:
    """The box centres within ``width`` m of the floor's shortest way from start to goal.

    Within ``region`` (the box centres a plan may reach; ``None``: the floor's bounds).
    ``None`` where there is no band: ``width <= 0``, no way known (stopped, or start and
    goal apart in the relaxation), or a band covering more than :data:`MOST` of the region.
    """
    if width <= 0.0:
        return None
    way = free_route(checker, (start[0], start[1]), (goal[0], goal[1]),
                     should_stop=should_stop)
    if way is None or len(way) < 2:
        return None
    within = region if region is not None else shapely.box(*checker.world.bounds)
    band = shapely.intersection(shapely.LineString(way).buffer(width), within)
    if band.is_empty or band.area > MOST * within.area:
        return None
    return band


def corridor_lattice(checker: PivotChecker, costs: CostModel, start: Pose, goal: Pose, *,
                     width: float, region: BaseGeometry | None, weight: float,
                     should_stop: Stop) -> TransferLattice | None:
    """A lattice over :func:`corridor_region`'s band (``None`` where there is none).

    ``weight``: the lattice's heuristic inflation (as the whole lattice's).
    """
    band = corridor_region(checker, start, goal, width=width, region=region,
                           should_stop=should_stop)
    if band is None:
        return None
    return TransferLattice(checker, costs, region=band, weight=weight)


def band_first(lattice: TransferLattice) -> bool:
    """Whether the band ``lattice``'s try comes before the RRT-Connect's (:data:`FIRST_AREA`)."""
    return lattice.region is not None and lattice.region.area <= FIRST_AREA

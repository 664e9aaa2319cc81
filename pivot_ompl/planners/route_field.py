"""The free field a transfer's route is followed on, kept per scene with the routes found on it.

The route bound of a plan's quality block is the length of the shortest path of the box's
centre through the disk relaxation's free cells
(:func:`~pivot_ompl.analysis.plan_bounds.disk_cells`). :func:`route_field` gives that field
for a checker's scene (laid in the walls' frame where the scene has one), made once per scene
geometry and shared by every plan of it; :meth:`RouteField.found` gives the route between two
points at a margin from the walls, found once and kept; :func:`free_route` is the shortest
one (margin 0), which :mod:`~pivot_ompl.planners.follow_route` follows first and
:mod:`~pivot_ompl.planners.corridor` guides by.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.analysis.plan_bounds import disk_cells
from pivot_ompl.analysis.route_path import FreeField, Route, route_polyline
from pivot_ompl.analysis.wall_frame import WallFrame, wall_frame
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene.shared import scene_shared

__all__ = ["MAX_CELLS", "ROUTES_KEPT", "RouteField", "free_route", "route_field"]

Stop = Callable[[], bool]

#: Most raster cells of the route's field (a coarser raster than the bound's: a guide).
MAX_CELLS = 50_000
#: Most routes kept per scene (then forgotten all at once: a later plan finds them again).
ROUTES_KEPT = 512


@dataclass
class RouteField:
    """A scene's free field and the routes found on it (at most :data:`ROUTES_KEPT`).

    Attributes:
        field: the disk relaxation's free cells (in ``frame`` when there is one).
        routes: by ``(start x, start y, goal x, goal y, first margin, margin)`` (m; the
            later margins' routes pass by the first's: :func:`route_polyline`'s ``via``),
            ``None`` where there is none.
        frame: the walls' frame the field lies in, ``None`` for the scene's own.
    """

    field: FreeField
    routes: dict[tuple[float, ...], Route | None]
    frame: WallFrame | None = None

    def route(self, a: tuple[float, float], b: tuple[float, float], *, margin: float,
              via: Route | None, poll: Callable[[], None]) -> Route | None:
        """:func:`route_polyline` from ``a`` to ``b`` (m, in the scene), its points too.

        The field lies in ``frame`` when there is one (its cells, and ``via``'s, are the
        frame's); the points go in and out of it by a rigid motion.
        """
        f = self.frame
        if f is None:
            return route_polyline(self.field, a, b, margin=margin, via=via, poll=poll)
        r = route_polyline(self.field, f.point_in(a), f.point_in(b), margin=margin, via=via,
                           poll=poll)
        return None if r is None else r._replace(points=[f.point_out(p) for p in r.points])

    def found(self, a: tuple[float, float], b: tuple[float, float], *, first: float,
              margin: float, via: Route | None, should_stop: Stop) -> Route | None:
        """:meth:`route` kept in :attr:`routes` (``first``: the first margin tried, m).

        Raises:
            Interrupted: ``should_stop`` said stop while the route was searched.
        """
        key = (a[0], a[1], b[0], b[1], first, margin)
        if key not in self.routes:
            if len(self.routes) >= ROUTES_KEPT:
                self.routes.clear()
            self.routes[key] = self.route(a, b, margin=margin, via=via,
                                          poll=lambda: _poll(should_stop))
        return self.routes[key]


def route_field(checker: PivotChecker, should_stop: Stop) -> RouteField | None:
    """The free field of the disk relaxation of ``checker``'s scene; ``None`` if stopped.

    Laid in the walls' frame (:func:`~pivot_ompl.analysis.wall_frame.wall_frame`) where
    the scene has one: the raster then covers the floor's own area, not the axis-aligned
    box round a turned floor (which grows with the square of a turned row's length, and
    whose cells, :data:`MAX_CELLS` at most, came out wider than the box there: no cell
    was blocked). Kept, with the routes found on it, per scene geometry
    (:func:`~pivot_ompl.scene.shared.scene_shared`): a later plan of the same scene,
    with a checker of its own, finds it made.
    """
    def made() -> RouteField | None:
        frame = wall_frame(checker.scene, should_stop=should_stop)
        cells = disk_cells(checker.scene if frame is None else frame.scene,
                           should_stop=should_stop, max_cells=MAX_CELLS)
        if cells is None or should_stop():
            return None
        return RouteField(FreeField.of(*cells), {}, frame)

    return scene_shared(checker.scene, ("free field", MAX_CELLS), made)


def free_route(checker: PivotChecker, a: tuple[float, float], b: tuple[float, float], *,
               should_stop: Stop) -> list[tuple[float, float]] | None:
    """The shortest route of the box's centre from ``a`` to ``b`` through the free field.

    The route :func:`~pivot_ompl.planners.follow_route.follow_route` follows first
    (margin 0), kept with the field's routes (a later follow of a phase between the same
    points finds it); ``None`` if there is none or stopped.
    """
    known = route_field(checker, should_stop)
    if known is None:
        return None
    try:
        route = known.found(a, b, first=0.0, margin=0.0, via=None, should_stop=should_stop)
    except Interrupted:
        return None
    return None if route is None else list(route.points)


def _poll(should_stop: Stop) -> None:
    if should_stop():
        raise Interrupted("the followed route")

"""The layered route bound on finer cells, asked only where a plan's route ratio is high.

The layered route bound (:mod:`~pivot_ompl.analysis.route_layers`) runs inside the exact
relaxation on cells of :data:`~pivot_ompl.analysis.route_layers.MIN_CELL` (8 cm): finer cells
make it longer where the regrasps' places are narrow (``gen:walls:2``: 7.83 m on 8 cm cells,
8.14 m on 5 cm), but cost every plan's bound their time. So the quality block asks for
:data:`FINE_CELL` cells only for a plan with regrasps whose box route is over
:data:`REFINE_RATIO` times the bound it carries, when the exact relaxation's estimated time
(:func:`~pivot_ompl.analysis.bound_levels.exhaustive_estimate`, times :data:`COST_FACTOR` for
the finer layers) fits the time left; the relaxation runs in the walls' frame
(:func:`~pivot_ompl.analysis.wall_frame.relaxed_scene`: a rigid motion, the route's length the
same). Every route it gives is a proof (the layered argument holds on any cells); the larger of
it and the route the plan had is kept, once per scene in the process.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from pivot_ompl.analysis.bound_levels import exhaustive_estimate
from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.analysis.wall_frame import relaxed_scene
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import keep_shared, shared_value

log = logging.getLogger(__name__)

#: A plan's route over its route bound beyond which the finer cells are tried.
REFINE_RATIO = 1.3
#: The finer layered route's smallest cell side (m).
FINE_CELL = 0.05
#: The finer relaxation's time over the exact relaxation's estimate.
COST_FACTOR = 2.0


def finer_route(scene: Scene, route: float | None, *, route_length: float | None,
                regrasps: int, should_stop: Callable[[], bool] | None = None,
                time_left: Callable[[], float] | None = None) -> float | None:
    """The layered route bound on :data:`FINE_CELL` cells (m), or ``None`` (module docstring).

    ``None`` unless the plan (``regrasps`` > 0, a box route of ``route_length`` m) has a
    route ratio over :data:`REFINE_RATIO` against ``route``, and the estimate fits
    ``time_left()`` (if known); also when stopped by ``should_stop`` or when no finer route
    was found. A result once found for ``scene`` is read again at no cost.
    """
    if regrasps == 0 or route is None or route_length is None:
        return None
    if route_length <= REFINE_RATIO * route:
        return None
    known = shared_value(scene, ("finer route", FINE_CELL))
    if known is not None:
        return float(known)
    if time_left is not None and COST_FACTOR * exhaustive_estimate(scene) > time_left():
        return None  # the scene's estimate: the turned one's four more walls change it little
    found = regrasp_lower_bound(relaxed_scene(scene, should_stop=should_stop),
                                should_stop=should_stop, route_cell=FINE_CELL)
    if found.solvable is not True or not found.complete or found.shortest_route is None:
        return None
    log.debug("route bound on %.3f m cells: %.3f m (before %.3f m)", FINE_CELL,
              found.shortest_route, route)
    keep_shared(scene, ("finer route", FINE_CELL), found.shortest_route)
    return found.shortest_route

"""The regrasp relaxation in more than one frame, where the plan's count is not yet proven.

The relaxations lay raster cells and yaw bins along the axes of the frame they run in, so
their bound depends on it: a turned copy of a floor (``rot:2.0:gen:walls:3``, which keeps
its old floor as four long walls round it) proves 3 regrasps relaxed in the world's frame
and only 1 in the frame its inner walls give (:func:`~pivot_ompl.analysis.wall_frame.
wall_frame` with ``facing``). Turning the scene is a rigid motion: a plan of the scene is
one of the turned scene, so every frame's bound is a proof for the scene, and the largest
of them is one too.

:func:`framed_lower_bound` relaxes in the walls' frame first (all edges counted:
:func:`~pivot_ompl.analysis.wall_frame.wall_frame`'s default; also where its bounds are
larger than that default allows but its coarsest raster's cells are finer than the world's,
a large floor turned in the world whose world-frame raster gets coarser cells across its
walls for the same estimated time, or where at least :data:`ALIGNED` of the walls' length
runs along its axes, a map drawn square to its walls and turned, whose raster is exact to
them there only; the scene itself where it gives none) and, only while
the bound is below the plan's regrasps (``target``), in the other frames: the world's, the
walls' where the first call found it not worth its cost, then the facing walls' (each once,
a frame equal to one tried skipped), ``should_stop`` polled between them and by each. A
stopped or unsolvable result of another frame is dropped
(the first frame's stands). The kept result is the frame's whose count is the largest (its
counts of bins and pieces with it), with the longest route any frame proved.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable

from pivot_ompl.analysis.bound_levels import CELLS, scaled_lower_bound
from pivot_ompl.analysis.guided_refine import Hint
from pivot_ompl.analysis.raster_cover import floor_raster
from pivot_ompl.analysis.regrasp_bound import RegraspBound
from pivot_ompl.analysis.wall_frame import WallFrame, wall_frame
from pivot_ompl.scene import Scene
from pivot_ompl.scene.walls import aligned_share

log = logging.getLogger(__name__)

#: Share of the walls' length along the walls' frame's axes from which that frame is
#: relaxed first (a map drawn square to its walls and turned in the world: its raster is
#: exact to the walls there only; a layout whose walls run in more than one direction, as
#: ``walls_3_turned``'s 46 %, is relaxed as it is first).
ALIGNED = 0.9
#: Two frames whose directions differ by less than this (rad, modulo a quarter turn) are one.
SAME_YAW = 1e-6
#: The later frames' ``worth`` (:func:`~pivot_ompl.analysis.wall_frame.wall_frame`): turned
#: wherever the turned bounds are not larger than the scene's (a map turned by 29 degrees:
#: 306 of 419 m², over the first frame's half, yet its walls on the cells' axes prove the
#: regrasp its door forces, which the world's frame does not).
WORTH_ANY = 1.0


def framed_lower_bound(scene: Scene, *, resolution: float, target: int | None,
                       refine_seconds: float, should_stop: Callable[[], bool] | None,
                       guided_seconds: float,
                       places: tuple[tuple[float, float], ...],
                       hint: Hint | None = None) -> RegraspBound:
    """:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound` over frames (module docstring).

    The arguments are ``scaled_lower_bound``'s (``places`` and ``hint``'s places in
    ``scene``'s frame, turned into each frame's); ``guided_seconds`` is shared: each later
    frame gets what the earlier ones left of it.
    """
    t0 = time.perf_counter()
    first = wall_frame(scene, should_stop=should_stop)
    walls = None if first is not None else wall_frame(scene, should_stop=should_stop,
                                                      worth=WORTH_ANY)
    if walls is not None and (_cell(walls.scene) < _cell(scene) or
                              aligned_share(scene.obstacles, walls.yaw) >= ALIGNED):
        first = walls
    best = _in_frame(scene, first, resolution=resolution, target=target,
                     refine_seconds=refine_seconds, should_stop=should_stop,
                     guided_seconds=guided_seconds, places=places, hint=hint)
    tried = [None if first is None else first.yaw]
    for kind in ("world", "walls", "facing"):
        if not _wanted(best, target) or (should_stop is not None and should_stop()):
            break
        frame = None if kind == "world" else walls if kind == "walls" else wall_frame(
            scene, should_stop=should_stop, facing=True)
        if (kind != "world" and frame is None) or \
                _seen(None if frame is None else frame.yaw, tried):
            continue
        tried.append(None if frame is None else frame.yaw)
        left = max(0.0, guided_seconds - (time.perf_counter() - t0))
        other = _in_frame(scene, frame, resolution=resolution, target=target,
                          refine_seconds=refine_seconds, should_stop=should_stop,
                          guided_seconds=left, places=places, hint=hint)
        if other.solvable is not True or not other.complete:
            continue  # stopped (or a relaxation that a plan refutes): the first stands
        log.debug("regrasp bound in another frame (%s): %s, before %s",
                  "world" if frame is None else f"{math.degrees(frame.yaw):.1f} deg",
                  other.regrasps, best.regrasps)
        best = _stronger(best, other)
    return dataclasses.replace(best, seconds=time.perf_counter() - t0)


def _in_frame(scene: Scene, frame: WallFrame | None, *, resolution: float,
              target: int | None, refine_seconds: float,
              should_stop: Callable[[], bool] | None, guided_seconds: float,
              places: tuple[tuple[float, float], ...], hint: Hint | None) -> RegraspBound:
    """The relaxation of ``scene`` turned into ``frame`` (``None``: as it is)."""
    if frame is None:
        return scaled_lower_bound(scene, resolution=resolution, target=target,
                                  refine_seconds=refine_seconds, should_stop=should_stop,
                                  guided_seconds=guided_seconds, places=places, hint=hint)

    def turned() -> tuple[int | None, tuple[tuple[float, float], ...]] | None:
        said = hint()  # type: ignore[misc]
        return None if said is None else (said[0], tuple(frame.point_in(p) for p in said[1]))

    return scaled_lower_bound(frame.scene, resolution=resolution, target=target,
                              refine_seconds=refine_seconds, should_stop=should_stop,
                              guided_seconds=guided_seconds,
                              places=tuple(frame.point_in(p) for p in places),
                              hint=None if hint is None else turned)


def _cell(scene: Scene) -> float:
    """The coarsest raster's cell (m) on ``scene``'s bounds."""
    return floor_raster(scene.bounds, CELLS[0]).cell


def _seen(yaw: float | None, tried: list[float | None]) -> bool:
    """Whether a frame of direction ``yaw`` (``None``: the world's) was tried already."""
    for t in tried:
        if t is None or yaw is None:
            if t is None and yaw is None:
                return True
            continue
        d = (yaw - t) % (0.5 * math.pi)
        if min(d, 0.5 * math.pi - d) < SAME_YAW:
            return True
    return False


def _wanted(bound: RegraspBound, target: int | None) -> bool:
    """Whether another frame may still raise ``bound`` to the plan's ``target``."""
    return (target is not None and bound.solvable is True and bound.complete
            and bound.regrasps is not None and bound.regrasps < target)


def _stronger(a: RegraspBound, b: RegraspBound) -> RegraspBound:
    """The bound of the larger count (``a`` on ties), with the longer of both routes."""
    best = b if (b.regrasps or 0) > (a.regrasps or 0) else a
    routes = [r for r in (a.shortest_route, b.shortest_route) if r is not None]
    return dataclasses.replace(best, shortest_route=max(routes) if routes else None,
                               guided=a.guided or b.guided, held=a.held or b.held)

"""The regrasp bound computed coarse to fine: raster covers first, the polygons where needed.

Sound relaxations of the same problem at several precisions (:mod:`~pivot_ompl.analysis.
raster_bound` on cells of :data:`CELLS`, coarse to fine; :mod:`~pivot_ompl.analysis.
regrasp_bound`, exact polygons) each give a lower bound; a coarser one is never above the
polygons' but may be below it. :func:`scaled_lower_bound` runs the coarsest raster (about a
second on a 1500 m² map of 2000 boxes), then a finer level only when both hold:

* the answer may depend on it: the bound so far is below ``target`` (the regrasps of the
  plan to judge; with no target, always), and no level already proved that no plan exists;
* it fits: the estimated costs of the levels run so far (the coarsest included) and of this
  one, from the floor's cells, the yaw bins and the body's rows of lattice offsets
  (:data:`SECONDS_PER_CELL_ROW`) or, for the polygons, from the bins and the obstacle pieces
  (:data:`SECONDS_PER_PIECE`, both measured), add up to at most ``refine_seconds`` (a small
  scene's polygons take about a second; a 2000-box map's about four minutes), or, with
  a plan's count to reach (``target``), a finer raster estimated at most
  :data:`LEVEL_SECONDS` fits what ``guided_seconds`` allows (the refinement below gets
  the rest: on a lab map whose 0.85 m door forces a regrasp, the 5 cm level proves it where
  the refinement of the 10 cm one does not). Estimates, not clocks: the levels run are the
  same on a loaded machine.

The result is the strongest of the levels run (each is a proof), marked ``exhaustive`` when
the polygons ran to the end. When the polygons fit they run straight after the coarsest
raster (no finer raster can beat them); otherwise the finer rasters run in turn. The
coarsest raster and the polygons are the late proof's when it built them already for this
scene (:mod:`~pivot_ompl.analysis.relaxation_handoff`).

With ``guided_seconds``, when the polygons did not run and the bound is still wanted, the
coarsest raster is then refined where its best path passes narrow places
(:func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound`: rounds of one to two
seconds on a 5000-box floor, each a proof; it polls ``should_stop`` and its rounds done
stand), marked ``guided`` when it ran to its end; only when the coarsest raster's estimate
and its own (:func:`guided_estimate`, from the floor's cells and yaw bins) add up to at most
``guided_seconds``: an estimate, so a refinement that cannot end in the time given is not
started. On a floor of few obstacle pieces, whose held poses' count
(:func:`~pivot_ompl.analysis.pose_regrasps.pose_regrasp_bound`: exact polygons per yaw bin
and grasp, the fewest grasp changes over them) is estimated at most :data:`POSE_SECONDS`,
that count runs in its place (:func:`may_pose`): measured on the corridor rows, the
refinement's raster proves 0 there and the count 3-5, with its cost bounded by bin, round
and search counts. It runs after the exact polygons too, where they prove less than
``target`` (they keep the motions' 8 mm and ask for no walk: 2 on the 4-room corridor rows,
whose plans and the count need 3).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable

from pivot_ompl.analysis.guided_refine import Hint, guided_lower_bound
from pivot_ompl.analysis.pose_regrasps import pose_estimate, pose_regrasp_bound
from pivot_ompl.analysis.raster_bound import RasterGraph, raster_graph, raster_lower_bound
from pivot_ompl.analysis.raster_cover import RasterCover, floor_raster, raster_cover
from pivot_ompl.analysis.regrasp_bound import (
    RESOLUTION,
    RegraspBound,
    held_bodies,
    regrasp_lower_bound,
    yaw_bins,
)
from pivot_ompl.analysis.relaxation_handoff import take_coarse, take_exact
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE

log = logging.getLogger(__name__)

#: Largest estimated time (s) of all levels run together (a finer one runs only if it fits).
#: A quarter of the 10 s a plan's bounds may take: the estimates run high (fig10 turned by
#: 30 degrees, with its old bounds as walls: the polygons estimated 1.9 s, run in 1.4 s), and
#: at 2 s such copies of a small scene lost their exact bound to the raster's 0.
REFINE_SECONDS = 2.5
#: Largest estimated time (s) of a finer raster level paid from ``guided_seconds`` (beyond
#: :data:`REFINE_SECONDS`): its layers hold every cell of the floor for every yaw bin.
LEVEL_SECONDS = 10.0
#: The raster levels' cell sides (m), coarse to fine (a floor over the raster's cell cap
#: gets larger cells at every level).
CELLS = (0.1, 0.05, 0.025)
#: The raster's cost (s) per cell, layer and row of lattice offsets (measured 0.4-1.2 ns;
#: the upper end, so that a plan's bound stays within about 2 s on the Nav2 warehouse).
SECONDS_PER_CELL_ROW = 1.2e-9
#: Rows' worth of further work per layer (labelling, the joins between pieces).
ROWS_PER_LAYER = 10
#: The guided refinement's cost (s) per coarse cell, yaw bin and round (its rounds rebuild
#: the coarse graph over the whole floor; measured 6.4e-8 on the Willow Garage office at
#: e40f4ca, 4.6e-8 at e8b0282, less since: the first round reads the raster bound's graph
#: and the walk checks label the whole floor less often).
SECONDS_PER_CELL_BIN_ROUND = 5e-8
#: Rounds the guided estimate counts (the Willow Garage office's 2 takes 6).
GUIDED_ROUNDS = 6
#: Largest estimate (s) of the held poses' count run in place of the guided refinement
#: (:func:`~pivot_ompl.analysis.pose_regrasps.pose_estimate`: 1.4 s on the 32-room corridor
#: row of 105 boxes, where the refinement gains nothing; the Willow Garage office's 5049
#: boxes: about 65 s, so the refinement runs there).
POSE_SECONDS = 2.0
#: The polygon relaxation's cost (s) per obstacle piece, yaw bin and grasp (measured on fig10,
#: the house and the Nav2 warehouse maps: 0.22-0.39 ms).
SECONDS_PER_PIECE = 3e-4


def exhaustive_estimate(scene: Scene, *, resolution: float = RESOLUTION) -> float:
    """Estimated time (s) of :func:`~pivot_ompl.analysis.regrasp_bound.regrasp_lower_bound`."""
    pieces = sum(1 if isinstance(o, BoxObstacle | CylinderObstacle) else len(o.points) - 2
                 for o in scene.obstacles)
    return 2 * yaw_bins(scene, resolution) * max(1, pieces) * SECONDS_PER_PIECE


def raster_estimate(scene: Scene, cell: float) -> float:
    """Estimated time (s) of :func:`~pivot_ompl.analysis.raster_bound.raster_lower_bound`."""
    raster = floor_raster(scene.bounds, cell)
    bins = yaw_bins(scene, 0.5 * raster.cell)
    span = max(2.0 * p.reach for g in (0, 1) for p in held_bodies(scene, g))
    rows = span / raster.cell + ROWS_PER_LAYER
    return 2 * bins * raster.shape[0] * raster.shape[1] * rows * SECONDS_PER_CELL_ROW


def guided_estimate(scene: Scene) -> float:
    """Estimated time (s) of :func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound`."""
    raster = floor_raster(scene.bounds, CELLS[0])
    bins = yaw_bins(scene, 0.5 * raster.cell)
    cells = raster.shape[0] * raster.shape[1]
    return GUIDED_ROUNDS * cells * bins * SECONDS_PER_CELL_BIN_ROUND


def scaled_lower_bound(scene: Scene, *, target: int | None = None,
                       resolution: float = RESOLUTION,
                       refine_seconds: float = REFINE_SECONDS,
                       should_stop: Callable[[], bool] | None = None,
                       guided_seconds: float = 0.0,
                       places: tuple[tuple[float, float], ...] = (),
                       hint: Hint | None = None) -> RegraspBound:
    """The fewest regrasps any plan of ``scene`` needs, coarse to fine (module docstring).

    Args:
        scene: the scene.
        target: the regrasps of a plan the bound is to judge (finer levels run only while
            the bound is below it); ``None``: as exact as the time estimates allow.
        resolution: the polygon relaxation's yaw-bin erosion (m).
        refine_seconds: largest estimated time (s) of all levels together (the coarsest
            always runs; ``math.inf``: run them all).
        should_stop: polled by every level; stopped, the levels done stand (unknown when
            the first was stopped).
        guided_seconds: time (s) the coarsest raster and its guided refinement may take
            together by their estimates (module docstring; 0: never refined, ``math.inf``:
            whenever the bound is still wanted).
        places: where a plan of ``target`` regrasps (m, ``scene``'s frame): refined first
            by the guided refinement (its ``places``; cost only).
        hint: what a search beside expects so far, asked by the guided refinement every
            round (its ``hint``; cost only).
    """
    t0 = time.perf_counter()
    kept = take_coarse(scene, cell=CELLS[0], clearance=KEEP_CLEARANCE)  # the late proof's
    cover: RasterCover | None
    graph: RasterGraph | None
    if kept is not None:
        cover, graph = kept
    else:
        cover = raster_cover(scene, cell=CELLS[0], should_stop=should_stop)
        graph = _graph(scene, cover, should_stop)
    graphs = [graph]  # handed on to the guided refinement, which frees it after round 0
    del graph, kept  # so held by ``graphs`` alone
    best = raster_lower_bound(scene, cell=CELLS[0], should_stop=should_stop, cover=cover,
                              graph=graphs[0])
    if best.solvable is None or cover is None:
        return best
    spent = raster_estimate(scene, CELLS[0])  # estimates, not clocks: the same on any load
    estimate = exhaustive_estimate(scene, resolution=resolution)
    if _wanted(best, target) and spent + estimate <= refine_seconds:
        full = regrasp_lower_bound(scene, resolution=resolution, should_stop=should_stop,
                                   built=take_exact(scene, resolution=resolution,
                                                    clearance=KEEP_CLEARANCE))
        if full.solvable is not None:
            best = dataclasses.replace(_better(full, best), exhaustive=True)
            if _wanted(best, target) and may_pose(scene, guided_seconds):  # walks, 1 cm
                best = held_poses_bound(scene, best, target, should_stop)
            return dataclasses.replace(best, seconds=time.perf_counter() - t0)
        return dataclasses.replace(best, seconds=time.perf_counter() - t0)
    done = floor_raster(scene.bounds, CELLS[0]).cell
    paid = 0.0  # the finer levels' estimates paid from guided_seconds
    for cell in CELLS[1:]:
        if floor_raster(scene.bounds, cell).cell >= done:
            continue  # a floor too large for finer cells
        cost = raster_estimate(scene, cell)
        if not _wanted(best, target):
            break
        if spent + cost > refine_seconds:  # a plan's count to reach: the refinement's time
            if target is None or cost > LEVEL_SECONDS or spent + cost > guided_seconds:
                break
            paid += cost
        spent += cost
        done = floor_raster(scene.bounds, cell).cell
        finer = raster_lower_bound(scene, cell=cell, should_stop=should_stop)
        if finer.solvable is None:
            break
        best = _better(finer, best)
    guided_seconds -= paid
    if _wanted(best, target) and may_pose(scene, guided_seconds):
        best = held_poses_bound(scene, best, target, should_stop)
    elif _wanted(best, target) and may_guide(scene, guided_seconds):
        found = guided_lower_bound(scene, cover=cover, target=target, should_stop=should_stop,
                                   coarse=graphs.pop(),  # not held here: freed after round 0
                                   places=places, hint=hint)
        if found is not None:
            best = dataclasses.replace(_better(found, best), guided=found.guided)
    log.debug("regrasp bound %s from the raster (polygons estimated %.1f s)", best.regrasps,
              estimate)
    return dataclasses.replace(best, seconds=time.perf_counter() - t0)


def _graph(scene: Scene, cover: RasterCover | None,
           should_stop: Callable[[], bool] | None) -> RasterGraph | None:
    """The coarsest raster's graph (``None`` without a cover or when stopped)."""
    if cover is None:
        return None
    try:
        return raster_graph(scene, cover, should_stop=should_stop)
    except Interrupted:
        return None


def may_guide(scene: Scene, guided_seconds: float) -> bool:
    """Whether the guided refinement fits ``guided_seconds`` on ``scene`` (estimates)."""
    return guided_seconds > 0 and (
        raster_estimate(scene, CELLS[0]) + guided_estimate(scene) <= guided_seconds)


def may_pose(scene: Scene, guided_seconds: float) -> bool:
    """Whether the held poses' count replaces the guided refinement on ``scene``.

    When its estimate is at most :data:`POSE_SECONDS` and, with the coarsest raster's, fits
    ``guided_seconds`` (module docstring).
    """
    pose = pose_estimate(scene)
    return guided_seconds > 0 and pose <= POSE_SECONDS and (
        raster_estimate(scene, CELLS[0]) + pose <= guided_seconds)


def held_poses_bound(scene: Scene, best: RegraspBound, target: int | None,
                     should_stop: Callable[[], bool] | None) -> RegraspBound:
    """``best`` raised by the held poses' count (marked ``held`` when it ran to its end)."""
    held = pose_regrasp_bound(scene, target=target, should_stop=should_stop)
    if held.apart:
        return dataclasses.replace(best, regrasps=None, solvable=False, shortest_route=None)
    return dataclasses.replace(
        best, regrasps=max(best.regrasps or 0, held.regrasps or 0),
        held=held.complete, complete=best.complete and held.complete)


def may_refine(scene: Scene, *, resolution: float = RESOLUTION,
               refine_seconds: float = REFINE_SECONDS, paid_seconds: float = 0.0) -> bool:
    """Whether a level finer than the coarsest raster fits ``refine_seconds`` on ``scene``.

    ``paid_seconds``: the refinement's time a plan's count may pay a finer raster from
    (:func:`scaled_lower_bound`; at most :data:`LEVEL_SECONDS` a level).
    """
    if exhaustive_estimate(scene, resolution=resolution) <= refine_seconds:
        return True
    coarse = floor_raster(scene.bounds, CELLS[0]).cell
    most = max(refine_seconds, min(LEVEL_SECONDS, paid_seconds))
    return any(floor_raster(scene.bounds, c).cell < coarse
               and raster_estimate(scene, c) <= most for c in CELLS[1:])


def _wanted(bound: RegraspBound, target: int | None) -> bool:
    """Whether a finer level may change what the bound says of a plan of ``target``."""
    if bound.solvable is False:
        return False
    return target is None or (bound.regrasps is not None and bound.regrasps < target)


def _better(a: RegraspBound, b: RegraspBound) -> RegraspBound:
    """The stronger of two sound bounds (``a``'s counts), each part the larger."""
    if a.solvable is False or b.solvable is False:
        return a if a.solvable is False else b
    routes = [r for r in (a.shortest_route, b.shortest_route) if r is not None]
    return dataclasses.replace(a, regrasps=max(a.regrasps or 0, b.regrasps or 0),
                               shortest_route=max(routes) if routes else None,
                               complete=a.complete and b.complete)

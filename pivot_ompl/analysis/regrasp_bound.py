"""A sound lower bound on the number of regrasps any plan of a scene needs.

**Relaxation.** A plan is a sequence of transfer phases (box and robot move together with one
grasp ``k``; every intermediate configuration ``(x, y, yaw)`` of the box has box and robot
inside the bounds and clear of the obstacles) joined by regrasps (the box rests at one pose
where the robot holds it with grasp ``k`` before and grasp ``j`` after). Forget the pivoting
kinematics (any continuous motion of ``(x, y, yaw)`` is allowed), the walk round the box and
the obstacles' heights (every obstacle is a prism standing on the floor, so a body meets it
exactly where their floor shadows meet), and keep of the held assembly the two floor bodies the
checkers test (:class:`~pivot_ompl.validity.collision.CollisionWorld`): the box's footprint
and the holding robot's convex body (the hull of
:meth:`~pivot_ompl.grasp.BoxGraspModel.held_outline`, which reaches the held face: no gap
between robot and box where a wall's corner could hide), each kept
:data:`~pivot_ompl.validity.collision.KEEP_CLEARANCE` from the obstacles. Every plan is then a
path of the relaxed problem with the same number of grasp changes, so the fewest grasp changes
of the relaxed problem is a lower bound.

**Over-approximating the free space.** Yaw is cut into ``N`` bins of width ``w`` (``N`` even).
In bin ``b`` (centre ``t_b``), rotating a body about the box's centre from ``t_b`` to any yaw of
the bin moves none of its points by more than ``D = 2 r sin(w / 4)`` (``r``: the farthest
point of that body from the box's centre). If the body at ``(x, y, yaw)`` is free, then the
body at ``(x, y, t_b)`` *eroded* by ``D`` (the points whose ``D``-disk lies in it) lies inside
the body at ``(x, y, yaw)`` (Brouwer: the map ``p -> p + y - T(p)`` sends the disk of radius
``D`` about a point ``y`` of the eroded body into itself, so ``y = T(p)`` for a point ``p`` of
the body), so it is free too. A body kept ``c`` from the obstacles is the body grown by ``c``
kept clear; the net offset ``c - D - tol`` (``tol``: the swept checks' own tolerance,
:data:`~pivot_ompl.validity.certify.SWEEP_TOLERANCE`, how close an accepted motion may come
between its checked samples) grows or erodes the convex body (growth by the polygon of chords
of the round offset, erosion by the exact inward offset: both subsets of the true set). With
the yaw fixed at ``t_b`` the positions where such a convex body ``E`` is free are exact
polygons: outside every ``K (+) -E`` (Minkowski sum, the convex hull of the vertex differences
for a convex obstacle piece ``K``; polygons are split into triangles, cylinders replaced by
inscribed polygons, which are subsets) and inside the bounds shrunk by ``E``'s extent (the body
eroded by ``D + tol`` only: the bounds keep no clearance). So ``F(b, k)``, the positions where
both bodies of grasp ``k`` are free at ``t_b``, contains every free ``(x, y)`` of the whole bin:
an over-approximation.

**Search.** Nodes are the connected pieces of every ``F(b, k)``. A continuous transfer stays in
one piece while its yaw stays in a bin and crosses to the next bin at a shared yaw, so through
a point common to a piece of ``F(b, k)`` and one of ``F(b +- 1, k)`` (cost 0). A regrasp from
``k`` to ``j`` happens at one pose, so in a point common to pieces of ``F(b, k)`` and
``F(b, j)`` (cost 1), and only where the walking robot may get from one grasp pose to the
other round the resting box (:class:`~pivot_ompl.analysis.regrasp_walk.WalkRelaxation`, itself
a sound relaxation; checked lazily, only for regrasps whose far piece is not reached yet).
The fewest cost-1 edges from a piece holding the start to a piece holding the goal (a
breadth-first search by levels) is at most the regrasps of any valid plan. Finer bins
(``resolution``, the largest erosion) resolve narrower passages; coarser ones are faster and
still sound. Grasp ``k + 2`` at yaw ``t`` is the same set as grasp ``k`` at ``t + pi``, so only
grasps 0 and 1 are computed.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import cast

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis import route_layers
from pivot_ompl.analysis.free_pieces import HULL_PAIRS, free_region, meeting_per_yaw
from pivot_ompl.analysis.piece_graph import PieceGraph, Regrasp
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
from pivot_ompl.analysis.route_bound import shortest_route
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, rectangle_corners, wrap_angle
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

log = logging.getLogger(__name__)

#: Largest erosion (m) of the robot's rectangle by the rotation within a yaw bin: it sets the
#: number of bins (narrower passages than about this are not resolved).
RESOLUTION = 0.02
#: Yaw bins at most (a tiny ``resolution`` on a large robot would ask for many more).
MAX_BINS = 720
#: Added to every erosion (m): keeps the over-approximation on the safe side of round-off.
ROUND_OFF = 1e-7


@dataclass(frozen=True)
class RegraspBound:
    """Outcome of :func:`regrasp_lower_bound`.

    Attributes:
        regrasps: fewest regrasps any valid plan needs; ``None`` when unknown (stopped by
            the time limit) or when the relaxation finds no path at all (then no plan exists;
            ``solvable`` is ``False``).
        solvable: the relaxed problem joins start and goal (``False`` proves that no plan
            exists); ``None`` when stopped.
        bins: yaw bins used.
        pieces: connected pieces of free positions over all bins and grasps.
        seconds: wall-clock time (s).
        shortest_route: lower bound (m) on the box centre's route of any plan
            (:func:`~pivot_ompl.analysis.route_bound.shortest_route`), ``None`` if unknown.
        complete: every part was computed (``False``: the route bound was stopped by the
            time limit; such a result is not kept by the cache).
        exhaustive: computed by the exact polygon relaxation (``False``: by a faster one,
            :mod:`~pivot_ompl.analysis.raster_bound`, sound but possibly lower).
        guided: the raster relaxation was refined to the end where its best path passes
            narrow places (:mod:`~pivot_ompl.analysis.guided_refine`).
        held: the held poses' count ran to its end (:mod:`~pivot_ompl.analysis.pose_regrasps`).
    """

    regrasps: int | None
    solvable: bool | None
    bins: int
    pieces: int
    seconds: float
    shortest_route: float | None = None
    complete: bool = True
    exhaustive: bool = True
    guided: bool = False
    held: bool = False


@dataclass(frozen=True)
class Body:
    """A convex floor body in the box's frame (its vertices, counter-clockwise)."""

    points: np.ndarray
    _offsets: dict[float, np.ndarray | None] = field(default_factory=dict, init=False,
                                                     repr=False, compare=False)

    @property
    def reach(self) -> float:
        """Distance of its farthest point from the box's centre."""
        return float(np.hypot(self.points[:, 0], self.points[:, 1]).max())

    def offset_points(self, yaw: float, d: float) -> np.ndarray | None:
        """Vertices after turning the box frame by ``yaw`` and eroding by ``d`` (growing if < 0).

        ``None`` when the erosion leaves nothing. Offsets commute with rotations: each ``d``'s
        is built once at yaw 0 and turned (not built again for every yaw bin).
        """
        if d not in self._offsets:
            poly = shapely.Polygon(self.points)
            poly = poly.buffer(-d, join_style="mitre") if d > 0 else \
                poly.buffer(-d, quad_segs=4) if d < 0 else poly
            self._offsets[d] = None if poly.is_empty or poly.geom_type != "Polygon" \
                else np.asarray(poly.exterior.coords)[:-1]
        pts, c, s = self._offsets[d], math.cos(yaw), math.sin(yaw)
        return None if pts is None else pts @ np.array([[c, s], [-s, c]])


def held_bodies(scene: Scene, grasp: int) -> list[Body]:
    """The box's footprint and the holding robot's convex body at ``grasp``, box frame."""
    m = scene.model
    robot = m.robot_pose((0.0, 0.0, 0.0), grasp)
    box = rectangle_corners((0.0, 0.0, 0.0), m.object_size[0], m.object_size[1])
    held = shapely.MultiPoint(m.held_corners(robot, grasp)).convex_hull
    return [Body(np.array(box, dtype=float)),
            Body(np.asarray(held.exterior.coords)[:-1])]


def yaw_bins(scene: Scene, resolution: float) -> int:
    """Even number of yaw bins whose rotation erosion is at most ``resolution``."""
    reach = max(p.reach for g in (0, 1) for p in held_bodies(scene, g))
    w = 4.0 * math.asin(min(1.0, resolution / (2.0 * reach)))
    n = max(8, math.ceil(2.0 * math.pi / w))
    return min(MAX_BINS, n + n % 2)


@dataclass
class FreeCover:
    """Over-approximation of the free states of every grasp (see the module docstring).

    Attributes:
        bins: yaw bins (even); bin ``b`` holds yaws ``-pi + [b, b + 1) * 2 pi / bins``.
        free: connected pieces of free box positions of grasps 0 and 1, per bin.
    """

    bins: int
    free: list[list[list[BaseGeometry]]]

    @property
    def width(self) -> float:
        """Width of a yaw bin (rad)."""
        return 2.0 * math.pi / self.bins

    def bin_of(self, yaw: float) -> int:
        """The bin holding ``yaw`` (any angle)."""
        return int((wrap_angle(yaw) + math.pi) // self.width) % self.bins

    def pieces(self, b: int, grasp: int) -> list[BaseGeometry]:
        """Pieces of bin ``b`` at ``grasp`` (grasp ``k + 2`` is grasp ``k`` a half turn on)."""
        return self.free[grasp % 2][(b + (self.bins // 2) * ((grasp % 4) // 2)) % self.bins]

    def holding(self, pose: Pose, grasp: int) -> list[int]:
        """Indices of the pieces of ``pose``'s bin at ``grasp`` that hold its position."""
        pt = shapely.Point(pose[0], pose[1])
        return [c for c, geom in enumerate(self.pieces(self.bin_of(pose[2]), grasp))
                if geom.distance(pt) <= ROUND_OFF]

    def covers(self, pose: Pose, grasp: int) -> bool:
        """Whether the state may be free (``False`` proves it is in collision)."""
        return bool(self.holding(pose, grasp))


def free_cover(scene: Scene, *, resolution: float = RESOLUTION,
               tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
               should_stop: Callable[[], bool] | None = None) -> FreeCover | None:
    """The :class:`FreeCover` of ``scene``; ``None`` if ``should_stop`` said stop.

    Args:
        scene: the scene.
        resolution: largest erosion (m) of the rotation within a yaw bin; sets the bins.
        tolerance: the swept checks' tolerance (m), added to every erosion.
        clearance: distance (m) the checkers keep every body from the obstacles.
        should_stop: polled once per yaw bin (and while the boxes are merged, the pieces
            being the obstacles with touching boxes merged: :func:`merge_boxes`).
    """
    n = yaw_bins(scene, resolution)
    w = 2.0 * math.pi / n
    try:
        pieces = obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))
    except Interrupted:
        return None
    free: list[list[list[BaseGeometry]]] = [[], []]
    for g in (0, 1):
        parts = held_bodies(scene, g)
        inside = [2.0 * p.reach * math.sin(0.25 * w) + tolerance + ROUND_OFF for p in parts]
        clear = [d - clearance for d in inside]
        step = max(1, HULL_PAIRS // max(1, len(parts) * len(pieces)))
        for b0 in range(0, n, step):  # the hulls of a few bins at once (vectorised)
            yaws = [-math.pi + (b + 0.5) * w for b in range(b0, min(n, b0 + step))]
            try:
                hulls = meeting_per_yaw([[e for p, d in zip(parts, clear, strict=True)
                                          if (e := p.offset_points(yaw, d)) is not None]
                                         for yaw in yaws], pieces, should_stop=should_stop)
            except Interrupted:
                return None
            for yaw, meeting in zip(yaws, hulls, strict=True):
                if should_stop is not None and should_stop():
                    return None
                free[g].append(free_region(scene.bounds, [p.offset_points(yaw, d) for p, d
                                                          in zip(parts, inside, strict=True)],
                                           meeting))
    return FreeCover(n, free)


@dataclass
class CoverGraph:
    """The relaxation's graph over a :class:`FreeCover` (:func:`cover_graph`).

    Attributes:
        graph: pieces joined by transfers and regrasps.
        ids: the node of each piece ``(bin, grasp, index)``.
        nodes: the piece of each node.
        allowed: whether a regrasp edge is allowed (the walk relaxation, lazily).
        holding: the nodes holding a pose (every grasp).
        walk: the walk relaxation (``None`` when every regrasp is allowed).
    """

    graph: PieceGraph
    ids: dict[tuple[int, int, int], int]
    nodes: list[tuple[int, int, int]]
    allowed: Callable[[tuple[int, int, int, int, int]], bool]
    holding: Callable[[Pose], list[int]]
    walk: WalkRelaxation | None


def cover_graph(scene: Scene, cover: FreeCover, *, tolerance: float = SWEEP_TOLERANCE,
                clearance: float = KEEP_CLEARANCE, walks: bool = True,
                should_stop: Callable[[], bool] | None = None) -> CoverGraph:
    """The pieces of ``cover`` joined as the module docstring says.

    ``should_stop`` is polled once per bin and raises :class:`~pivot_ompl.errors.Interrupted`.
    """
    n = cover.bins
    ids: dict[tuple[int, int, int], int] = {}
    for b in range(n):
        for k in range(4):
            for c in range(len(cover.pieces(b, k))):
                ids[(b, k, c)] = len(ids)
    nodes = list(ids)
    graph = PieceGraph([cover.pieces(b, k)[c].area for b, k, c in nodes])

    def link(b1: int, k1: int, b2: int, k2: int, regrasp: bool) -> None:
        ga, gb = cover.pieces(b1, k1), cover.pieces(b2, k2)
        if not ga or not gb:
            return
        ia, ib = shapely.STRtree(gb).query(ga, predicate="intersects")
        for i, j in zip(ia.tolist(), ib.tolist(), strict=True):
            u, v = ids[(b1, k1, i)], ids[(b2, k2, j)]
            graph.add(u, v, (b1, k1, i, k2, j) if regrasp else None)

    for b in range(n):
        if should_stop is not None and should_stop():
            raise Interrupted("the regrasp bound's graph")
        for k in range(4):
            link(b, k, (b + 1) % n, k, False)  # a transfer crossing into the next bin
            for j in range(k + 1, 4):
                link(b, k, b, j, True)  # a regrasp

    walk = WalkRelaxation(scene, width=cover.width, tolerance=tolerance,
                          clearance=clearance) if walks else None

    def allowed(edge: tuple[int, int, int, int, int]) -> bool:
        if walk is None:
            return True
        b, k, i, j, c = edge
        region = cover.pieces(b, k)[i].intersection(cover.pieces(b, j)[c])
        return walk.may_regrasp(region, -math.pi + (b + 0.5) * cover.width, k, j)

    def holding(pose: Pose) -> list[int]:
        b = cover.bin_of(pose[2])
        return [ids[(b, k, c)] for k in range(4) for c in cover.holding(pose, k)]

    return CoverGraph(graph, ids, nodes, allowed, holding, walk)


def _layered(scene: Scene, cover: FreeCover, joined: CoverGraph, pieces: list[BaseGeometry],
             reached: set[int], comps: route_layers.Components,
             should_stop: Callable[[], bool] | None,
             cell: float) -> route_layers.LayeredRoute | None:
    """:mod:`~pivot_ompl.analysis.route_layers`' bound, regrasps asked of the walk relaxation.

    ``pieces``: each node's free positions, in ``joined.nodes``' order.
    """
    edges = [(u, v, e) for u in range(len(pieces)) for v, e in joined.graph.one[u] if u < v]

    def allowed(name: Hashable, region: BaseGeometry) -> bool:
        edge = cast(Regrasp, name)
        return joined.walk is None or joined.walk.may_regrasp(
            region, -math.pi + (edge[0] + 0.5) * cover.width, edge[1], edge[3])

    return route_layers.layered_route(
        pieces, joined.graph.zero, edges, allowed,
        reached=reached, starts=joined.holding(scene.start), goals=joined.holding(scene.goal),
        start=scene.start, goal=scene.goal, bounds=scene.bounds, should_stop=should_stop,
        components=comps, min_cell=cell)


def regrasp_lower_bound(scene: Scene, *, resolution: float = RESOLUTION,
                        tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                        walks: bool = True, should_stop: Callable[[], bool] | None = None,
                        built: tuple[FreeCover, CoverGraph] | None = None,
                        route_cell: float = route_layers.MIN_CELL) -> RegraspBound:
    """Fewest regrasps any plan of ``scene`` needs (see the module docstring: sound).

    Args:
        scene: the scene.
        resolution: largest erosion (m) of the rotation within a yaw bin; sets the bins.
        tolerance: the swept checks' tolerance (m), added to every erosion.
        clearance: distance (m) the checkers keep every body from the obstacles.
        walks: allow a regrasp only where the walking robot may get round the resting box
            (:mod:`~pivot_ompl.analysis.regrasp_walk`); ``False``: wherever both grasps fit.
        should_stop: polled once per yaw bin and per regrasp checked; when it returns
            ``True`` the result is unknown.
        built: :func:`free_cover` and its :func:`cover_graph` of these arguments when built.
        route_cell: the layered route bound's smallest cell side (m).
    """
    t0 = time.perf_counter()
    cover = built[0] if built else free_cover(scene, resolution=resolution, tolerance=tolerance,
                                              clearance=clearance, should_stop=should_stop)
    n = yaw_bins(scene, resolution)
    if cover is None:
        return RegraspBound(None, None, n, 0, time.perf_counter() - t0)
    try:
        joined = built[1] if built else cover_graph(scene, cover, tolerance=tolerance,
                                                    clearance=clearance, walks=walks,
                                                    should_stop=should_stop)
    except Interrupted:
        return RegraspBound(None, None, n, 0, time.perf_counter() - t0)
    ids, nodes, walk, holding = joined.ids, joined.nodes, joined.walk, joined.holding
    try:
        best, reached = joined.graph.fewest_regrasps(
            holding(scene.start), set(holding(scene.goal)), joined.allowed, should_stop)
    except Interrupted:
        return RegraspBound(None, None, n, len(ids), time.perf_counter() - t0)
    route, complete = None, True
    if best is not None:
        pieces = [cover.pieces(b, k)[c] for b, k, c in nodes]
        try:  # the transfer components' footprints: their union is the plain bound's
            comps = route_layers.transfer_components(pieces, joined.graph.zero, reached,
                                        should_stop=should_stop)
            route = shortest_route(comps[1], scene.bounds, scene.start, scene.goal,
                                   should_stop=should_stop)
        except Interrupted:
            complete = False
        if route is not None and best > 0:
            try:  # stopped partway: a proof, but not kept (more rounds might raise it)
                found = _layered(scene, cover, joined, pieces, reached, comps, should_stop,
                                 route_cell)
                if found is not None:
                    route, complete = max(route, found.route or 0.0), not found.stopped
            except Interrupted:
                complete = False
    seconds = time.perf_counter() - t0
    log.debug("regrasp bound %s over %d yaw bins, %d pieces, %d walk queries, %.2f s", best, n,
              len(ids), walk.queries if walk else 0, seconds)
    return RegraspBound(best, best is not None, n, len(ids), seconds, route, complete)

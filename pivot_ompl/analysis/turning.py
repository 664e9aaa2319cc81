"""Where the held box runs out of room to turn: a proven infeasibility with no narrow passage.

:mod:`~pivot_ompl.analysis.passage` explains a scene the relaxation proves has no plan by the
narrowest gap on the way; when every gap is as wide as the held assembly, what is missing is
room to turn (a corner too tight for the box and the robot holding it, a room too small to
turn round in). This module finds that place on the regrasp bound's own relaxation
(:mod:`~pivot_ompl.analysis.regrasp_bound`, exact polygons): the box positions reachable from
the start (every yaw, every grasp, regrasps where the walk relaxation allows them) and those
from which the goal is reachable are computed; when the goal is not among the first, no plan
exists (this *is* the relaxation's proof), and the *place* is where the two sets come
closest (the middle of their largest overlap: positions both reach, at different yaws). It
reports there the room to turn in (the widest free circle near the place), the yaws
the box arrives at from the start and those it must leave at for the goal, and the held
assembly's outline (width and length, clearance included).

The widths are exact distances; the yaws are the relaxation's bins (a few degrees wide).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.passage import hull_extents
from pivot_ompl.analysis.regrasp_bound import RESOLUTION, cover_graph, free_cover
from pivot_ompl.analysis.relaxation_handoff import keep_exact
from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

#: Slack (m) on "nearest" when the yaws of the pieces nearest the place are collected.
NEAR = 0.05
#: Grid step (m) of the centres tried for the widest free circle round the place.
CIRCLE_STEP = 0.02


@dataclass(frozen=True)
class TurningPlace:
    """The place where the held box cannot turn from the start's way onto the goal's.

    Attributes:
        center: the place ``(x, y)`` (m, world frame): a box position.
        width: the diameter (m) of the widest free circle of the floor centred within half
            the assembly's length of the place (the room there to turn in).
        assembly_width: the narrowest width of the box and the robot holding it (m, their
            convex outline plus the clearance on both sides).
        assembly_length: their outline's length square to that width (m, with clearance).
        from_start: the box's yaws (degrees, ``[low, high]`` counter-clockwise) at which it
            comes there from the start.
        to_goal: the box's yaws (degrees, likewise) from which the goal may be reached there.
    """

    center: tuple[float, float]
    width: float
    assembly_width: float
    assembly_length: float
    from_start: tuple[float, float]
    to_goal: tuple[float, float]

    @property
    def reason(self) -> str:
        """One line a person can act on: where, how wide, what needs what."""
        x, y = self.center
        a, b = self.from_start
        c, d = self.to_goal
        return (f"no plan: the box cannot turn at ({x:.2f}, {y:.2f}), where the widest free "
                f"circle is {self.width:.2f} m across; the box and the robot holding it "
                f"({self.assembly_width:.2f} x {self.assembly_length:.2f} m) come there from "
                f"the start at yaw {a:.0f}..{b:.0f} deg and the goal needs {c:.0f}..{d:.0f} deg")

    def as_dict(self) -> dict[str, object]:
        """The plan file's ``turn`` field (JSON-ready)."""
        return {"center": list(self.center), "width": self.width,
                "assembly_width": self.assembly_width,
                "assembly_length": self.assembly_length,
                "from_start": list(self.from_start), "to_goal": list(self.to_goal),
                "reason": self.reason}


def assembly_outline(model: BoxGraspModel, *, clearance: float = KEEP_CLEARANCE
                     ) -> tuple[float, float]:
    """``(width, length)`` (m) of the narrower grasp's outline of box and holding robot.

    The width is the outline's least width, the length its extent square to it; both with
    ``clearance`` on both sides.
    """
    box = np.array(rectangle_corners((0.0, 0.0, 0.0), model.object_size[0],
                                     model.object_size[1]), dtype=float)
    best = (math.inf, 0.0)
    for grasp in (0, 1):
        robot = model.robot_pose((0.0, 0.0, 0.0), grasp)
        pts = np.vstack([box, np.array(model.held_corners(robot, grasp), dtype=float)])
        w, length = min(hull_extents(pts), key=lambda e: e[0])
        if w < best[0]:
            best = (w, length)
    return best[0] + 2.0 * clearance, best[1] + 2.0 * clearance


def turning_place(scene: Scene, *, resolution: float = RESOLUTION,
                  clearance: float = KEEP_CLEARANCE,
                  should_stop: Callable[[], bool] | None = None,
                  keep: bool = False) -> TurningPlace | None:
    """The place where the held box cannot turn (module docstring), when no plan exists.

    ``None`` when the relaxation joins start and goal (nothing is proven), or when
    ``should_stop`` said stop. A place returned is a proof that no plan exists. ``keep``:
    a cover and graph that join start and goal are kept for the plan's regrasp bound
    (:func:`~pivot_ompl.analysis.relaxation_handoff.keep_exact`).
    """
    try:
        return _turning_place(scene, resolution, clearance, should_stop, keep)
    except Interrupted:
        return None


def _turning_place(scene: Scene, resolution: float, clearance: float,
                   should_stop: Callable[[], bool] | None, keep: bool) -> TurningPlace | None:
    cover = free_cover(scene, resolution=resolution, clearance=clearance,
                       should_stop=should_stop)
    if cover is None:
        return None
    joined = cover_graph(scene, cover, clearance=clearance, should_stop=should_stop)
    starts, goals = joined.holding(scene.start), joined.holding(scene.goal)
    if not starts or not goals:
        return None  # an invalid start or goal: the planner says so
    best, from_start = joined.graph.fewest_regrasps(starts, set(goals), joined.allowed,
                                                    should_stop)
    if best is not None:
        if keep:
            keep_exact(scene, cover, joined, resolution=resolution, clearance=clearance)
        return None
    _, to_goal = joined.graph.fewest_regrasps(goals, set(), joined.allowed, should_stop)

    def geoms(nodes: set[int]) -> list[tuple[int, BaseGeometry]]:
        out = []
        for u in nodes:
            b, k, c = joined.nodes[u]
            out.append((b, cover.pieces(b, k)[c]))  # b: the box's yaw bin at every grasp
        return out

    s_parts, g_parts = geoms(from_start), geoms(to_goal)
    s_all = shapely.union_all([g for _, g in s_parts])
    g_all = shapely.union_all([g for _, g in g_parts])
    centre = _meeting_point(s_all, g_all)
    w, length = assembly_outline(scene.model, clearance=clearance)
    width = widest_circle(scene, centre, 0.5 * length, should_stop)
    return TurningPlace((float(centre.x), float(centre.y)), width, w, length,
                        yaw_arc(_near_bins(s_parts, centre), cover.bins),
                        yaw_arc(_near_bins(g_parts, centre), cover.bins))


def _meeting_point(a: BaseGeometry, b: BaseGeometry) -> shapely.Point:
    """The middle of the largest overlap of ``a`` and ``b``, else of their shortest join."""
    both = a.intersection(b)
    parts = [g for g in getattr(both, "geoms", [both]) if g.area > 0]
    if parts:
        big = max(parts, key=lambda g: g.area)
        c = big.centroid
        return c if big.contains(c) else big.representative_point()
    return shapely.shortest_line(a, b).interpolate(0.5, normalized=True)


def _near_bins(parts: list[tuple[int, BaseGeometry]], p: shapely.Point) -> list[int]:
    """The bins of the pieces nearest ``p`` (within :data:`NEAR` of the nearest)."""
    d = [g.distance(p) for _, g in parts]
    least = min(d)
    return sorted({b for (b, _), di in zip(parts, d, strict=True) if di <= least + NEAR})


def yaw_arc(bins: list[int], n: int) -> tuple[float, float]:
    """The smallest arc (degrees, ``low <= high``, low in [-180, 180)) holding ``bins``."""
    w = 360.0 / n
    if len(bins) >= n:
        return (-180.0, 180.0)
    held = sorted(set(bins))
    gaps = [((held[(i + 1) % len(held)] - held[i]) % n or n, i) for i in range(len(held))]
    _, i = max(gaps)
    first = held[(i + 1) % len(held)]
    last = held[i]
    low = -180.0 + first * w
    high = -180.0 + (last + 1) * w
    if high <= low:
        high += 360.0
    return (low, high)


def widest_circle(scene: Scene, centre: shapely.Point, radius: float,
                   should_stop: Callable[[], bool] | None) -> float:
    """Diameter (m) of the widest free circle whose centre is within ``radius`` of ``centre``.

    Centres on a grid of :data:`CIRCLE_STEP`; the free floor is the bounds less the obstacles.
    """
    x0, y0, x1, y1 = scene.bounds
    r = np.arange(-radius, radius + 0.5 * CIRCLE_STEP, CIRCLE_STEP)
    gx, gy = np.meshgrid(centre.x + r, centre.y + r, indexing="ij")
    keep = ((gx - centre.x) ** 2 + (gy - centre.y) ** 2 <= radius * radius) \
        & (gx > x0) & (gx < x1) & (gy > y0) & (gy < y1)
    px, py = gx[keep], gy[keep]
    if not len(px):
        return 0.0
    dist = np.minimum.reduce([px - x0, x1 - px, py - y0, y1 - py])
    polys = [shapely.Polygon(q) for q in
             obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))]
    if polys:
        tree = shapely.STRtree(polys)
        pts = shapely.points(px, py)
        (i, j), d = tree.query_nearest(pts, return_distance=True, all_matches=False)
        near = np.full(len(px), np.inf)
        near[i] = d
        inside = tree.query(pts, predicate="intersects")[0]
        near[inside] = 0.0
        dist = np.minimum(dist, near)
    return 2.0 * float(max(0.0, dist.max()))

"""Which passage keeps a scene from having a plan: the explanation of a proven infeasibility.

The regrasp bound's relaxation (:mod:`~pivot_ompl.analysis.regrasp_bound`) proves that no
plan exists; this module says why in terms a person can act on. The floor's obstacles (with
touching boxes merged, :func:`~pivot_ompl.validity.merge.merge_boxes`) and the floor's edges
are the walls; a *gap* is the shortest segment between two walls closer than the held
assembly's width (:func:`assembly_width`: the box and the holding robot together, plus the
checkers' clearance on both sides). Close every such gap: what remains of the floor falls
apart into regions the held box can roam. The gaps join those regions; the widest way from
the start's region to the goal's (the path whose narrowest gap is widest) has one narrowest
gap, the *passage* reported: no route of the held box avoids a passage at most that wide.

The passage is an explanation, not the proof (the relaxation is): the widths are exact
(distances between the walls' floor shadows), the held assembly's width is the width of its
convex outline, which an assembly turning inside a slot might beat by a little. Where no
opening joins the two regions at all, the floor itself is cut: that is a proof
(:func:`explain_no_plan`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.passage_reach import cell_budget, raster_cell, share_region
from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_footprints, obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

log = logging.getLogger(__name__)

#: Half-thickness (m) of the segment that closes a gap (it must seal it, nothing more).
SEAL = 1e-6
#: Gaps narrower than this (m) are walls touching up to round-off (a floor turned or mirrored
#: moves touching edges apart by ~1e-16 m): sealed like every gap, but joining no regions.
TOUCH = 2.0 * SEAL
#: Most gaps the search closes (their union is not interruptible and grows faster than their
#: number: 2837 gaps of a 30 x 15 m SLAM map took 17 s); beyond, no passage is reported.
MAX_GAPS = 1000


@dataclass(frozen=True)
class Passage:
    """The narrowest passage every route of the held box must take (:func:`blocking_passage`).

    Attributes:
        center: the gap's midpoint ``(x, y)`` (m, world frame); ``None`` when no gap joins
            the start's region to the goal's at all (one of them is closed on every side).
        ends: the gap's two ends on the walls, ``((x, y), (x, y))`` (m); ``None`` with
            ``center``.
        width: the gap's width (m); 0 when closed.
        box_needs: the narrowest gap the box alone may pass (m: its short side plus the
            clearance on both sides).
        assembly_needs: the narrowest gap the box and the robot holding it may pass together
            (m: the width of their convex outline plus the clearance on both sides).
        note: the reason, when another proof than the width says why the passage blocks
            (:mod:`~pivot_ompl.analysis.pose_proof`: wide enough, but not to turn through).
    """

    center: tuple[float, float] | None
    ends: tuple[tuple[float, float], tuple[float, float]] | None
    width: float
    box_needs: float
    assembly_needs: float
    note: str | None = None

    @property
    def reason(self) -> str:
        """One line a person can act on: which passage, where, its width, what needs what."""
        if self.note is not None:
            return self.note
        if self.center is None:
            return (f"no plan: no opening joins the start's region to the goal's (the box "
                    f"and the robot holding it need {self.assembly_needs:.2f} m)")
        x, y = self.center
        if self.width >= self.box_needs:
            return (f"no plan: the slot at ({x:.2f}, {y:.2f}) is {self.width:.2f} m; the box "
                    f"passes ({self.box_needs:.2f} m) but the robot needs "
                    f"{self.assembly_needs:.2f} m to follow the box")
        return (f"no plan: the passage at ({x:.2f}, {y:.2f}) is {self.width:.2f} m; the box "
                f"needs {self.box_needs:.2f} m (with the robot holding it "
                f"{self.assembly_needs:.2f} m)")

    def as_dict(self) -> dict[str, object]:
        """The plan file's ``passage`` field (JSON-ready)."""
        return {"center": None if self.center is None else list(self.center),
                "ends": None if self.ends is None else [list(p) for p in self.ends],
                "width": self.width, "box_needs": self.box_needs,
                "assembly_needs": self.assembly_needs, "reason": self.reason}


def hull_extents(points: np.ndarray) -> list[tuple[float, float]]:
    """``(width, length)`` (m) of a point set's convex outline square to and along each edge.

    The least width over every direction is the least of the widths (the outline's
    narrowest direction is square to one of its edges).
    """
    hull = np.asarray(shapely.MultiPoint(points).convex_hull.exterior.coords)
    out = []
    for a, b in zip(hull[:-1], hull[1:], strict=True):
        d = b - a
        n = math.hypot(d[0], d[1])
        if n < 1e-12:
            continue
        off = np.abs((points[:, 0] - a[0]) * d[1] - (points[:, 1] - a[1]) * d[0]) / n
        along = (points @ d) / n
        out.append((float(off.max()), float(along.max() - along.min())))
    return out


def min_width(points: np.ndarray) -> float:
    """The least width (m) of a point set's convex outline over every direction."""
    return min((w for w, _ in hull_extents(points)), default=math.inf)


def assembly_width(model: BoxGraspModel, *, clearance: float = KEEP_CLEARANCE) -> float:
    """Narrowest gap (m) the box and the robot holding it may pass, over the grasps."""
    box = np.array(rectangle_corners((0.0, 0.0, 0.0), model.object_size[0],
                                     model.object_size[1]), dtype=float)
    widths = []
    for grasp in (0, 1):
        robot = model.robot_pose((0.0, 0.0, 0.0), grasp)
        held = np.array(model.held_corners(robot, grasp), dtype=float)
        widths.append(min_width(np.vstack([box, held])))
    return min(widths) + 2.0 * clearance


def _walls(scene: Scene, thickness: float,
           should_stop: Callable[[], bool] | None) -> list[BaseGeometry]:
    """The obstacles' convex floor pieces and four slabs just outside the floor's bounds."""
    polys = [shapely.Polygon(p) for p in
             obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))]
    x0, y0, x1, y1 = scene.bounds
    t = thickness
    polys += [shapely.box(x0 - t, y0 - t, x1 + t, y0), shapely.box(x0 - t, y1, x1 + t, y1 + t),
              shapely.box(x0 - t, y0, x0, y1), shapely.box(x1, y0, x1 + t, y1)]
    return polys


def _gap_centre(wall_a: BaseGeometry, wall_b: BaseGeometry, width: float
                ) -> tuple[float, float]:
    """Centre of the gap between two walls ``width`` apart: of the hull of their facing parts.

    (The shortest segment between two parallel faces sits at one end of the slot; the hull of
    the parts of each wall within the gap's width of the other spans the whole slot.)
    """
    reach = width * (1.0 + 1e-6) + 1e-9
    near_a = wall_a.intersection(wall_b.buffer(reach, quad_segs=2))
    near_b = wall_b.intersection(wall_a.buffer(reach, quad_segs=2))
    c = shapely.union_all([near_a, near_b]).convex_hull.centroid
    if c.is_empty:  # the facing parts vanished to round-off: the shortest segment's middle
        c = shapely.shortest_line(wall_a, wall_b).interpolate(0.5, normalized=True)
    return (float(c.x), float(c.y))


def _region_of(regions: list[BaseGeometry], tree: shapely.STRtree,
               xy: tuple[float, float]) -> int | None:
    """Index of the region holding (or, off every region, nearest) the point ``xy``."""
    if not regions:
        return None
    return int(tree.nearest(shapely.Point(xy)))


def blocking_passage(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
                     should_stop: Callable[[], bool] | None = None,
                     gaps_below: float | None = None) -> Passage | None:
    """The narrowest gap on the widest way of the held box from start to goal.

    ``None`` when the start's and goal's regions are joined without any gap narrower than
    the held assembly (the obstruction is then not one passage: room to turn, to regrasp...),
    when the floor has more than :data:`MAX_GAPS` such gaps (a cluttered map: not searched)
    or when ``should_stop`` said stop. ``gaps_below``: the gaps closed are those narrower
    than this (m) instead of the held assembly's width (a proof that the assembly cannot
    turn through wider gaps names the widest one).
    """
    return passage_search(scene, clearance=clearance, should_stop=should_stop,
                          gaps_below=gaps_below)[0]


def passage_search(scene: Scene, *, clearance: float = KEEP_CLEARANCE,
                   should_stop: Callable[[], bool] | None = None,
                   gaps_below: float | None = None) -> tuple[Passage | None, bool | None]:
    """:func:`blocking_passage`'s answer, and whether the way is clear.

    The way is clear (``True``) when the start's and the goal's regions are joined clear of
    every gap closed (narrower than the held assembly, or than ``gaps_below``); ``False``
    when every way passes such a gap (whether a passage is named or the gaps were too many
    to search); ``None`` when ``should_stop`` said stop.
    """
    try:
        return _blocking_passage(scene, clearance, should_stop, gaps_below)
    except Interrupted:
        return None, None


def _blocking_passage(scene: Scene, clearance: float,
                      should_stop: Callable[[], bool] | None,
                      gaps_below: float | None = None) -> tuple[Passage | None, bool]:
    model = scene.model
    need = assembly_width(model, clearance=clearance)
    shut = need if gaps_below is None else gaps_below
    box_need = min(model.object_size[0], model.object_size[1]) + 2.0 * clearance
    walls = _walls(scene, max(1.0, shut), should_stop)
    tree = shapely.STRtree(walls)
    a, b = tree.query(walls, predicate="dwithin", distance=shut)
    keep = a < b
    a, b = a[keep], b[keep]
    lines = shapely.shortest_line(np.asarray(walls, dtype=object)[a],
                                  np.asarray(walls, dtype=object)[b])
    widths = shapely.length(lines)
    gaps = widths > 0.0
    a, b, lines, widths = a[gaps], b[gaps], lines[gaps], widths[gaps]
    s_xy, g_xy = (scene.start[0], scene.start[1]), (scene.goal[0], scene.goal[1])
    if share_region(walls, lines, scene.bounds, s_xy, g_xy, cell=raster_cell(shut), seal=SEAL,
                    max_cells=cell_budget(len(walls) + len(lines)), should_stop=should_stop):
        return None, True  # one region (clear of every gap, so of those kept below)
    # a gap whose segment meets a third wall is not needed: that wall's gaps to both ends are
    # shorter, so closed too, and seal the same way (on cluttered maps most gaps are such)
    # (the walls query a tree of the lines: GEOS prepares the walls, the costlier side)
    hits = np.bincount(shapely.STRtree(lines).query(walls, predicate="intersects")[1],
                       minlength=len(lines))
    gaps = hits <= 2
    a, b, lines, widths = a[gaps], b[gaps], lines[gaps], widths[gaps]
    if len(lines) > MAX_GAPS:
        log.debug("passage search skipped: %d gaps (> %d)", len(lines), MAX_GAPS)
        return None, False
    if should_stop is not None and should_stop():
        raise Interrupted("the passage search")
    x0, y0, x1, y1 = scene.bounds
    # walls grown by SEAL: edges that touch up to round-off leave no crack between them
    solid = shapely.union_all(list(shapely.buffer(walls, SEAL, join_style="mitre"))
                              + list(shapely.buffer(lines, SEAL)))
    free = shapely.box(x0, y0, x1, y1).difference(solid)
    regions = [g for g in getattr(free, "geoms", [free]) if not g.is_empty]
    if should_stop is not None and should_stop():
        raise Interrupted("the passage search")
    rtree = shapely.STRtree(regions)
    start, goal = _region_of(regions, rtree, s_xy), _region_of(regions, rtree, g_xy)
    if start is None or goal is None or start == goal:
        return None, start is not None and start == goal
    touch_gap, touch_region = rtree.query(shapely.buffer(lines, 4.0 * SEAL),
                                          predicate="intersects")
    joins: dict[int, list[int]] = {}
    for g, r in zip(touch_gap.tolist(), touch_region.tolist(), strict=True):
        joins.setdefault(g, []).append(r)
    parent = list(range(len(regions)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for g in sorted(joins, key=lambda g: -widths[g]):  # widest gaps first (maximin path)
        if widths[g] <= TOUCH:  # the rest are touching walls: no opening at all
            break
        rs = joins[g]
        for r in rs[1:]:
            parent[find(r)] = find(rs[0])
        if find(start) == find(goal):
            p, q = shapely.get_coordinates(lines[g])[:2]
            mid = _gap_centre(walls[a[g]], walls[b[g]], float(widths[g]))
            log.debug("blocking passage: %.3f m at (%.2f, %.2f)", widths[g], *mid)
            return Passage(mid, ((float(p[0]), float(p[1])), (float(q[0]), float(q[1]))),
                           float(widths[g]), box_need, need), False
    return Passage(None, None, 0.0, box_need, need), False


def gap_at(scene: Scene, place: tuple[float, float], *, reach: float, widest: float,
           clearance: float = KEEP_CLEARANCE) -> Passage | None:
    """The narrowest gap whose shortest segment passes within ``reach`` of ``place``.

    Walls: the obstacles' footprints and the floor's outside, merged where they touch,
    within ``reach + widest`` of ``place`` (gaps up to ``widest`` m wide are seen); ``None``
    when no two walls there have such a gap.
    """
    point = shapely.Point(place)
    disk = point.buffer(reach + widest, quad_segs=8)
    feet = np.asarray(obstacle_footprints(scene.obstacles), dtype=object)
    near = feet[shapely.intersects(feet, disk)] if len(feet) else feet
    floor = shapely.box(*scene.bounds)
    local = shapely.union_all([*near, floor.buffer(1.0, join_style="mitre").difference(floor)])
    walls = [w for w in getattr(local.intersection(disk), "geoms", [local.intersection(disk)])
             if not w.is_empty and w.area > 0.0]
    best: tuple[float, int, int, BaseGeometry] | None = None
    for i in range(len(walls)):
        for j in range(i + 1, len(walls)):
            line = shapely.shortest_line(walls[i], walls[j])
            if 0.0 < line.length <= widest and line.distance(point) <= reach and (
                    best is None or line.length < best[0]):
                best = (line.length, i, j, line)
    if best is None:
        return None
    width, i, j, line = best
    model = scene.model
    (px, py), (qx, qy) = shapely.get_coordinates(line)[:2]
    return Passage(_gap_centre(walls[i], walls[j], width),
                   ((float(px), float(py)), (float(qx), float(qy))), float(width),
                   min(model.object_size[0], model.object_size[1]) + 2.0 * clearance,
                   assembly_width(model, clearance=clearance))


class PassageOnce:
    """One scene's :func:`blocking_passage`, searched once and shared.

    :func:`pivot_ompl.api.plan` asks for the passage before the search
    (:func:`explain_no_plan`) and again in the late proof
    (:class:`~pivot_ompl.analysis.late_proof.LateProof`); one instance answers both. A
    search that ``should_stop`` may have cut short is not kept (asked again, it runs again).

    Args:
        scene: the scene whose passage is searched.

    Attributes:
        clear: once searched, whether the start's and the goal's regions are joined clear of
            every gap narrower than the held assembly (:func:`passage_search`); ``None``
            before, or when the search was stopped.
    """

    def __init__(self, scene: Scene) -> None:
        """Nothing searched yet."""
        self.scene = scene
        self._known = False
        self._passage: Passage | None = None
        self.clear: bool | None = None

    def __call__(self, *, should_stop: Callable[[], bool] | None = None) -> Passage | None:
        """The passage (as :func:`blocking_passage`), searched the first time only."""
        if self._known:
            return self._passage
        passage, clear = passage_search(self.scene, should_stop=should_stop)
        if passage is not None or should_stop is None or not should_stop():
            self._known, self._passage, self.clear = True, passage, clear
        return passage

    @property
    def answer(self) -> tuple[Passage | None, bool | None] | None:
        """The passage and :attr:`clear` once searched (to :meth:`share`), else ``None``."""
        return (self._passage, self.clear) if self._known else None

    def share(self, answer: tuple[Passage | None, bool | None] | None) -> None:
        """Take the :attr:`answer` of the same scene's search made elsewhere (``None``: none)."""
        if answer is not None:
            self._known, (self._passage, self.clear) = True, answer


def explain_no_plan(scene: Scene, *, should_stop: Callable[[], bool] | None = None,
                    passages: PassageOnce | None = None) -> tuple[str, Passage] | None:
    """Why ``scene`` has no plan, when a passage blocks it and the relaxation proves it.

    First the passage (:func:`blocking_passage`, milliseconds): when the start's and the
    goal's regions are joined by gaps as wide as the held assembly, no proof is tried (the
    relaxation is slow on large floors, and the plans it would rule out are rare) and the
    answer is ``None``. Otherwise the regrasp bound's relaxation runs: when it joins no path
    no plan exists, and the answer is the passage's reason (one line) and the passage;
    ``None`` when it joins one or ``should_stop`` stopped it (nothing is proven then).
    A passage with no opening at all (``center`` ``None``) is its own proof: the box's
    centre cannot leave the floor less the obstacles' footprints (every obstacle stands on
    the floor, as the box does), and that floor holds no way from start to goal (walls
    closer than :data:`TOUCH` count as touching: no box passes them), so the relaxation
    is not run.
    ``passages``: the scene's passage search to share (:class:`PassageOnce`), if any.
    """
    search = passages if passages is not None else PassageOnce(scene)
    passage = search(should_stop=should_stop)
    if passage is None:
        return None
    if passage.center is None:  # the floor itself is cut between start and goal: proven
        return passage.reason, passage
    bound = lower_bound(scene, should_stop=should_stop)
    if bound.solvable is not False:
        return None
    return passage.reason, passage

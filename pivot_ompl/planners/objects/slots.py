"""Narrow passages read from the scene's geometry: gaps between facing obstacles.

A *passage* is the gap between two obstacles (the room's sides count as obstacles) whose
width lies in a given range. Its axis runs square to the shortest segment joining them,
through that segment's midpoint; along the axis it is centred on the stretch where the two
obstacles face each other (the overlap of their projections on the axis), so a slot cut
through a thick wall is centred in the wall whatever the segment's ends. Everything comes from
the obstacles' own footprints (shapely's exact distances), so a rotated, mirrored or
unfamiliar layout gives its own passages: no direction of the world is preferred.

The regrasp planner seeds its object roadmap with box poses along two kinds of passage:

* **slots** (:func:`slots`, :func:`slot_poses`), too narrow for the walking robot: only the
  box passes, the robot lets go of it and walks round. Sampling finds such a pose (box within
  a few centimetres of both sides, yaw within a few degrees of the axis) only after thousands
  of samples;
* **doors** (:func:`doors`, :func:`door_poses`), wide enough for the held assembly (box and
  robot) but narrower than the disk it sweeps turning: robot and box pass together, pushed
  or pulled straight along the door's axis. Random poses line the assembly up with such a door
  rarely (a 1.7 m door in a wall: hundreds of diffusion steps per door on a floor of many
  rooms); the seeded ones do it by construction, a straight push from a pose wholly before the
  door to one wholly past it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.objects.roadmap import canonical
from pivot_ompl.scene import Obstacle, Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.assembly_field import assembly_bodies
from pivot_ompl.validity.footprints import obstacle_footprints
from pivot_ompl.validity.merge import merge_boxes


@dataclass(frozen=True)
class Passage:
    """A gap between two obstacles.

    Attributes:
        center: the middle of the gap (m): across, the midpoint of the shortest segment
            joining the obstacles; along, the middle of the stretch where they face each other.
        axis: yaw (rad) of the passage's axis, in ``[-pi/2, pi/2)`` (either way along it).
        width: the gap (m), the length of that shortest segment.
        length: the stretch along the axis where the obstacles face each other (m, ``0`` when
            they face each other at one point only, e.g. two disks).
    """

    center: tuple[float, float]
    axis: float
    width: float
    length: float


class Area(Protocol):
    """Where passages are looked for (e.g. :class:`~.floor_band.BandRegion`)."""

    def holds(self, x: float, y: float) -> bool:
        """Whether the point ``(x, y)`` is in the area."""

    def meets(self, bounds: tuple[float, float, float, float]) -> bool:
        """Whether the area meets the box ``(x0, y0, x1, y1)``."""


def _room_sides(bounds: tuple[float, float, float, float], depth: float) -> list[BaseGeometry]:
    """The four slabs just outside the room's bounds, ``depth`` thick."""
    x0, y0, x1, y1 = bounds
    return [shapely.box(x0 - depth, y0 - depth, x0, y1 + depth),
            shapely.box(x1, y0 - depth, x1 + depth, y1 + depth),
            shapely.box(x0, y0 - depth, x1, y0),
            shapely.box(x0, y1, x1, y1 + depth)]


def _extent(geom: BaseGeometry, u: np.ndarray) -> tuple[float, float]:
    """The interval of ``geom``'s projection on the unit vector ``u``."""
    pts = np.asarray(shapely.get_coordinates(geom))
    proj = pts @ u
    return float(proj.min()), float(proj.max())


#: Length (m) cut off both ends of a gap's shortest segment before testing what lies across it
#: (its ends touch the two obstacles, and the pieces adjoining them).
_SEGMENT_TRIM = 1e-4
#: Obstacles whose pairs :func:`find_passages` measures in one vectorised batch (the
#: termination condition is polled between batches).
PAIR_BATCH = 64


def _blocked(shapes: np.ndarray, tree: shapely.STRtree, ends: np.ndarray, i: np.ndarray,
             j: np.ndarray) -> np.ndarray:
    """Per pair, whether a third obstacle's interior meets the segment joining the pair.

    ``ends``: the pairs' shortest segments, ``(n, 2, 2)``; ``i``, ``j``: the pairs' indices
    in ``shapes``. The segments are trimmed by :data:`_SEGMENT_TRIM` at both ends, and all
    tested at once (one query of ``tree``, one vectorised predicate).
    """
    out = np.zeros(len(i), dtype=bool)
    a, b = ends[:, 0], ends[:, 1]
    d = np.array([math.hypot(bx - ax, by - ay) for (ax, ay), (bx, by) in zip(a, b, strict=True)])
    long = np.flatnonzero(d > 2.0 * _SEGMENT_TRIM)
    if not len(long):
        return out
    t = (_SEGMENT_TRIM / d[long])[:, None]
    a, b = a[long], b[long]
    segs = shapely.linestrings(np.stack([a + t * (b - a), b - t * (b - a)], axis=1))
    s, k = tree.query(segs, predicate="intersects")
    third = (k != i[long][s]) & (k != j[long][s])
    s, k = s[third], k[third]
    if not len(s):
        return out
    order = np.argsort(s, kind="stable")
    s, k = s[order], k[order]
    rank = np.arange(len(s)) - np.searchsorted(s, s)  # the candidate's place in its segment's
    blocked = np.zeros(len(segs), dtype=bool)
    for r in range(int(rank.max()) + 1):  # the r-th candidates of the segments still open
        ask = np.flatnonzero((rank == r) & ~blocked[s])
        if not len(ask):
            break
        hit = shapely.relate_pattern(shapes[k[ask]], segs[s[ask]], "T********")
        blocked[s[ask[hit]]] = True
    out[long] = blocked
    return out


def find_passages(scene: Scene, *, min_width: float, max_width: float,
                  should_stop: Callable[[], bool] = lambda: False,
                  obstacles: Sequence[Obstacle] | None = None,
                  within: Area | None = None) -> list[Passage]:
    """Every gap of width in ``[min_width, max_width]`` between two obstacles or sides.

    Each pair of obstacles (the room's four sides included) gives at most one passage, at its
    shortest segment, if no third obstacle lies across that segment (a gap with something in
    it is the gaps on either side of that thing: an obstacle made of thin pieces otherwise
    gives one passage per pair of pieces facing each other across the gap, thousands on a
    large floor; boxes touching along a whole side count as one, :func:`merge_boxes`). Sides
    meeting at a corner, and obstacles touching, give none. The pairs are measured in
    vectorised batches of :data:`PAIR_BATCH` obstacles (a SLAM map's specks make hundreds of
    thousands of pairs); the passages come in the order of the obstacles, then of the
    obstacle tree's query.
    ``should_stop`` is polled per batch: the passages found so far are returned.
    ``obstacles``: the scene's with touching boxes merged already (a collision world's
    :attr:`~pivot_ompl.validity.collision.CollisionWorld.obstacles`); ``None``: merged here.
    ``within``: only the passages whose centre it holds (an obstacle farther from it than
    ``max_width`` is not looked at); ``None``: the whole floor.
    """
    merged = merge_boxes(scene.obstacles) if obstacles is None else obstacles
    listed = obstacle_footprints(merged)
    listed += _room_sides(scene.bounds, max(1.0, 2.0 * max_width))
    shapes = np.empty(len(listed), dtype=object)
    shapes[:] = listed
    tree = shapely.STRtree(shapes)
    near = np.asarray(_near(listed, within, max_width), dtype=bool)
    out: list[Passage] = []
    for first in range(0, len(shapes), PAIR_BATCH):
        if should_stop():
            break
        rows = np.flatnonzero(near[first:first + PAIR_BATCH]) + first
        if not len(rows):
            continue
        q, j = tree.query(shapes[rows], predicate="dwithin", distance=max_width)
        i = rows[q]
        pair = (j > i) & near[j]
        i, j = i[pair], j[pair]
        width = shapely.distance(shapes[i], shapes[j])
        fits = (width >= min_width) & (width <= max_width)
        i, j, width = i[fits], j[fits], width[fits]
        if not len(i):
            continue
        ends = shapely.get_coordinates(shapely.shortest_line(shapes[i], shapes[j]))
        ends = ends.reshape(-1, 2, 2)
        for n in np.flatnonzero(~_blocked(shapes, tree, ends, i, j)):
            p = _passage(shapes[i[n]], shapes[j[n]], ends[n], float(width[n]))
            if within is None or within.holds(*p.center):
                out.append(p)
    return out


def _passage(a: BaseGeometry, b: BaseGeometry, ends: np.ndarray, width: float) -> Passage:
    """The passage between ``a`` and ``b`` across their shortest segment ``ends``."""
    ax, ay, bx, by = (float(v) for v in ends.ravel())
    axis = math.atan2(by - ay, bx - ax) + 0.5 * math.pi
    u = np.array([math.cos(axis), math.sin(axis)])
    lo_a, hi_a = _extent(a, u)
    lo_b, hi_b = _extent(b, u)
    lo, hi = max(lo_a, lo_b), min(hi_a, hi_b)
    mid = np.array([0.5 * (ax + bx), 0.5 * (ay + by)])
    along = 0.5 * (lo + hi) if hi >= lo else float(mid @ u)
    c = mid + (along - float(mid @ u)) * u
    return Passage((float(c[0]), float(c[1])),
                   (axis + 0.5 * math.pi) % math.pi - 0.5 * math.pi, width, max(0.0, hi - lo))


def _near(shapes: list[BaseGeometry], within: Area | None, reach: float) -> list[bool]:
    """Per shape, whether ``within`` meets its bounding box grown by ``reach`` (all: ``None``)."""
    if within is None:
        return [True] * len(shapes)
    grown = shapely.bounds(shapes) + np.array([-reach, -reach, reach, reach])
    return [within.meets((float(b[0]), float(b[1]), float(b[2]), float(b[3]))) for b in grown]


def passage_poses(passage: Passage, *, reach: float, spacing: float,
                  approach: tuple[float, ...]) -> list[Pose]:
    """Box poses on a passage's axis, at both yaws square to each other along it.

    Every ``spacing`` from the centre up to ``length / 2 + reach`` on both sides (through the
    passage and out of it), then at ``length / 2 + reach + d`` for each ``d`` of ``approach``
    (where the box is pushed in or pulled out).
    """
    half = 0.5 * passage.length + reach
    n = int(math.floor(half / spacing + 1e-9))
    offsets = [k * spacing for k in range(-n, n + 1)]
    offsets += [s * (half + d) for d in approach for s in (-1.0, 1.0)]
    cx, cy = passage.center
    c, s = math.cos(passage.axis), math.sin(passage.axis)
    return [(cx + t * c, cy + t * s, yaw) for yaw in (passage.axis, passage.axis + 0.5 * math.pi)
            for t in offsets]


def slots(checker: PivotChecker, *, play: float,
          should_stop: Callable[[], bool] = lambda: False,
          within: Area | None = None) -> list[Passage]:
    """The scene's slots: gaps wide enough for the box but not for the walking robot.

    A gap counts if it is wider than the box's narrow side (plus the kept clearance on both
    sides) and narrower than the walking robot's least width (plus the clearance and
    ``play``, beyond which the robot's walk passes). ``within``: as for :func:`find_passages`.
    """
    m, clear = checker.model, checker.world.clearance
    ahead, behind, half_width = m.walking_extent()
    narrowest = min(ahead + behind, 2.0 * half_width) + 2.0 * clear
    return find_passages(checker.scene, obstacles=checker.world.obstacles,
                         min_width=min(m.object_size[:2]) + 2.0 * clear,
                         max_width=narrowest + play, should_stop=should_stop, within=within)


def slot_poses(checker: PivotChecker, passages: list[Passage], *, spacing: float,
               approach: tuple[float, ...],
               should_stop: Callable[[], bool] = lambda: False) -> list[Pose]:
    """The free box poses along ``passages`` (:func:`passage_poses`, yaw modulo pi).

    ``should_stop`` is polled per passage: the poses found so far are returned.
    """
    reach = max(checker.model.object_size[:2])
    out: list[Pose] = []
    for passage in passages:
        if should_stop():
            break
        for q in passage_poses(passage, reach=reach, spacing=spacing, approach=approach):
            if checker.box_valid(q):
                out.append(canonical(q))
    return out


@dataclass(frozen=True)
class AssemblyExtent:
    """The held assembly's size in the frame of its car (the grasps' widest).

    Attributes:
        width: its least width across the car's heading, over the grasps (m): a gap
            narrower (less the kept clearance) lets no held assembly through.
        radius: the radius of the disk it sweeps turning about its car, the grasps' largest
            (m): a gap wider than that diameter is no narrow passage for it.
        reach: how far it extends along the heading from the box's centre, either way, the
            grasps' largest (m): a box centre that far past a passage has the whole assembly
            through.
    """

    width: float
    radius: float
    reach: float


def assembly_extent(checker: PivotChecker) -> AssemblyExtent:
    """The held assembly's :class:`AssemblyExtent` for the checker's model."""
    m = checker.model
    widths, radii, reaches = [], [], []
    for g in range(4):
        pts = np.concatenate(assembly_bodies(m, g, 0.0))
        widths.append(float(np.ptp(pts[:, 1])))
        radii.append(float(np.hypot(pts[:, 0], pts[:, 1]).max()))
        reaches.append(float(np.abs(pts[:, 0] - m.half_extent(g)).max()))
    return AssemblyExtent(min(widths), max(radii), max(reaches))


def doors(checker: PivotChecker, *, play: float,
          should_stop: Callable[[], bool] = lambda: False,
          within: Area | None = None) -> list[Passage]:
    """The scene's doors: gaps the held assembly passes but cannot turn in.

    Wider than the assembly's least width and narrower than the disk it sweeps turning
    (:func:`assembly_extent`), both plus the kept clearance on both sides, plus ``play``:
    a gap a little wider than the disk still holds an assembly crossing it to a narrow
    range of yaws. ``within``: as for :func:`find_passages`.
    """
    ext, clear = assembly_extent(checker), checker.world.clearance
    return find_passages(checker.scene, obstacles=checker.world.obstacles,
                         min_width=ext.width + 2.0 * clear,
                         max_width=2.0 * (ext.radius + clear) + play, should_stop=should_stop,
                         within=within)


def door_poses(checker: PivotChecker, passages: list[Passage], *,
               should_stop: Callable[[], bool] = lambda: False) -> list[Pose]:
    """The free box poses on the doors' axes from which the assembly passes straight through.

    Per door, box centres on its axis at its centre and as far beyond its ends as the
    assembly reaches (:func:`assembly_extent`): the outer two hold the whole assembly on
    either side, and each is one straight push or pull from the centre. At both yaws square
    to each other (each grasp pushes along the axis at one of them); yaw modulo pi.
    ``should_stop`` is polled per door: the poses found so far are returned.
    """
    reach = assembly_extent(checker).reach
    out: list[Pose] = []
    for passage in passages:
        if should_stop():
            break
        cx, cy = passage.center
        c, s = math.cos(passage.axis), math.sin(passage.axis)
        half = 0.5 * passage.length + reach
        for yaw in (passage.axis, passage.axis + 0.5 * math.pi):
            for t in (-half, 0.0, half):
                q = (cx + t * c, cy + t * s, yaw)
                if checker.box_valid(q):
                    out.append(canonical(q))
    return out

"""The passages a plan may need, found along the box's coarse routes and widened on demand.

On a floor of at least ``band_area`` square metres (bounds) cut into at least ``band_boxes``
obstacles (a SLAM map's walls and specks), the regrasp planner seeds its
object roadmap with the slots and doors (:mod:`.slots`) of the band round the box's
cheapest coarse routes (:class:`~.floor_band.FloorBand`) only, in levels of growing slack
(``band_slacks``, then the whole floor). Of the passages found in a
level's band it keeps (:func:`choose_passages`):

* those that lead somewhere the held assembly cannot simply go round nearby
  (:meth:`~.floor_band.FloorBand.bypassed`: the gaps between SLAM specks in an open room,
  and the gaps along a wall cut into pieces, are none);
* one of each group of near-equal ones (centres within ``band_spacing``, axes within
  :data:`SAME_AXIS`; the narrowest stays): the cross-sections of one corridor between wall
  pieces;
* at most ``band_passages`` per kind and level (times the level's number), those on the
  cheapest routes first.

The passages' geometry is exact (found and seeded as ever): only which ones is decided on
the raster. A smaller or plainer floor gets every passage, unless it is *crowded*: more slots,
or more doors, than one level may seed (``band_passages``; a small room's SLAM map whose
specks make thousands of gaps, each a few dozen roadmap nodes to multiplex). There the band is
made once that many are found, and the passages are chosen from them as above.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.objects.floor_band import BandRegion, BandStats, FloorBand
from pivot_ompl.planners.objects.roadmap import PoseIndex, Roadmap
from pivot_ompl.planners.objects.slots import Area, Passage, door_poses, doors, slot_poses, slots
from pivot_ompl.planners.sampling_config import SamplingConfig
from pivot_ompl.se2 import Pose

Stop = Callable[[], bool]

#: Axes (rad, modulo pi) within which two near passages count as one.
SAME_AXIS = math.radians(30.0)


def _axis_gap(a: float, b: float) -> float:
    return abs((a - b + 0.5 * math.pi) % math.pi - 0.5 * math.pi)


def thinned(passages: list[Passage], spacing: float) -> list[Passage]:
    """The passages, narrowest first, less those near one kept before.

    Near: centres within ``spacing`` and axes within :data:`SAME_AXIS`.
    """
    kept: list[Passage] = []
    buckets: dict[tuple[int, int], list[Passage]] = {}
    for p in sorted(passages, key=lambda q: q.width):
        bx, by = int(p.center[0] // spacing), int(p.center[1] // spacing)
        near = (q for i in (-1, 0, 1) for j in (-1, 0, 1)
                for q in buckets.get((bx + i, by + j), ()))
        if any(math.dist(p.center, q.center) < spacing and _axis_gap(p.axis, q.axis) < SAME_AXIS
               for q in near):
            continue
        kept.append(p)
        buckets.setdefault((bx, by), []).append(p)
    return kept


def choose_passages(passages: list[Passage], band: FloorBand, *, reach: float, spacing: float,
                    cap: int) -> list[Passage]:
    """The passages worth seeding of ``passages`` (module docstring), narrowest first.

    ``reach``: how near (m) a way round counts (:meth:`FloorBand.bypassed`).
    """
    useful = [p for p in passages if not band.bypassed(p, reach=reach)]
    few = thinned(useful, spacing)
    few.sort(key=lambda p: (band.route_cost(*p.center), p.width))
    return sorted(few[:cap], key=lambda p: p.width)


@dataclass(frozen=True)
class Seeded:
    """What one seeding of the passages added.

    Attributes:
        slots: slots found (this level's).
        slot_nodes: roadmap nodes added along them.
        doors: doors found (this level's).
        door_nodes: roadmap nodes added along them.
    """

    slots: int = 0
    slot_nodes: int = 0
    doors: int = 0
    door_nodes: int = 0


def add_poses(roadmap: Roadmap, seeded: PoseIndex, poses: Iterable[Pose], *, kind: str,
              spacing: float, region: BaseGeometry | None, should_stop: Stop) -> int:
    """Add the free box poses along passages that a plan may visit, each once.

    A pose is left out when its position is outside ``region`` (the box centres reachable
    from the start, :meth:`~.samplers.PoseSampler.region`; ``None``: the floor) or when a pose
    seeded before (``seeded``, which gets the poses added) lies within half the ``spacing``
    of it (:func:`~.roadmap.pose_metric`): one gap between obstacles made of several pieces
    is found once per pair of pieces. Passages come narrowest first, so of near-equal poses
    the one centred in the tightest gap stays. Returns the number added (of ``kind``).
    """
    added = 0
    for k, q in enumerate(poses):
        if k % 64 == 63 and should_stop():  # thousands of passage poses on large floors
            break
        if region is not None and not shapely.contains_xy(region, q[0], q[1]):
            continue
        if seeded.any_within(q, 0.5 * spacing):
            continue
        seeded.append(roadmap.add(q, kind))
        added += 1
    return added


class PassageBand:
    """The slots and doors to seed, level by level (module docstring).

    Args:
        checker: the scene, box and held assembly.
        start, goal: the box's poses.
        config: the object roadmap's parameters (``slot_play``, ``door_play``, ``band_*``).

    Attributes:
        level: the band's level (index in ``band_slacks``; their number: the whole floor),
            ``0`` at first.
        band: the coarse routes, ``None`` when every passage is seeded (a small or plain
            floor, or the band disabled).
    """

    def __init__(self, checker: PivotChecker, start: Pose, goal: Pose,
                 config: SamplingConfig) -> None:
        """Nothing computed yet (:meth:`slots` and :meth:`doors` do)."""
        self.checker, self.start, self.goal, self.config = checker, start, goal, config
        self.level = 0
        self.band: FloorBand | None = None
        self._made = False
        self._crowded = False  #: more passages of a kind found than a level seeds

    def applies(self) -> bool:
        """Whether the floor is large and cluttered enough for a band (``band_*``)."""
        cfg = self.config
        x0, y0, x1, y1 = self.checker.world.bounds
        return bool(cfg.band_slacks) and (x1 - x0) * (y1 - y0) >= cfg.band_area \
            and len(self.checker.world.obstacles) >= cfg.band_boxes

    def _band(self, should_stop: Stop) -> FloorBand | None:
        if not self._made:
            self._made = True
            cfg = self.config
            if self.applies() or (self._crowded and bool(cfg.band_slacks)):
                try:
                    self.band = FloorBand(self.checker, self.start, self.goal,
                                          cell=cfg.band_cell, max_cells=cfg.band_max_cells,
                                          penalty=cfg.band_penalty, margin=cfg.band_margin,
                                          should_stop=should_stop)
                except Interrupted:
                    self._made = False
        return self.band

    @property
    def stats(self) -> BandStats | None:
        """The coarse routes' figures (``None``: no band)."""
        return None if self.band is None else self.band.stats

    def area(self) -> BandRegion | None:
        """The band at this level (``None``: no band, or the whole floor)."""
        if self.band is None or not self.band.joined() \
                or self.level >= len(self.config.band_slacks):
            return None
        return self.band.region(self.config.band_slacks[self.level])

    def _area(self) -> Area | None:
        if self.band is None:
            return None
        slacks = self.config.band_slacks
        return self.band.region(slacks[self.level] if self.level < len(slacks) else math.inf)

    def slots(self, should_stop: Stop) -> list[Passage]:
        """The slots to seed at this level, narrowest first."""
        return self._chosen(slots, self.config.slot_play, should_stop)

    def doors(self, should_stop: Stop) -> list[Passage]:
        """The doors to seed at this level, narrowest first."""
        return self._chosen(doors, self.config.door_play, should_stop)

    def _chosen(self, find: Callable[..., list[Passage]], play: float,
                should_stop: Stop) -> list[Passage]:
        band = self._band(should_stop)
        found = find(self.checker, play=play, should_stop=should_stop, within=self._area())
        cfg = self.config
        if band is None and not self._crowded and len(found) > cfg.band_passages:
            self._crowded, self._made = True, False  # a crowded floor: the band after all
            band = self._band(should_stop)
        if band is None:
            return sorted(found, key=lambda p: p.width)
        return choose_passages(found, band, reach=cfg.band_reach, spacing=cfg.band_spacing,
                               cap=cfg.band_passages * (self.level + 1))

    def seed(self, roadmap: Roadmap, seeded: PoseIndex, region: BaseGeometry | None,
             should_stop: Stop) -> Seeded:
        """Add this level's slot and door poses to ``roadmap`` (:func:`add_poses`).

        As the configuration asks (``slots``, ``doors``, their spacing and approaches).
        """
        cfg, ck = self.config, self.checker
        n_slots = n_doors = slot_nodes = door_nodes = 0
        if cfg.slots:
            found = self.slots(should_stop)
            n_slots = len(found)
            slot_nodes = add_poses(
                roadmap, seeded, slot_poses(ck, found, spacing=cfg.slot_spacing,
                                            approach=cfg.slot_approach, should_stop=should_stop),
                kind="slot", spacing=cfg.slot_spacing, region=region, should_stop=should_stop)
        if cfg.doors:
            found = self.doors(should_stop)
            n_doors = len(found)
            door_nodes = add_poses(
                roadmap, seeded, door_poses(ck, found, should_stop=should_stop), kind="door",
                spacing=cfg.slot_spacing, region=region, should_stop=should_stop)
        return Seeded(n_slots, slot_nodes, n_doors, door_nodes)

    def can_widen(self) -> bool:
        """Whether a wider level is left (a band, and a slack after this one)."""
        return (self.band is not None and self.band.joined()
                and self.level < len(self.config.band_slacks))

    def widen(self) -> None:
        """Go to the next level (its passages include this one's)."""
        if self.can_widen():
            self.level += 1

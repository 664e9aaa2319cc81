"""A proof that no plan exists from the held assembly's poses, refined in yaw where needed.

The box moves only while the robot holds it (at one of four grasps), continuously through
valid poses (the transfer checks certify every rotation's sweep: every pose keeps
:data:`MOTION_CLEARANCE`, the 1 cm less the sweep's tolerance); a regrasp leaves the box
where it rests. So a plan is a path through the held poses ``(x, y, yaw, grasp)`` that keeps
its grasp while it moves and changes grasp only standing still, with both grasps valid there.
This relaxation over-approximates those poses: the yaw circle is cut into bins, and per bin
and grasp the box positions at which the assembly may be valid at some yaw of the bin fall
into connected parts (:func:`~pivot_ompl.analysis.pose_cells.free_components`; a halved bin's
from its parent's, :class:`~pivot_ompl.analysis.pose_bins.BinRegions`). Two parts are
joined when they meet and their bins are neighbours at one grasp (a motion crossing the bins'
common yaw), or they meet at one bin for two grasps and the robot may walk between the two
stances round the box resting there (a regrasp; the walk,
:mod:`~pivot_ompl.analysis.pose_walk`, is asked only of a chain's regrasps: one it refuses is
dropped and the chain sought again, :func:`~pivot_ompl.analysis.pose_chain.walked_chain`).
A path of the plan visits joined parts only, so when no part holding the start is joined to
one holding the goal, no plan exists.

An obstacle piece left out of the sums only enlarges the parts, so the parts of fewer pieces
still over-approximate the poses. The proof first sums only the pieces near the room's narrow
passages between start and goal (:mod:`~pivot_ompl.analysis.pose_passages`: on a large floor
a small share of them, the open floor's walls left out); where those parts still join start
and goal, or compute the regions of :data:`PASSAGE_BINS` bins, the proof starts again with every
piece.

The bins start coarse (:data:`FIRST_BINS`); while a chain of parts joins start and goal, the
chain's bins in which it regrasps (:func:`~pivot_ompl.analysis.pose_split.regrasp_bins`),
else those whose part spans more floor than its neighbours on the chain
(:func:`~pivot_ompl.analysis.pose_split.spanning_bins`), else its widest bins, are halved
with the bins opposite them (a chain through too coarse bins is
refined away, a true one stays; a grasp that is another's half turn has that grasp's parts at
the opposite bin, so a bin and its opposite cost one bin's parts), up to :data:`MAX_BINS`
bins or bins of :data:`FINEST` rad; a bin's parts are computed when a chain search first
reaches a part of it or of a neighbouring bin
(:class:`~pivot_ompl.analysis.pose_graph.PoseGraph`, ``lazy``), the stop
polled before each and before every chain search. Pivoting
is small-time controllable, so where the finest bins still join start and goal the answer
is "joined" (no proof; the poses connect at the bins' scale).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property, partial

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_bins import BinRegions
from pivot_ompl.analysis.pose_chain import Node
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_graph import PoseGraph
from pivot_ompl.analysis.pose_split import regrasp_bins, spanning_bins
from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import GRASPS
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

log = logging.getLogger(__name__)

#: Per part, the parts of the other side it meets (:meth:`HeldParts.meet`).
Partners = dict[int, list[int]]

#: Yaw bins of the first round (over the whole turn).
FIRST_BINS = 32
#: Most yaw bins (each costs the box's free region and four grasps' free parts, about 30 ms
#: on a 5 m arena of 157 boxes): the memory and time bound.
MAX_BINS = 1024
#: Narrowest bin (rad) halved again (the lab door's and the TurtleBot3 arena's proofs end
#: at 1.4 degrees).
FINEST = 2.0 * math.pi / 512

#: Largest share of the pieces near the room that lie near its passages for a first proof
#: with those only (:func:`prove_no_plan`): more would save little of a proof with all.
PASSAGE_SHARE = 0.5
#: Fewest pieces near the room for a first proof with the passages' (on fewer, as on the
#: shipped scenes' 7-17, a bin's sums cost little next to its chain search).
PASSAGE_FLOOR = 64
#: Most bins whose regions the passages' proof computes (:func:`prove_no_plan`) before it
#: gives way to the proof with every piece (40 on the lab door's 1506 boxes): where its
#: looser parts still join start and goal by then, the proof with every piece is the answer.
PASSAGE_BINS = 48

#: Bins a proof computes, for :func:`proof_estimate` (the regions computed, a twin's not
#: counted: 40 on the 1506 boxes of the lab door and on the TurtleBot3 arena, 36-122 on the
#: feasible 4- to 32-room corridor rows).
ESTIMATED_BINS = 64
#: Time (s) of one obstacle piece's sums and union, per bin computed and grasp (whole
#: proofs, their set-up and chain searches included: 3.8e-5 on the lab door, 4.8e-5 on
#: the arena; the corridor rows' long walls cost more, 3.9e-4 for the 16 rooms' 57: the
#: every-yaw gate, not this estimate, spares them the proof).
SECONDS_PER_PIECE = 5e-5


@dataclass(frozen=True)
class PoseProof:
    """What the held poses' relaxation says about a scene (:func:`prove_no_plan`).

    Attributes:
        apart: ``True``: no part holding the start is joined to one holding the goal (no
            plan exists); ``False``: joined at the finest bins (nothing proven); ``None``:
            stopped, out of bins, or start or goal in no part (nothing proven).
        bins: yaw bins of the last round.
        finest: the narrowest bin (rad).
        rounds: rounds of refinement.
        seconds: time taken (s).
        reached: with ``apart``, the start's parts (their union: :attr:`start_reach`).
        refused: with ``apart``, the box positions of the last round's regrasps on a chain
            from start to goal round whose resting box the robot cannot walk (m, world).
    """

    apart: bool | None
    bins: int
    finest: float
    rounds: int
    seconds: float
    reached: tuple[BaseGeometry, ...] = ()
    refused: tuple[BaseGeometry, ...] = ()

    @cached_property
    def start_reach(self) -> BaseGeometry | None:
        """With ``apart``, the box positions the start's parts cover (m, world).

        Joined when first asked: the parts of every bin overlap, and their union costs as
        much as a bin's parts.
        """
        return shapely.union_all(self.reached) if self.reached else None


class HeldParts:
    """The free parts of every (bin, grasp), computed once per bin and kept.

    Args:
        scene: the scene.
        clearance: kept from the obstacles (m) by the box centre's room (:attr:`room`) and,
            unless ``parts_clearance`` says otherwise, by the parts' poses.
        should_stop: polled while the obstacles are merged and before the room is found
            (:class:`~pivot_ompl.errors.Interrupted` when true).
        parts_clearance: kept by the parts' poses (m), within the room; ``None``:
            ``clearance``.
        regions: what builds each bin's regions from the grown pieces, the bodies and the
            room (:class:`~pivot_ompl.analysis.pose_bins.BinRegions` or a subclass).
        floor: the scene's :class:`~pivot_ompl.analysis.pose_floor.HeldFloor` to read (its
            pieces, room and walks), shared with other relaxations of the scene; built here
            when ``None``, of another scene, or kept at another clearance than ``clearance``.
        pieces: the grown pieces to sum, stacked by vertex count, some of the floor's near
            the room (fewer pieces, larger free parts: still an over-approximation, unless
            ``regions`` is coarse); ``None``: all of those the bins' regions read.
    """

    def __init__(self, scene: Scene, clearance: float,
                 should_stop: Callable[[], bool] | None, *,
                 parts_clearance: float | None = None,
                 regions: type[BinRegions] = BinRegions,
                 floor: HeldFloor | None = None,
                 pieces: dict[int, np.ndarray] | None = None) -> None:
        if floor is None or floor.scene is not scene or floor.clearance != clearance:
            floor = HeldFloor(scene, clearance, should_stop)
        self.floor = floor
        self.bodies = floor.bodies
        #: where the box centre may go at all (``None``: not even the start is in it)
        self.room = floor.room
        self.area = floor.area
        kept = clearance if parts_clearance is None else parts_clearance
        grown = (pieces if pieces is not None
                 else floor.coarse_near_room(kept, should_stop) if regions.coarse
                 else floor.near_room(kept))
        self.bins = regions(grown, self.bodies, self.area)
        self.known: dict[tuple[float, float], list[list[BaseGeometry]]] = {}
        self.met: dict[tuple[float, ...], tuple[Partners, Partners]] = {}
        self.walks = floor.walks
        self.walked: dict[tuple[float, float], dict[tuple[int, int, int, int], bool]] = {}

    def of(self, a: float, b: float) -> list[list[BaseGeometry]]:
        """Per grasp, the free parts of the bin ``[a, b]``."""
        key = (a, b)
        if key not in self.known:
            self.known[key] = [[g for g in getattr(r, "geoms", [r]) if not g.is_empty]
                               for r in self.bins.regions(a, b)]
        return self.known[key]

    def forget(self, a: float, b: float) -> None:
        """Drop the parts of the bin ``[a, b]`` (halved: never asked again)."""
        self.known.pop((a, b), None)
        self.walked.pop((a, b), None)

    def may_regrasp(self, edges: list[float], u: Node, v: Node) -> bool:
        """Whether the robot may walk round the box between parts ``u`` and ``v``.

        ``u``, ``v``: parts of one bin of ``edges``, asked where they meet
        (:mod:`~pivot_ompl.analysis.pose_walk`); ``False`` proves that no regrasp joins them.
        """
        a, b = edges[u[0]], edges[u[0] + 1]
        key = (*u[1:], *v[1:]) if u[1:] < v[1:] else (*v[1:], *u[1:])
        asked = self.walked.setdefault((a, b), {})
        if key not in asked:
            here = self.of(a, b)
            region = here[key[0]][key[1]].intersection(here[key[2]][key[3]])
            asked[key] = self.walks.may_regrasp(region, a, b, key[0], key[2])
        return asked[key]

    def meet(self, key: tuple[float, ...], a: list[BaseGeometry],
             b: list[BaseGeometry]) -> tuple[Partners, Partners]:
        """Which parts of ``a`` meet which of ``b`` (kept under ``key``: bins and grasps).

        Per part of ``a`` the parts of ``b`` it meets, and per part of ``b`` those of ``a``,
        each list ascending.
        """
        if key not in self.met:
            self.met[key] = _meets(a, b)
        return self.met[key]


#: Yaw keys per turn (:func:`turn_key`): bins are dyadic parts of the turn, far coarser.
TURN_KEYS = 1 << 20


def turn_key(yaw: float) -> int:
    """``yaw`` (rad) as an integer step of the turn, modulo the turn: a bin edge's key."""
    return round(yaw / (2.0 * math.pi) * TURN_KEYS) % TURN_KEYS


def with_opposites(edges: list[float], split: set[int]) -> list[int]:
    """The bins ``split`` of ``edges`` and those opposite them (their yaws plus pi), sorted.

    A bin's parts at a grasp that is another's half turn are the opposite bin's
    (:class:`HeldParts`): halved together, both bins' halves cost what one bin's do.
    """
    at = {(turn_key(edges[i]), turn_key(edges[i + 1])): i for i in range(len(edges) - 1)}
    out = set(split)
    for i in split:
        j = at.get((turn_key(edges[i] + math.pi), turn_key(edges[i + 1] + math.pi)))
        if j is not None:
            out.add(j)
    return sorted(out)


def _meets(a: list[BaseGeometry], b: list[BaseGeometry]) -> tuple[Partners, Partners]:
    ab: Partners = {}
    ba: Partners = {}
    if a and b:
        hit = shapely.intersects(np.array(a, dtype=object)[:, None],
                                 np.array(b, dtype=object)[None])
        for i, j in zip(*np.nonzero(hit), strict=True):  # row by row: both lists ascending
            ab.setdefault(int(i), []).append(int(j))
            ba.setdefault(int(j), []).append(int(i))
    return ab, ba


def widest_bins(edges: list[float], path: list[Node], finest: float
                ) -> tuple[list[int], float]:
    """The bins of a chain to halve, with those opposite them, and the chain's widest (rad).

    The chain's widest bins first (within 1 %), none of :data:`FINEST` or finer: a chain
    through coarse bins is most often false (:func:`with_opposites`).
    """
    widths = {i: edges[i + 1] - edges[i] for i, _, _ in path}
    widest = max(widths.values())
    return with_opposites(edges, {i for i, w in widths.items()
                                  if w > finest and w >= 0.99 * widest}), widest


def halve(parts: HeldParts, edges: list[float], split: list[int]) -> None:
    """Halve the bins ``split`` of ``edges`` in place, their parts forgotten."""
    for i in reversed(split):
        parts.forget(edges[i], edges[i + 1])
        edges.insert(i + 1, 0.5 * (edges[i] + edges[i + 1]))


def proof_estimate(scene: Scene) -> float:
    """Estimated time (s) of :func:`prove_no_plan` (:data:`ESTIMATED_BINS` bins)."""
    pieces = sum(1 if isinstance(o, BoxObstacle | CylinderObstacle) else len(o.points) - 2
                 for o in scene.obstacles)
    return ESTIMATED_BINS * len(GRASPS) * (pieces + 4) * SECONDS_PER_PIECE


#: Clearance (m) every pose of a checked transfer keeps: the checkers' 1 cm at the sampled
#: poses, less the sweep tolerance between them (a certified interval's points are within it
#: of a sample: :func:`~pivot_ompl.validity.certify.certify`).
MOTION_CLEARANCE = KEEP_CLEARANCE - SWEEP_TOLERANCE


def prove_no_plan(scene: Scene, *, clearance: float = MOTION_CLEARANCE,
                  first_bins: int = FIRST_BINS, max_bins: int = MAX_BINS,
                  finest: float = FINEST,
                  should_stop: Callable[[], bool] | None = None,
                  floor: HeldFloor | None = None) -> PoseProof:
    """Whether the held poses' relaxation separates start and goal (the module docstring).

    First with the pieces near the room's narrow passages only
    (:meth:`~pivot_ompl.analysis.pose_floor.HeldFloor.passages_near_room`, where they are at
    most :data:`PASSAGE_SHARE` of :data:`PASSAGE_FLOOR` or more pieces): fewer pieces to sum
    per bin, and free parts that still over-approximate the valid poses, so start and goal
    apart there are apart. Else, or where those parts join them, with every piece.

    ``floor``: the scene's floor built at ``clearance``, shared with other relaxations (by
    default its own). Never raises on a stop: the answer is then ``apart=None``.
    """
    t0 = time.perf_counter()
    refine = partial(_refined, scene, first_bins=first_bins, max_bins=max_bins,
                     finest=finest, should_stop=should_stop, t0=t0)
    try:
        parts = HeldParts(scene, clearance, should_stop, floor=floor)
        if parts.room is None:
            return PoseProof(None, first_bins, 2.0 * math.pi / first_bins, 0,
                             time.perf_counter() - t0)
        if not parts.room.covers(shapely.Point(scene.goal[:2])):  # the box alone cannot go
            return PoseProof(True, first_bins, 2.0 * math.pi / first_bins, 0,
                             time.perf_counter() - t0, (parts.room,))
        narrow = passages_try(parts.floor, clearance)
        if narrow is not None:
            tried = HeldParts(scene, clearance, should_stop, floor=parts.floor, pieces=narrow)

            def enough() -> bool:  # polled before every bin's regions and chain search
                return tried.bins.computed >= PASSAGE_BINS or (
                    should_stop is not None and should_stop())

            proof = refine(tried, should_stop=enough)
            if proof.apart or (should_stop is not None and should_stop()):
                return proof
            log.debug("held poses: the passages' %d pieces join start and goal (%.2f s); "
                      "every piece next", count_pieces(narrow), proof.seconds)
        return refine(parts)
    except Interrupted:
        return PoseProof(None, first_bins, 2.0 * math.pi / first_bins, 0,
                         time.perf_counter() - t0)


def count_pieces(pieces: dict[int, np.ndarray]) -> int:
    """Pieces of a stack by vertex count."""
    return sum(len(stack) for stack in pieces.values())


def passages_try(floor: HeldFloor, clearance: float) -> dict[int, np.ndarray] | None:
    """The pieces :func:`prove_no_plan` sums first (those near the passages), ``None``: none.

    Tried where :data:`PASSAGE_FLOOR` or more pieces lie near the room and at most
    :data:`PASSAGE_SHARE` of them near its passages.
    """
    every = count_pieces(floor.near_room(clearance))
    if every < PASSAGE_FLOOR:
        return None
    narrow = floor.passages_near_room(clearance)
    return narrow if 0 < count_pieces(narrow) <= PASSAGE_SHARE * every else None


def _refined(scene: Scene, parts: HeldParts, *, first_bins: int, max_bins: int,
             finest: float, should_stop: Callable[[], bool] | None, t0: float) -> PoseProof:
    """The rounds of :func:`prove_no_plan` over ``parts`` (``seconds`` counted from ``t0``)."""
    edges = [2.0 * math.pi * i / first_bins for i in range(first_bins + 1)]
    rounds = 0

    def result(apart: bool | None, reach: tuple[BaseGeometry, ...] = (),
               refused: tuple[BaseGeometry, ...] = ()) -> PoseProof:
        widths = np.diff(edges)
        return PoseProof(apart, len(edges) - 1, float(widths.min()), rounds,
                         time.perf_counter() - t0, reach, refused)

    try:
        while True:
            rounds += 1
            graph = PoseGraph(parts, edges, should_stop, lazy=True)
            starts, goals = graph.nodes_at(edges, scene.start), graph.nodes_at(edges, scene.goal)
            if not starts or not goals:
                return result(None)
            found = graph.walked(parts, edges, starts, goals, should_stop=should_stop)
            path = found.nodes
            if found.price is None:
                reach = tuple(graph.bin(i)[g][k] for i, g, k in found.reached)
                return result(True, reach, tuple(graph.refused))
            split, widest = widest_bins(edges, path, finest)
            widths = np.diff(edges).tolist()
            first = (regrasp_bins(path, widths, finest)  # a coarse regrasp: likeliest false
                     or spanning_bins(path, [graph.bin(i)[g][k].area for i, g, k in path],
                                      widths, finest))  # then a part spanning more
            if first:
                split = with_opposites(edges, first)
            log.debug("held poses, round %d: %d bins, a chain of %d parts over %d bins; %d "
                      "halved (%.2f degrees); %d regrasps refused", rounds, len(edges) - 1,
                      len(path), len({i for i, _, _ in path}), len(split),
                      math.degrees(widest), len(graph.refused))
            if not split:
                return result(False)
            if len(edges) - 1 + len(split) > max_bins:
                return result(None)
            halve(parts, edges, split)
    except Interrupted:
        return result(None)

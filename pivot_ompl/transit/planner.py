"""The robot walking alone round the resting box (transit, the regrasping roadmap).

Free walking as in the regrasp paper (Section IV): forward walking, turning while walking,
sideways and backward steps, and turns in place. The walk planner is A* over a state lattice
(:mod:`pivot_ompl.transit.lattice`: floor grid x 16 headings), so it is complete at its
resolution: if a walk made of lattice motions exists, it is found. It needs no turning disk:
a robot narrower than a door walks through it forward or sideways.

* **Exact ends**: the grasp poses are joined to the nearby lattice states (within
  ``1.5 * resolution``, the two nearest headings) by a short straight motion.
* **Certified**: every motion is a straight move of the robot's centre with linear yaw,
  certified collision-free from clearances (:mod:`pivot_ompl.validity.certify`) against the
  obstacles and the bounds, and apart against the resting box (kept ``box_margin`` away: the
  robot's bounding box does not cover its arms' sway while it walks), each from its own
  clearances (larger than their minimum: fewer samples). A lattice motion's result is cached,
  the obstacles' part for the scene (walks pass the same doors again and again), the box's
  part per box pose. The clearances of lattice states are lower bounds from the turning disk
  where it is clear (one query per grid position for all headings), the robot body's own
  distance otherwise; the obstacles' part is cached per scene, the box's per box pose.
* **Admissible heuristics, cheap first**: most walks are easy, so a query is first searched
  guided by ``hypot(D, turn_cost * heading error)`` (weighted by ``floor_inflation``), where
  ``D`` is the shortest floor distance to the goal round the obstacles and the resting box
  (:meth:`~pivot_ompl.transit.field.FloorField.distances`, over the grid positions
  where the walking body fits at one of 32 yaws), a lower bound of every walk's length; every
  motion costs at least ``hypot(length, turn_cost * turn)``
  (:func:`~.lattice.motion_cost`). Where ``D`` is infinite no walk exists. A search
  past ``quick_expansions`` states (a tight spot, where that guide, blind to the headings,
  fills every heading of the cells near the goal) is made again guided by the cost-to-go of
  the lattice relaxed to its states
  (:meth:`~pivot_ompl.transit.field.FloorField.lattice_costs`: the same motions and
  costs, a state free when the walking body at its heading fits there and does not meet the
  grown box, motions' sweeps not checked; one Dijkstra, scipy), weighted by ``inflation``: it
  knows where the robot can stand at which heading, and where it is infinite no walk exists,
  so such queries end at once. Floors whose lattice is larger than ``max_field_states`` keep
  the floor distance.
* **Smoothing**: the lattice path is shortened greedily by certified straight motions (any
  direction, linear yaw) and by forward walks along Dubins curves (OMPL's, turning radius
  ``step_forward / step_turn``) whenever they cost less, in two passes. A Dubins shortcut is
  refused cheaply when it can be: its cost bounded from its length
  (:func:`~.lattice.forward_chain_cost_bound`), then its poses at 1/2, 1/4 and 3/4 of
  the way (a blocked curve nearly always is at one of them), before it is sampled whole and
  costed (:func:`~.lattice.chain_cost`). The lattice states' clearances come from the
  search's caches, and the second pass reuses what the first learnt: the poses' clearances,
  the motions certified or refused, the curves sampled.
* **Lazy**: a motion (and the state it reaches) is certified only when the search takes it
  from the queue (lazy A*, :func:`pivot_ompl.graph.astar` with ``valid``): most motions out of
  an expanded state never are, and cost nothing.
* Every loop honours the caller's termination condition; a search larger than
  ``max_expansions`` states gives up (no walk).
"""

from __future__ import annotations

import logging
import math
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.dubins import Dubins
from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.field import FloorField
from pivot_ompl.transit.lattice import (
    HEADING_YAWS,
    N_HEADINGS,
    chain_cost,
    forward_chain_cost_bound,
    motion_cost,
    nearest_headings,
    primitives,
)
from pivot_ompl.validity.certify import SWEEP_TOLERANCE, certify
from pivot_ompl.validity.collision import CollisionWorld

log = logging.getLogger(__name__)

State = tuple[int, int, int]
_START: State = (-1, -1, -1)
_GOAL: State = (-2, -2, -2)


@dataclass(frozen=True)
class WalkResult:
    """A transit walk.

    Attributes:
        valid: a collision-free walk was found.
        robot_path: key poses (straight segments, yaw interpolated linearly between them).
        length: walking distance of the robot's centre (m).
        cost: walking cost (m of forward walking: sideways, backward and turning weighted by
            the scene's ``robot.walk`` costs).
    """

    valid: bool
    robot_path: tuple[Pose, ...]
    length: float
    cost: float


INVALID_WALK = WalkResult(False, (), math.inf, math.inf)


@dataclass
class _BoxTable:
    """What is known of the lattice with the box resting at one pose."""

    #: lower bound of each state's clearance (obstacles, bounds and box)
    states: dict[State, float] = field(default_factory=dict)
    #: lower bound of each state's clearance to the box, less the margin
    box: dict[State, float] = field(default_factory=dict)
    #: lattice motions (end states in order) certified clear of the box
    edges: dict[tuple[State, State], bool] = field(default_factory=dict)


@dataclass
class _SmoothMemo:
    """What the smoothing passes over one walk learn, shared between them."""

    #: clearances of each pose met (:meth:`WalkPlanner._exact_parts`)
    clearances: dict[Pose, tuple[float, float]] = field(default_factory=dict)
    #: straight motions (linear yaw) certified free or refused
    segments: dict[tuple[Pose, Pose], bool] = field(default_factory=dict)
    #: Dubins walks sampled: their poses (ends included) and their cost; ``None``: blocked
    curves: dict[tuple[Pose, Pose], tuple[np.ndarray, float] | None] = field(
        default_factory=dict)


class _GiveUp(Exception):
    """The lattice search exceeded its budget."""


@dataclass
class WalkPlanner:
    """Plans the robot's walk between two grasps of a resting box (see the module docstring).

    Args:
        model: box and robot geometry.
        world: the static obstacles (robot body queries go through it).
        walk: step limits and walking costs.
        resolution: lattice grid spacing (m).
        box_margin: clearance kept from the resting box while walking (m).
        tolerance: swept-check tolerance (m).
        max_expansions: lattice states expanded before a query gives up.
        box_cache: resting-box poses whose lattice clearances are kept.
        inflation: weight of the lattice cost-to-go heuristic (weighted A*: a walk costs at
            most this times the cheapest lattice walk; measured 0.6 % above it at 1.5).
        floor_inflation: weight of the floor-distance heuristic (floors too large for the
            lattice cost-to-go).
        max_field_states: largest lattice (grid positions x headings) whose cost-to-go is
            computed (about 100 bytes a state); larger floors use the floor distances.
        quick_expansions: a walk is first searched guided by the floor distances (cheap to
            compute, blind to the robot's heading); past this many expansions it is searched
            again guided by the lattice's cost-to-go (a Dijkstra per query, which pays only for
            the hard walks: turning in a tight spot, or no walk at all).
    """

    model: BoxGraspModel
    world: CollisionWorld
    walk: WalkParameters = field(default_factory=WalkParameters)
    resolution: float = 0.1
    box_margin: float = 0.08
    tolerance: float = SWEEP_TOLERANCE
    max_expansions: int = 60_000
    box_cache: int = 16
    inflation: float = 1.5
    floor_inflation: float = 3.0
    max_field_states: int = 1_000_000
    quick_expansions: int = 1500
    #: Termination condition polled by the search (set by the owner).
    should_stop: Callable[[], bool] | None = field(default=None, repr=False)
    expansions: int = field(default=0, init=False)

    def __post_init__(self) -> None:
        """Lattice size, primitives and the caches."""
        b = self.world.bounds
        self._nx = int(math.floor((b[2] - b[0]) / self.resolution)) + 1
        self._ny = int(math.floor((b[3] - b[1]) / self.resolution)) + 1
        self._prims = primitives(self.resolution, self.walk)
        self._radius = self.model.robot_radius()
        self._disk: dict[tuple[int, int], float] = {}
        self._static: dict[State, float] = {}
        self._boxed: OrderedDict[Pose, _BoxTable] = OrderedDict()
        self._static_edges: dict[tuple[State, State], bool] = {}
        self._distances: OrderedDict[tuple, np.ndarray] = OrderedDict()
        self._lattice: OrderedDict[tuple, np.ndarray] = OrderedDict()
        self._dubins = Dubins(turning_radius=self.walk.turning_radius)
        self.field = FloorField(self.model, self.world, self.resolution, self.box_margin)

    # -- clearances ------------------------------------------------------------------------
    def pose(self, s: State) -> Pose:
        """The robot pose of lattice state ``s``."""
        b = self.world.bounds
        return (b[0] + s[0] * self.resolution, b[1] + s[1] * self.resolution,
                HEADING_YAWS[s[2]])

    def _exact(self, p: Pose, obj: Pose | None) -> float:
        """Clearance (m) of the robot at ``p`` to obstacles, bounds and the resting box."""
        d = self._static_exact(p)
        if obj is not None and d > 0.0:
            d = min(d, self._box_clear(p, obj, d))
        return d

    def _static_exact(self, p: Pose) -> float:
        """Clearance (m) of the robot at ``p`` to the obstacles and the bounds."""
        w = self.world
        b, r = w.bounds, self._radius
        d = min(p[0] - b[0], b[2] - p[0], p[1] - b[1], b[3] - p[1]) - r  # disk: a lower bound
        if d < 2.0 * r:
            d = w.robot_bounds_margin(p)
            if d <= 0.0:
                return d
        return min(d, w.robot_distance(p))

    def _box_clear(self, p: Pose, obj: Pose, enough: float) -> float:
        """Lower bound of the robot's clearance at ``p`` to the box at ``obj``, less the margin.

        The cheap bound (:meth:`_box_lower_bound`) when it reaches ``enough``, else exact.
        """
        lb = self._box_lower_bound(p, obj)
        if lb < enough:
            return self.world.robot_box_distance(p, obj) - self.box_margin
        return lb

    def _box_lower_bound(self, p: Pose, obj: Pose) -> float:
        """Lower bound of the robot's clearance to the box at ``obj``, less the box margin.

        The robot's centre to the box rectangle, less the turning radius.
        """
        c, sn = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = p[0] - obj[0], p[1] - obj[1]
        lx, ly = abs(c * ex + sn * ey), abs(-sn * ex + c * ey)
        hw, hd = 0.5 * self.model.object_size[0], 0.5 * self.model.object_size[1]
        return math.hypot(max(0.0, lx - hw), max(0.0, ly - hd)) - self._radius - self.box_margin

    def _static_clearance(self, s: State) -> float:
        """Lower bound of the robot's clearance to obstacles and bounds at ``s`` (cached)."""
        v = self._static.get(s)
        if v is not None:
            return v
        x, y, yaw = self.pose(s)
        cell = (s[0], s[1])
        dd = self._disk.get(cell)
        if dd is None:
            b, r = self.world.bounds, self._radius
            dd = min(x - b[0] - r, b[2] - x - r, y - b[1] - r, b[3] - y - r)
            if dd > 0.0:
                dd = min(dd, self.world.turning_disk_distance(x, y))
            self._disk[cell] = dd
        if dd > 2.0 * self.resolution:
            v = dd
        else:
            w = self.world
            v = w.robot_bounds_margin((x, y, yaw))
            if v > 0.0:
                v = min(v, w.robot_distance((x, y, yaw)))
        self._static[s] = v
        return v

    def _box_table(self, obj: Pose) -> _BoxTable:
        table = self._boxed.get(obj)
        if table is None:
            table = _BoxTable()
            self._boxed[obj] = table
            while len(self._boxed) > self.box_cache:
                self._boxed.popitem(last=False)
        else:
            self._boxed.move_to_end(obj)
        return table

    def _box_state(self, s: State, obj: Pose, table: _BoxTable) -> float:
        """Lower bound of the robot's clearance at ``s`` to the box at ``obj`` (cached)."""
        v = table.box.get(s)
        if v is None:
            v = self._box_clear(self.pose(s), obj, 2.0 * self.resolution)
            table.box[s] = v
        return v

    def _clearance(self, s: State, obj: Pose, table: _BoxTable) -> float:
        """Lower bound of the robot's clearance at ``s`` with the box resting at ``obj``."""
        v = table.states.get(s)
        if v is not None:
            return v
        v = self._static_clearance(s)
        if v > 0.0:
            v = min(v, self._box_state(s, obj, table))
        table.states[s] = v
        return v

    def _sweep(self, a: Pose, b: Pose) -> float:
        """Farthest (m) any point of the walking body moves along ``a -> b`` (linear yaw)."""
        return math.hypot(b[0] - a[0], b[1] - a[1]) + self._radius * abs(wrap_angle(b[2] - a[2]))

    def _certified(self, a: Pose, b: Pose, clearance: Callable[[Pose], float], da: float,
                   db: float) -> bool:
        """The straight motion ``a -> b`` (linear yaw) keeps ``clearance`` positive.

        ``da``/``db``: lower bounds of ``clearance`` at the ends.
        """
        if da <= 0.0 or db <= 0.0:
            return False
        dyaw = wrap_angle(b[2] - a[2])
        lip = self._sweep(a, b)
        if da + db > lip:
            return True

        def at(s: float) -> float:
            return clearance((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                              a[2] + s * dyaw))

        return certify(at, lip, tolerance=self.tolerance, d0=da, d1=db).valid

    def _edge_free(self, u: State, v: State, obj: Pose, table: _BoxTable) -> bool:
        """The lattice motion between ``u`` and ``v`` is certified free (both ends free).

        Certified apart against the obstacles and bounds (cached for the scene: the same
        motions recur in every walk) and against the resting box (cached per box pose), each
        from its own clearances, which are larger than their minimum: fewer samples.
        """
        key = (u, v) if u < v else (v, u)
        ok = self._static_edges.get(key)
        if ok is None:
            ok = self._certified(self.pose(key[0]), self.pose(key[1]), self._static_exact,
                                 self._static_clearance(key[0]),
                                 self._static_clearance(key[1]))
            self._static_edges[key] = ok
        if not ok:
            return False
        ok = table.edges.get(key)
        if ok is None:
            a, b = self.pose(key[0]), self.pose(key[1])
            enough = self._sweep(a, b)
            ok = self._certified(a, b, lambda p: self._box_clear(p, obj, enough),
                                 self._box_state(key[0], obj, table),
                                 self._box_state(key[1], obj, table))
            table.edges[key] = ok
        return ok

    def _exact_parts(self, p: Pose, obj: Pose) -> tuple[float, float]:
        """:meth:`_exact` in two parts: to the obstacles and bounds, and to the box.

        The robot's clearance at ``p`` to the obstacles and bounds, and a lower bound of its
        clearance to the box less the margin (``-inf`` when the first is not positive);
        their minimum is :meth:`_exact`.
        """
        d = self._static_exact(p)
        return d, (self._box_clear(p, obj, d) if d > 0.0 else -math.inf)

    def _free_between(self, a: Pose, b: Pose, obj: Pose, ca: tuple[float, float],
                      cb: tuple[float, float]) -> bool:
        """:meth:`segment_free` from both ends' :meth:`_exact_parts` (no query at the ends).

        The obstacles and the box are certified apart, each from its own end clearances.
        """
        if min(ca) <= 0.0 or min(cb) <= 0.0:
            return False
        if a == b:
            return True
        sweep = self._sweep(a, b)
        if min(ca) + min(cb) > sweep:
            return True  # the ends' clearances alone certify it
        if not self._certified(a, b, self._static_exact, ca[0], cb[0]):
            return False
        return self._certified(a, b, lambda p: self._box_clear(p, obj, sweep), ca[1], cb[1])

    def segment_free(self, a: Pose, b: Pose, obj: Pose | None, *, da: float | None = None,
                     db: float | None = None) -> bool:
        """The straight motion ``a -> b`` (linear yaw) is certified free.

        ``da``/``db``: lower bounds of the end clearances (obstacles, bounds and box), if
        known. The obstacles and bounds, and the box, are certified apart (each from its own,
        larger, clearances).
        """
        if da is not None and da <= 0.0:
            return False
        if a == b:
            return (da if da is not None else self._exact(a, obj)) > 0.0
        if da is not None and db is not None and db > 0.0 and da + db > self._sweep(a, b):
            return True  # the ends' clearances alone certify it
        sa = da if da is not None else self._static_exact(a)
        sb = db if db is not None and db > 0.0 else self._static_exact(b)
        if not self._certified(a, b, self._static_exact, sa, sb):
            return False
        if obj is None:
            return True
        enough = self._sweep(a, b)
        ba = max(self._box_clear(a, obj, enough), da if da is not None else -math.inf)
        bb = max(self._box_clear(b, obj, enough), db if db is not None else -math.inf)
        return self._certified(a, b, lambda p: self._box_clear(p, obj, enough), ba, bb)

    # -- query -----------------------------------------------------------------------------
    def plan(self, obj: Pose, from_grasp: int, to_grasp: int, *,
             should_stop: Callable[[], bool] | None = None) -> WalkResult:
        """Walk from grasp ``from_grasp`` to grasp ``to_grasp`` of the box resting at ``obj``.

        Raises:
            Interrupted: ``should_stop()`` became true (floor field build, A* and smoothing
                poll it).
        """
        self.should_stop = should_stop
        m = self.model
        return self.plan_between(m.robot_pose(obj, from_grasp), m.robot_pose(obj, to_grasp),
                                 obj)

    def plan_between(self, start: Pose, goal: Pose, obj: Pose) -> WalkResult:
        """Walk from robot pose ``start`` to ``goal`` with the box resting at ``obj``."""
        table = self._box_table(obj)
        d_start, d_goal = self._exact(start, obj), self._exact(goal, obj)
        if d_start <= 0.0 or d_goal <= 0.0:
            return INVALID_WALK
        walk = self.walk
        starts = self._attach(start, obj, table, d_start, leaving=True)
        goals = self._attach(goal, obj, table, d_goal, leaving=False)
        if not starts or not goals:
            return INVALID_WALK
        # the floor distances first, with few expansions (most walks are easy); a walk
        # that needs more is searched again guided by the lattice's cost-to-go
        lattice = self._nx * self._ny * N_HEADINGS <= self.max_field_states
        dist = self._floor_distances(obj, goals)
        eps, gyaw, tc = self.floor_inflation, goal[2], walk.turn_cost

        def floor_closed(ix: int, iy: int, h: int) -> bool:  # no walk from there
            return math.isinf(dist[ix, iy])

        def floor_h(u: State) -> float:
            if u[0] < 0:
                return 0.0
            return eps * math.hypot(float(dist[u[0], u[1]]),
                                    tc * abs(wrap_angle(HEADING_YAWS[u[2]] - gyaw)))

        if all(floor_closed(*s) for s in starts):
            return INVALID_WALK
        try:
            states = self._search(starts, goals, obj, table, floor_closed, floor_h,
                                  self.quick_expansions if lattice else self.max_expansions)
        except _GiveUp:
            if not lattice:
                log.debug("walk search gave up after %d expansions", self.max_expansions)
                return INVALID_WALK
            costs = self._lattice_costs(obj, goals)
            weight = self.inflation

            def closed(ix: int, iy: int, h: int) -> bool:
                return math.isinf(costs[ix, iy, h])

            def heuristic(u: State) -> float:
                return 0.0 if u[0] < 0 else weight * float(costs[u])

            if all(closed(*s) for s in starts):
                return INVALID_WALK
            try:
                states = self._search(starts, goals, obj, table, closed, heuristic,
                                      self.max_expansions)
            except _GiveUp:
                log.debug("walk search gave up after %d expansions", self.max_expansions)
                states = []
        if not states:
            return INVALID_WALK
        poses = [start] + [self.pose(s) for s in states[1:-1]] + [goal]
        memo = _SmoothMemo()  # the second pass reuses what the first learnt
        for s in states[1:-1]:  # the lattice states' clearances, known from the search
            memo.clearances[self.pose(s)] = (self._static_clearance(s),
                                             self._box_state(s, obj, table))
        return self._result(self._smooth(self._smooth(poses, obj, memo=memo), obj, memo=memo))

    def _search(self, starts: dict[State, float], goals: dict[State, float], obj: Pose,
                table: _BoxTable, closed: Callable[[int, int, int], bool],
                heuristic: Callable[[State], float], cap: int) -> list[State]:
        """Lazy weighted A* over the lattice; ``[]``: no walk; raises ``_GiveUp`` past ``cap``."""
        counter = [0]
        stop = self.should_stop

        def neighbours(u: State):  # noqa: ANN202 - generator of (state, cost)
            if u == _START:
                yield from starts.items()
                return
            counter[0] += 1
            if counter[0] > cap:
                raise _GiveUp
            if stop is not None and counter[0] % 8 == 0 and stop():
                raise Interrupted("walk planning")
            nx, ny = self._nx, self._ny
            for pr in self._prims[u[2]]:
                ix, iy, h = u[0] + pr.dix, u[1] + pr.diy, (u[2] + pr.dh) % N_HEADINGS
                if 0 <= ix < nx and 0 <= iy < ny and not closed(ix, iy, h):
                    yield (ix, iy, h), pr.cost
            c = goals.get(u)
            if c is not None:
                yield _GOAL, c

        def free(u: State, v: State) -> bool:  # the joins to start and goal are certified
            if u == _START or v == _GOAL:
                return True
            return self._clearance(v, obj, table) > 0.0 and self._edge_free(u, v, obj, table)

        try:
            return astar([_START], {_GOAL}, neighbours, heuristic, valid=free)
        finally:
            self.expansions += counter[0]

    def _floor_distances(self, obj: Pose, goals: dict[State, float]) -> np.ndarray:
        """:meth:`FloorField.distances` to the goal states' positions (cached)."""
        cells = tuple(sorted({(s[0], s[1]) for s in goals}))
        dist = self._distances.get((obj, cells))
        if dist is None:
            if self.should_stop is not None and self.should_stop():  # tens of ms in C
                raise Interrupted("walk planning")
            dist = self.field.distances(obj, list(cells), self.should_stop)
            self._distances[(obj, cells)] = dist
            while len(self._distances) > 4 * self.box_cache:
                self._distances.popitem(last=False)
        return dist

    def _lattice_costs(self, obj: Pose, goals: dict[State, float]) -> np.ndarray:
        """:meth:`FloorField.lattice_costs` to the goal states (cached)."""
        key = (obj, tuple(sorted(goals)))
        costs = self._lattice.get(key)
        if costs is None:
            if self.should_stop is not None and self.should_stop():
                raise Interrupted("walk planning")
            costs = self.field.lattice_costs(obj, list(goals), self._prims, self.should_stop)
            self._lattice[key] = costs
            while len(self._lattice) > 4:  # a float per lattice state each; rarely asked again
                self._lattice.popitem(last=False)
        return costs

    def _attach(self, pose: Pose, obj: Pose, table: _BoxTable, d_pose: float, *,
                leaving: bool) -> dict[State, float]:
        """Lattice states joined to ``pose`` by a certified straight motion, with its cost."""
        b, res = self.world.bounds, self.resolution
        reach = 1.5 * res
        cx, cy = (pose[0] - b[0]) / res, (pose[1] - b[1]) / res
        out: dict[State, float] = {}
        for ix in range(math.floor(cx - 1.5), math.ceil(cx + 1.5) + 1):
            for iy in range(math.floor(cy - 1.5), math.ceil(cy + 1.5) + 1):
                if not (0 <= ix < self._nx and 0 <= iy < self._ny):
                    continue
                if math.hypot(ix - cx, iy - cy) * res > reach:
                    continue
                for h in nearest_headings(pose[2]):
                    s = (ix, iy, h)
                    cs = self._clearance(s, obj, table)
                    if cs <= 0.0:
                        continue
                    p = self.pose(s)
                    a, z = (pose, p) if leaving else (p, pose)
                    da, dz = (d_pose, cs) if leaving else (cs, d_pose)
                    if self.segment_free(a, z, obj, da=da, db=dz):
                        out[s] = motion_cost(a, z, self.walk)
        return out

    # -- smoothing -------------------------------------------------------------------------
    #: Certified shortcut attempts per smoothing pass.
    MAX_SHORTCUT_CHECKS = 400

    def _dubins_walk(self, a: Pose, b: Pose, length: float) -> np.ndarray:
        """Poses every ~``resolution`` along the Dubins curve ``a -> b`` (``length`` long).

        Ends included, as an ``(n, 3)`` array; yaws continuous from ``a``'s.
        """
        n = max(1, math.ceil(length / self.resolution))
        pts = np.array([a, *self._dubins.sample(a, b, [k / n for k in range(1, n)]), b])
        pts[1:-1, 2] = a[2] + (pts[1:-1, 2] - a[2] + math.pi) % (2.0 * math.pi) - math.pi
        return pts

    def _dubins_probes(self, a: Pose, b: Pose, pieces: int) -> list[Pose]:
        """The poses of :meth:`_dubins_walk` (``pieces`` pieces) at 1/2, 1/4 and 3/4 of the way.

        In that order; the same poses, to the bit (their clearances are shared).
        """
        ks = dict.fromkeys(k for k in (pieces // 2, pieces // 4, 3 * pieces // 4)
                           if 0 < k < pieces)
        out = []
        for k in ks:
            x, y, yaw = self._dubins.interpolate(a, b, k / pieces)
            out.append((x, y, a[2] + (yaw - a[2] + math.pi) % (2.0 * math.pi) - math.pi))
        return out

    def _smooth(self, poses: list[Pose], obj: Pose, *, memo: _SmoothMemo | None = None
                ) -> list[Pose]:
        """Greedy shortcuts: straight motions, then Dubins forward walks, when cheaper.

        ``memo``: what an earlier pass over the same walk learnt (clearances, certified or
        refused motions, sampled Dubins walks), reused and completed.
        """
        walk = self.walk
        memo = _SmoothMemo() if memo is None else memo
        known, segments, curves = memo.clearances, memo.segments, memo.curves
        costs = [motion_cost(a, b, walk) for a, b in zip(poses, poses[1:], strict=False)]
        prefix = [0.0]
        for c in costs:
            prefix.append(prefix[-1] + c)
        out = [poses[0]]
        checks = 0
        i, n = 0, len(poses)
        radius = walk.turning_radius

        def clear(p: Pose) -> tuple[float, float]:  # each pose's clearances, queried once
            d = known.get(p)
            if d is None:
                d = known[p] = self._exact_parts(p, obj)
            return d

        def chain_free(chain: list[Pose]) -> bool:
            cp = clear(chain[0])
            for p, q in zip(chain, chain[1:], strict=False):
                cq = clear(q)
                if min(cq) <= 0.0:
                    return False
                ok = segments.get((p, q))
                if ok is None:
                    ok = segments[(p, q)] = self._free_between(p, q, obj, cp, cq)
                if not ok:
                    return False
                cp = cq
            return True

        while i < n - 1:
            nxt, piece = i + 1, []
            # the far end first, then ends at halving distances: long shortcuts are tried
            # without spending the budget on every pose of a long walk
            ends = sorted({min(n - 1, i + step) for step in (n, 64, 32, 16, 8, 4, 2)},
                          reverse=True)
            for j in ends:
                if j <= i + 1:
                    continue
                if checks >= self.MAX_SHORTCUT_CHECKS:
                    break
                if self.should_stop is not None and self.should_stop():
                    raise Interrupted("walk smoothing")
                old = prefix[j] - prefix[i]
                a, b = poses[i], poses[j]
                if motion_cost(a, b, walk) < old - 1e-9:
                    checks += 1
                    if chain_free([a, b]):
                        nxt = j
                        break
                if (a, b) in curves:
                    curve = curves[(a, b)]
                else:
                    length = self._dubins.distance(a, b)
                    pieces = max(1, math.ceil(length / self.resolution))
                    # cheap refusals first: the curve's cost bounded from its length, then
                    # its poses at 1/2, 1/4 and 3/4 of the way (a blocked curve is nearly
                    # always blocked at one of them) before it is sampled whole
                    if length >= old - 1e-9 or forward_chain_cost_bound(
                            length, pieces, b[2] - a[2], radius, walk) >= old - 1e-9:
                        continue
                    curve = None
                    if all(min(clear(p)) > 0.0 for p in self._dubins_probes(a, b, pieces)):
                        pts = self._dubins_walk(a, b, length)
                        curve = (pts, chain_cost(pts, walk))
                    curves[(a, b)] = curve
                if curve is None:
                    continue
                pts, dc = curve
                if dc < old - 1e-9:
                    checks += 1
                    mids: list[Pose] = [(x, y, t) for x, y, t in pts[1:-1].tolist()]
                    if chain_free([a, *mids, b]):
                        nxt, piece = j, mids
                        break
            out.extend(piece)
            out.append(poses[nxt])
            i = nxt
        return out

    def _result(self, poses: list[Pose]) -> WalkResult:
        keys = [poses[0]]
        for p in poses[1:]:
            last = keys[-1]
            q = (p[0], p[1], last[2] + wrap_angle(p[2] - last[2]))
            if abs(q[0] - last[0]) + abs(q[1] - last[1]) + abs(q[2] - last[2]) > 1e-12:
                keys.append(q)
        keys[-1] = poses[-1]
        length = sum(math.hypot(b[0] - a[0], b[1] - a[1])
                     for a, b in zip(keys, keys[1:], strict=False))
        cost = sum(motion_cost(a, b, self.walk) for a, b in zip(keys, keys[1:], strict=False))
        return WalkResult(True, tuple(keys), length, cost)

"""The robot walking alone round the resting box (transit, the regrasping roadmap).

Free walking as in the regrasp paper (Section IV): forward walking, turning while walking,
sideways and backward steps, and turns in place. The walk planner is A* over a state lattice
(:mod:`pivot_ompl.transit.lattice`: floor grid x 16 headings), so it is complete at its
resolution: if a walk made of lattice motions exists, it is found. It needs no turning disk:
a robot narrower than a door walks through it forward or sideways.

* **Turned to the walls** (:mod:`pivot_ompl.transit.frame`): a corridor 1-3 cm wider than the
  walking body is side-stepped along at any floor angle; walks are certified in the scene.
* **Exact ends**: the grasp poses are joined to the nearby lattice states (within
  ``1.5 * resolution``, the two nearest headings) by a short straight motion.
* **Certified**: every motion is a straight move of the robot's centre with linear yaw,
  certified collision-free (:mod:`pivot_ompl.transit.clearance`) against the obstacles and
  the bounds, and apart against the resting box. A lattice motion's result is cached, the
  obstacles' part for the scene (walks pass the same doors again and again), the box's part
  per box pose.
* **Admissible heuristics, cheap first**: a query is first searched guided by
  ``hypot(D, turn_cost * heading error)`` (weighted by ``floor_inflation``), ``D`` the
  shortest floor distance to the goal round the obstacles and the resting box
  (:meth:`~pivot_ompl.transit.field.FloorField.distances`, grid positions where the walking
  body fits at one of 32 yaws; :meth:`WalkPlanner.floor_distances`), a lower bound of every
  walk's length (:func:`~.lattice.motion_cost`); where ``D`` is infinite no walk exists. A
  search past ``quick_expansions`` states (a tight spot) is made again guided by the lattice's
  cost-to-go relaxed to its states (:meth:`~pivot_ompl.transit.lattice_field.LatticeField.costs`:
  the same motions and costs, sweeps not checked; one Dijkstra, scipy), weighted by
  ``inflation``: it knows where the robot can stand at which heading, and where it is
  infinite no walk exists. Floors whose lattice is larger than ``max_field_states`` keep the
  floor distance.
* **Smoothing** (:mod:`pivot_ompl.transit.smoothing`): the lattice path is shortened by
  certified straight motions and forward Dubins walks whenever they cost less, in two passes
  starting from the lattice states' clearances the search already knows.
* **Lazy**: a motion (and the state it reaches) is certified only when the search takes it
  from the queue (lazy A*, :func:`pivot_ompl.graph.astar` with ``valid``): most motions out of
  an expanded state never are, and cost nothing.
* Every loop honours the caller's termination condition (an argument, never stored); a
  search larger than ``max_expansions`` states gives up (no walk).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.clearance import BoxedClearance, State, WalkClearance
from pivot_ompl.transit.field import FloorField, FloorWindow
from pivot_ompl.transit.frame import LatticeFrame, frame_of
from pivot_ompl.transit.guides import DISTANCE_BYTES, WalkGuides
from pivot_ompl.transit.lattice import (
    HEADING_YAWS,
    N_HEADINGS,
    motion_cost,
    nearest_headings,
    primitives,
)
from pivot_ompl.transit.smoothing import SmoothMemo, WalkSmoother
from pivot_ompl.transit.walks import INVALID_WALK, WalkResult, walk_result
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import CollisionWorld

log = logging.getLogger(__name__)

__all__ = ["DISTANCE_BYTES", "INVALID_WALK", "WalkPlanner", "WalkResult"]

Stop = Callable[[], bool] | None
_START: State = (-1, -1, -1)
_GOAL: State = (-2, -2, -2)


class _GiveUp(Exception):
    """The lattice search exceeded its budget."""


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
            computed (about 100 bytes a state); larger floors use the floor distances, each
            query's in a window round its goals (:mod:`pivot_ompl.transit.floor_window`).
        quick_expansions: a walk is first searched guided by the floor distances (cheap to
            compute, blind to the robot's heading); past this many expansions it is searched
            again guided by the lattice's cost-to-go (a Dijkstra per query, which pays only for
            the hard walks: turning in a tight spot, or no walk at all).
        should_stop: polled while the floor is turned to the lattice's frame.

    Attributes:
        frame: the lattice's frame, turned to the walls. ``world``, ``clearance``, ``field``
            and the lattice methods (:meth:`attach`, ...) are in it; :meth:`plan` and
            :meth:`plan_between` take and give scene poses.
        certifier: the walking robot's clearances in the scene (certifies scene walks).
        clearance: the walking robot's clearances and certified motions.
        smoother: the walks' shortcuts.
        field: the floor's fields (distances, lattice costs).
        guides: the searches' heuristics' fields per query, cached (:mod:`~.guides`).
        expansions: lattice states expanded so far, over every query.
    """

    frame: LatticeFrame
    certifier: WalkClearance
    clearance: WalkClearance
    smoother: WalkSmoother
    field: FloorField
    guides: WalkGuides
    expansions: int

    def __init__(self, model: BoxGraspModel, world: CollisionWorld,
                 walk: WalkParameters | None = None, *, resolution: float = 0.1,
                 box_margin: float = 0.08, tolerance: float = SWEEP_TOLERANCE,
                 max_expansions: int = 60_000, box_cache: int = 16, inflation: float = 1.5,
                 floor_inflation: float = 3.0, max_field_states: int = 1_000_000,
                 quick_expansions: int = 1500, should_stop: Stop = None,
                 yaw: float | None = None,
                 within: tuple[float, float, float, float] | None = None) -> None:
        """The frame, lattice size, primitives, the parts and the caches.

        ``yaw``: the direction the lattice's frame is turned to (:func:`~pivot_ompl.
        transit.frame.frame_of`'s); default: that of all the walls' edges. ``within``:
        where in that frame the walking body may be (m: ``(x0, y0, x1, y1)``, e.g. round
        the free floor, :func:`~pivot_ompl.analysis.wall_frame.floor_bounds`); the frame's
        grid covers no more (default: the scene's bounds turned).

        Raises:
            Interrupted: ``should_stop()`` became true while the floor was turned to the
                lattice's frame.
        """
        scene_world, self.frame = world, frame_of(world, yaw=yaw)
        world = world if self.frame.identity else self.frame.world(world, should_stop,
                                                                    within=within)
        self.model, self.world = model, world
        self.walk = walk if walk is not None else WalkParameters()
        self.resolution, self.box_margin, self.tolerance = resolution, box_margin, tolerance
        self.max_expansions, self.quick_expansions = max_expansions, quick_expansions
        self.inflation, self.floor_inflation = inflation, floor_inflation
        self.max_field_states = max_field_states
        self.expansions = 0
        b = world.bounds
        self._nx = int(math.floor((b[2] - b[0]) / resolution)) + 1
        self._ny = int(math.floor((b[3] - b[1]) / resolution)) + 1
        self._prims = primitives(resolution, self.walk)
        self.clearance = WalkClearance(model, world, resolution=resolution,
                                       box_margin=box_margin, tolerance=tolerance,
                                       box_cache=box_cache)
        self.certifier = self.clearance if self.frame.identity else WalkClearance(
            model, scene_world, resolution=resolution, box_margin=box_margin,
            tolerance=tolerance, box_cache=box_cache)
        self.smoother = WalkSmoother(self.clearance, self.walk, resolution=resolution)
        self.field = FloorField(model, world, resolution, box_margin,
                                window_from=max_field_states // N_HEADINGS + 1)
        self.guides = WalkGuides(self.field, self._prims, resolution=resolution,
                                 floor_inflation=floor_inflation,
                                 positions=self._nx * self._ny, box_cache=box_cache)

    def cached_fields(self) -> tuple[int, int]:
        """:meth:`.WalkGuides.cached_fields`."""
        return self.guides.cached_fields()

    # -- query -----------------------------------------------------------------------------
    def plan(self, obj: Pose, from_grasp: int, to_grasp: int, *,
             should_stop: Stop = None) -> WalkResult:
        """Walk from grasp ``from_grasp`` to grasp ``to_grasp`` of the box resting at ``obj``.

        Raises:
            Interrupted: ``should_stop()`` became true (floor field build, A* and smoothing
                poll it).
        """
        m = self.model
        return self.plan_between(m.robot_pose(obj, from_grasp), m.robot_pose(obj, to_grasp),
                                 obj, should_stop=should_stop)

    def plan_between(self, start: Pose, goal: Pose, obj: Pose, *,
                     should_stop: Stop = None) -> WalkResult:
        """Walk from robot pose ``start`` to ``goal`` with the box resting at ``obj``.

        Planned in the lattice's frame; the walk mapped back is certified in the scene.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        f = self.frame
        if f.identity:
            return self._plan_framed(start, goal, obj, should_stop)
        res = self._plan_framed(f.into(start), f.into(goal), f.into(obj), should_stop)
        keys = [start, *(f.out(p) for p in res.robot_path[1:-1]), goal]
        for a, b in zip(keys, keys[1:], strict=False) if res.valid else ():
            if should_stop is not None and should_stop():
                raise Interrupted("walk planning")
            if not self.certifier.segment_free(a, b, obj):  # the frame rounds the poses
                return INVALID_WALK
        return walk_result(keys, self.walk) if res.valid else res

    def _plan_framed(self, start: Pose, goal: Pose, obj: Pose, should_stop: Stop
                     ) -> WalkResult:
        """:meth:`plan_between` in the lattice's frame."""
        boxed = self.clearance.with_box(obj)
        starts = self.attach(start, obj, leaving=True)
        goals = self.attach(goal, obj, leaving=False)
        if not starts or not goals:
            return INVALID_WALK
        states = self._lattice_walk(starts, goals, goal[2], obj, boxed, should_stop)
        if not states:
            return INVALID_WALK
        poses = [start] + [self.clearance.pose(s) for s in states[1:-1]] + [goal]
        memo = SmoothMemo()  # the second pass reuses what the first learnt
        for s in states[1:-1]:  # the lattice states' clearances, known from the search
            memo.clearances[self.clearance.pose(s)] = (self.clearance.static_state(s),
                                                       boxed.box_state(s))
        smooth = self.smoother.smooth
        once = smooth(poses, obj, memo=memo, should_stop=should_stop)
        return walk_result(smooth(once, obj, memo=memo, should_stop=should_stop), self.walk)

    def _lattice_walk(self, starts: dict[State, float], goals: dict[State, float],
                      goal_yaw: float, obj: Pose, boxed: BoxedClearance, should_stop: Stop
                      ) -> list[State]:
        """The lattice states of the cheapest walk found (``[]``: none).

        Guided by the floor distances first, with few expansions (most walks are easy); a
        walk that needs more is searched again guided by the lattice's cost-to-go.
        """
        lattice = self._nx * self._ny * N_HEADINGS <= self.max_field_states
        dist = self.floor_distances(obj, goals, starts=starts, should_stop=should_stop)
        eps, tc = self.floor_inflation, self.walk.turn_cost

        def floor_closed(ix: int, iy: int, h: int) -> bool:  # no walk from there
            return math.isinf(dist[ix, iy])

        def floor_h(u: State) -> float:
            if u[0] < 0:
                return 0.0
            return eps * math.hypot(float(dist[u[0], u[1]]),
                                    tc * abs(wrap_angle(HEADING_YAWS[u[2]] - goal_yaw)))

        found = self._guided(starts, goals, boxed, floor_closed, floor_h,
                             self.quick_expansions if lattice else self.max_expansions,
                             should_stop)
        if found is None and lattice:
            costs = self.lattice_costs(obj, goals, should_stop=should_stop)
            weight = self.inflation

            def closed(ix: int, iy: int, h: int) -> bool:
                return math.isinf(costs[ix, iy, h])

            def heuristic(u: State) -> float:
                return 0.0 if u[0] < 0 else weight * float(costs[u])

            found = self._guided(starts, goals, boxed, closed, heuristic, self.max_expansions,
                                 should_stop)
        if found is None:
            log.debug("walk search gave up after %d expansions", self.max_expansions)
            return []
        return found

    def _guided(self, starts: dict[State, float], goals: dict[State, float],
                boxed: BoxedClearance, closed: Callable[[int, int, int], bool],
                heuristic: Callable[[State], float], cap: int, should_stop: Stop
                ) -> list[State] | None:
        """:meth:`_search`, ``[]`` at once if every start is ``closed``; ``None``: gave up."""
        if all(closed(*s) for s in starts):
            return []
        try:
            return self._search(starts, goals, boxed, closed, heuristic, cap, should_stop)
        except _GiveUp:
            return None

    def _search(self, starts: dict[State, float], goals: dict[State, float],
                boxed: BoxedClearance, closed: Callable[[int, int, int], bool],
                heuristic: Callable[[State], float], cap: int, should_stop: Stop
                ) -> list[State]:
        """Lazy weighted A* over the lattice; ``[]``: no walk; raises ``_GiveUp`` past ``cap``."""
        counter = [0]

        def neighbours(u: State):  # noqa: ANN202 - generator of (state, cost)
            if u == _START:
                yield from starts.items()
                return
            counter[0] += 1
            if counter[0] > cap:
                raise _GiveUp
            if should_stop is not None and counter[0] % 8 == 0 and should_stop():
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
            return boxed.state(v) > 0.0 and boxed.motion_free(u, v)

        try:
            return astar([_START], {_GOAL}, neighbours, heuristic, valid=free)
        finally:
            self.expansions += counter[0]

    def floor_distances(self, obj: Pose, goals: dict[State, float], *,
                        starts: dict[State, float] | None = None,
                        should_stop: Stop = None) -> np.ndarray | FloorWindow:
        """:meth:`.WalkGuides.floor_distances`."""
        return self.guides.floor_distances(obj, goals, starts=starts, should_stop=should_stop)

    def cached_limit(self, obj: Pose, goals: dict[State, float]) -> float | None:
        """:meth:`.WalkGuides.cached_limit`."""
        return self.guides.cached_limit(obj, goals)

    def first_limit(self, starts: dict[State, float], goals: dict[State, float]) -> float:
        """:meth:`.WalkGuides.first_limit`."""
        return self.guides.first_limit(starts, goals)

    def lattice_costs(self, obj: Pose, goals: dict[State, float], *,
                      should_stop: Stop = None) -> np.ndarray:
        """:meth:`.WalkGuides.lattice_costs`."""
        return self.guides.lattice_costs(obj, goals, should_stop=should_stop)

    def attach(self, pose: Pose, obj: Pose, *, leaving: bool) -> dict[State, float]:
        """Lattice states joined to ``pose`` by a certified straight motion, with its cost.

        Those within ``1.5 * resolution`` at the two headings nearest ``pose``'s yaw; from
        ``pose`` when ``leaving``, to it otherwise. ``{}`` when ``pose`` itself collides.
        """
        cl = self.clearance
        d_pose = cl.exact(pose, obj)
        if d_pose <= 0.0:
            return {}
        boxed = cl.with_box(obj)
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
                    cs = boxed.state(s)
                    if cs <= 0.0:
                        continue
                    p = cl.pose(s)
                    a, z = (pose, p) if leaving else (p, pose)
                    da, dz = (d_pose, cs) if leaving else (cs, d_pose)
                    if cl.segment_free(a, z, obj, da=da, db=dz):
                        out[s] = motion_cost(a, z, self.walk)
        return out

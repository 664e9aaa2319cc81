"""The path optimiser: the cheapest path over the waypoints of a found path.

A path is a list of ``(object pose, grasp)`` states; a grasp change happens at one object
pose (two consecutive states with the same pose), with a valid walk
(:meth:`PivotChecker.transit`). Its cost is the planner's one cost model
(:class:`~pivot_ompl.cost.CostModel`): seconds of whole-body execution plus a price per
regrasp (a transfer costs its rotations' seconds, a regrasp its price, its walk and a new
phase).

The optimiser keeps the path's object poses (the *waypoints*, in order) and chooses anew
which of them to pass through and with which grasp: a layered graph whose nodes are
``(waypoint i, grasp g)``, with

* a **transfer** ``(i, g) -> (j, g)`` for every ``j > i`` whose box centre lies within
  ``reach`` of waypoint ``i``'s (:data:`SHORTCUT_REACH`; always ``j = i + 1``): a shortcut
  when ``j > i + 1``, re-steered from scratch, its cost its rotations' seconds; and
* a **regrasp** ``(i, g) -> (i, h)`` (cost :meth:`~pivot_ompl.cost.CostModel.regrasp_seconds`).

Dynamic programming over the waypoints (the graph is acyclic but for the regrasps inside a
layer) gives the cheapest path; edges are checked lazily, only when a cheapest path uses
them, with optimistic costs until then (a transfer's
:meth:`~pivot_ompl.cost.CostModel.transfer_bound`; a walk is at least the straight line); the
transfers
of a candidate path are checked before its walks, which cost more, and the cheap filter of
every transfer of the path (:meth:`PivotChecker.path_free`) runs before any full check, so
one round refutes every shortcut of the path that crosses an obstacle. When every edge
of the cheapest path is checked it is optimal over the waypoints. Until then the best path
of checked edges is kept, so the result is always valid and never costlier than the input:
regrasps that serve nothing disappear, chains of regrasps merge, shortcuts replace detours and
the grasp of each phase is chosen by the cost. The termination condition is polled between
edge checks and passed to them. :func:`optimise_over` does the same over waypoints the path
need not pass (poses offered by another stage, e.g. :mod:`.follow_route`).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator, Found, Status, lazy_search
from pivot_ompl.se2 import Pose, wrap_angle

log = logging.getLogger(__name__)

State = tuple[Pose, int]

#: Longest shortcut (m, straight distance between the box's centres at its ends). Every
#: candidate shortcut of the cheapest optimistic path is refuted or checked one round at a
#: time, so without a reach the rounds grow with the square of the waypoints (all pairs,
#: 4600 rounds over 62 waypoints of a 16-room floor, where no shortcut beyond 7 m passed);
#: a longer straight move is the lattice re-routing's (:mod:`.routes.refine`). The planner's
#: value is ``OptimiserConfig.shortcut_reach``.
SHORTCUT_REACH = 8.0


@dataclass
class OptimiseStats:
    """What one optimisation did.

    Attributes:
        waypoints: distinct object poses of the input path.
        cost_before, cost_after: path cost (s, :class:`~pivot_ompl.cost.CostModel`).
        transfers_checked, walks_checked: edges checked (cache hits included).
        rounds: cheapest-path rounds.
        optimal: the result is the cheapest path over the waypoints (every edge checked).
        seconds: wall-clock time (s).
    """

    waypoints: int = 0
    cost_before: float = 0.0
    cost_after: float = 0.0
    transfers_checked: int = 0
    walks_checked: int = 0
    rounds: int = 0
    optimal: bool = False
    seconds: float = 0.0


@dataclass
class _Graph:
    """The layered graph of waypoints and grasps, with checked and optimistic edge costs."""

    checker: PivotChecker
    poses: list[Pose]
    costs: CostModel
    grasps: tuple[int, ...]
    reach: float = SHORTCUT_REACH
    end_grasp: int | None = None  # the grasp the path must end with (``None``: any)
    start_grasp: int | None = None  # the grasp the path must start with (``None``: any)
    nodes: list[list[int]] = field(default_factory=list)  # valid grasps per waypoint
    #: checked costs: ``None`` = invalid
    transfer: dict[tuple[int, int, int], float | None] = field(default_factory=dict)
    walk: dict[tuple[int, int, int], float | None] = field(default_factory=dict)
    _bounds: dict[tuple[str, int, int, int], float] = field(default_factory=dict)
    #: transfers that passed the cheap filter (not checked in full yet)
    filtered: set[tuple[int, int, int]] = field(default_factory=set)
    _later: dict[int, list[list[int]]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Valid grasps of every waypoint."""
        ck = self.checker
        self.nodes = [[g for g in self.grasps if ck.state_valid(p, g)] for p in self.poses]
        if self.end_grasp is not None:
            self.nodes[-1] = [g for g in self.nodes[-1] if g == self.end_grasp]
        if self.start_grasp is not None:
            self.nodes[0] = [g for g in self.nodes[0] if g == self.start_grasp]
        #: per grasp and waypoint ``i``: the later waypoints (ascending) where the grasp is
        #: valid and that a transfer from ``i`` may reach
        xy = np.array([(p[0], p[1]) for p in self.poses], dtype=float).reshape(-1, 2)
        n = len(xy)
        near = [np.flatnonzero(np.hypot(*(xy[i + 1:] - xy[i]).T) <= self.reach) + i + 1
                for i in range(n)]
        self._later = {g: [[j for j in sorted({*near[i].tolist(), i + 1})
                            if j < n and g in self.nodes[j]] for i in range(n)]
                       for g in self.grasps}

    def link(self, i: int, j: int, g: int) -> None:
        """Let the transfer ``(i, j)`` at ``g`` be tried whatever its length."""
        later = self._later[g][i]
        if j > i and j not in later and g in self.nodes[j]:
            later.append(j)
            later.sort()

    def transfer_bound(self, i: int, j: int, g: int) -> float:
        """Fewest seconds that can move the box from waypoint ``i`` to ``j`` at ``g``."""
        m = self.checker.model
        ca, cb = m.car_pose(self.poses[i], g), m.car_pose(self.poses[j], g)
        return self.costs.transfer_bound(math.hypot(cb[0] - ca[0], cb[1] - ca[1]),
                                         wrap_angle(cb[2] - ca[2]), m.edge_half_length(g),
                                         self.checker.scene.alpha_max)

    def walk_bound(self, i: int, g: int, h: int) -> float:
        """Cheapest conceivable regrasp from ``g`` to ``h`` at waypoint ``i`` (s)."""
        m = self.checker.model
        ra, rb = m.robot_pose(self.poses[i], g), m.robot_pose(self.poses[i], h)
        return self.costs.regrasp_seconds(math.hypot(rb[0] - ra[0], rb[1] - ra[1]))

    def cost(self, kind: str, key: tuple[int, int, int], optimistic: bool) -> float | None:
        """Checked cost of an edge; its bound if unchecked and ``optimistic``, else ``None``."""
        table = self.transfer if kind == "t" else self.walk
        if key in table:
            return table[key]
        if not optimistic:
            return None
        bkey = (kind, *key)
        b = self._bounds.get(bkey)
        if b is None:
            b = self.transfer_bound(*key) if kind == "t" else self.walk_bound(*key)
            self._bounds[bkey] = b
        return b

    def cheapest(self, optimistic: bool) -> tuple[float, list[tuple[int, int]]]:
        """Dynamic programming over the waypoints: ``(cost, nodes)``; ``inf`` if no path."""
        n = len(self.poses)
        checked, bounds = self.transfer, self._bounds
        best: dict[tuple[int, int], float] = {(0, g): 0.0 for g in self.nodes[0]}
        back: dict[tuple[int, int], tuple[int, int] | None] = {k: None for k in best}
        for i in range(n):
            layer = [g for g in self.nodes[i] if (i, g) in best]
            for _ in range(len(self.nodes[i]) - 1):  # regrasps inside the layer
                changed = False
                for g in list(layer):
                    for h in self.nodes[i]:
                        if h == g:
                            continue
                        c = self.cost("w", (i, g, h), optimistic)
                        if c is None:
                            continue
                        v = best[(i, g)] + c
                        if v < best.get((i, h), math.inf) - 1e-12:
                            best[(i, h)] = v
                            back[(i, h)] = (i, g)
                            if h not in layer:
                                layer.append(h)
                            changed = True
                if not changed:
                    break
            for g in layer:  # the transfers, the inner loop of the rounds: kept lean
                b0 = best[(i, g)]
                for j in self._later[g][i]:
                    key = (i, j, g)
                    if key in checked:
                        c = checked[key]
                        if c is None:
                            continue
                    elif not optimistic:
                        continue
                    else:
                        c = bounds.get(("t", i, j, g))
                        if c is None:
                            c = bounds[("t", i, j, g)] = self.transfer_bound(i, j, g)
                    v = b0 + c
                    if v < best.get((j, g), math.inf) - 1e-12:
                        best[(j, g)] = v
                        back[(j, g)] = (i, g)
        ends = [(best[(n - 1, g)], g) for g in self.nodes[n - 1] if (n - 1, g) in best]
        if not ends:
            return math.inf, []
        total, g = min(ends)
        path: list[tuple[int, int]] = []
        node: tuple[int, int] | None = (n - 1, g)
        while node is not None:
            path.append(node)
            node = back[node]
        return total, path[::-1]


def _waypoints(states: list[State]) -> tuple[list[Pose], list[tuple[int, int]]]:
    """Distinct consecutive object poses and the input path as ``(waypoint, grasp)`` nodes."""
    poses: list[Pose] = []
    nodes: list[tuple[int, int]] = []
    for pose, g in states:
        if not poses or pose != poses[-1]:
            poses.append(pose)
        nodes.append((len(poses) - 1, g))
    return poses, nodes


def optimise(checker: PivotChecker, states: list[State], *,
             should_stop: Callable[[], bool], costs: CostModel | None = None,
             grasps: tuple[int, ...] = (0, 1, 2, 3), reach: float = SHORTCUT_REACH,
             stats: OptimiseStats | None = None, start_grasp: int | None = None,
             end_grasp: int | None = None) -> list[State]:
    """The cheapest path over the waypoints of ``states`` found before ``should_stop``.

    Args:
        checker: validity of transfers and walks (its caches make re-checks free).
        states: a valid path of ``(object pose, grasp)`` states.
        should_stop: termination condition, polled between edge checks and passed to
            them (the pivot steering and the walk search poll it too).
        costs: the cost model (default :class:`~pivot_ompl.cost.CostModel`).
        grasps: the grasps the robot may use.
        reach: longest shortcut (m, :data:`SHORTCUT_REACH`); the input's own transfers are
            kept whatever their length.
        stats: filled with what was done, if given.
        start_grasp: the grasp the path starts with (the robot holds the box with it: a
            walk to another is priced); ``None``: any.
        end_grasp: the grasp the path ends with (a part of a longer path, which goes on
            from there); ``None``: any.

    Returns:
        A valid path from the same start pose to the same goal pose, never costlier than
        ``states`` (``states`` itself when nothing better was found).
    """
    if len(states) < 2:
        return list(states)
    poses, given = _waypoints(states)
    return optimise_over(checker, poses, given, should_stop=should_stop, costs=costs,
                         grasps=grasps, reach=reach, stats=stats, start_grasp=start_grasp,
                         end_grasp=end_grasp)


def optimise_over(checker: PivotChecker, poses: list[Pose], path: list[tuple[int, int]], *,
                  should_stop: Callable[[], bool], costs: CostModel | None = None,
                  grasps: tuple[int, ...] = (0, 1, 2, 3), reach: float = SHORTCUT_REACH,
                  stats: OptimiseStats | None = None, start_grasp: int | None = None,
                  end_grasp: int | None = None,
                  links: tuple[tuple[int, int], ...] = ()) -> list[State]:
    """The cheapest path over the waypoints ``poses`` (in order) found before ``should_stop``.

    :func:`optimise` over waypoints the given path need not pass (others to choose from).

    Args:
        checker: as :func:`optimise`'s.
        poses: the waypoints, in order.
        path: a valid path as ``(waypoint index, grasp)`` nodes, indices not decreasing,
            from the first waypoint to the last; its transfers are tried whatever their
            length.
        should_stop: as :func:`optimise`'s.
        costs: as :func:`optimise`'s.
        grasps: as :func:`optimise`'s.
        reach: as :func:`optimise`'s.
        stats: as :func:`optimise`'s.
        start_grasp: as :func:`optimise`'s.
        end_grasp: as :func:`optimise`'s.
        links: more transfers ``(i, j)``, ``i < j``, tried whatever their length.

    Returns:
        A valid path over the waypoints, never costlier than ``path``'s states (those
        states themselves when nothing better was found).
    """
    states = [(poses[i], g) for i, g in path]
    w = costs or CostModel()
    st = stats if stats is not None else OptimiseStats()
    t0 = time.perf_counter()
    st.waypoints = len(poses)
    evaluate = Evaluator(checker, w)
    before = evaluate.path(states).cost
    st.cost_before = st.cost_after = before
    if not math.isfinite(before) or len(poses) < 2:
        return list(states)
    graph = _Graph(checker, poses, w, tuple(sorted(set(grasps) | {g for _, g in states})),
                   reach=reach, end_grasp=end_grasp, start_grasp=start_grasp)
    # the input's own edges are checked (cache hits): the DP over checked edges finds it
    for (i, g), (j, h) in zip(path, path[1:], strict=False):
        if g == h:
            graph.transfer[(i, j, g)] = evaluate.transfer(poses[i], poses[j], g).cost
            graph.link(i, j, g)
        else:
            graph.walk[(i, g, h)] = evaluate.walk(poses[i], g, h).cost
    for i, j in links:
        for g in graph.grasps:
            graph.link(i, j, g)
    _lazy_rounds(graph, evaluate, should_stop, st)
    cost, nodes = graph.cheapest(optimistic=False)
    result = list(states)
    if nodes and cost < before - 1e-9:
        result = [(poses[i], g) for i, g in nodes]
        st.cost_after = cost
    st.seconds = time.perf_counter() - t0
    log.debug("optimiser: cost %.1f -> %.1f over %d waypoints, %d rounds, %d transfers and "
              "%d walks checked, %.3f s%s", before, st.cost_after, st.waypoints, st.rounds,
              st.transfers_checked, st.walks_checked, st.seconds,
              " (optimal)" if st.optimal else "")
    return result


def _lazy_rounds(graph: _Graph, evaluate: Evaluator, stop: Callable[[], bool],
                 st: OptimiseStats) -> None:
    """Cheapest optimistic path, check its unchecked edges, repeat until all are checked."""

    def cheapest() -> Found[list[tuple[int, int]]]:
        st.rounds += 1
        return Found(Status.VALID, graph.cheapest(optimistic=True)[1])

    lazy_search(cheapest, lambda nodes: _check_round(graph, evaluate, nodes, stop, st), stop)


def _check_round(graph: _Graph, evaluate: Evaluator, nodes: list[tuple[int, int]],
                 stop: Callable[[], bool], st: OptimiseStats) -> Status:
    """Check the unchecked edges of the cheapest optimistic path ``nodes``.

    ``VALID`` when every edge was checked already (the path is optimal), ``INVALID`` when
    edges were checked (the next round searches over what they cost), ``STOPPED``.
    """
    poses = graph.poses
    pending = []
    for (i, g), (j, h) in zip(nodes, nodes[1:], strict=False):
        key = (i, j, g) if g == h else (i, g, h)
        table = graph.transfer if g == h else graph.walk
        if key not in table:
            pending.append((g == h, key))
    if not pending:
        st.optimal = True
        return Status.VALID
    # a shortcut whose path crosses an obstacle is refused at once: every one of the
    # path's, before any full check (one round refutes them all)
    refuted = False
    for is_transfer, key in pending:
        if not is_transfer or key in graph.filtered:
            continue
        i, j, g = key
        if graph.checker.path_free(poses[i], poses[j], g):
            graph.filtered.add(key)
        else:
            st.transfers_checked += 1
            graph.transfer[key] = None
            refuted = True
    if refuted:
        return Status.INVALID
    # the transfers (cheaper) first: a walk is computed only when every transfer of the
    # candidate path holds, as in the search (measured: the optimiser's time -43 %)
    pending.sort(key=lambda e: not e[0])
    for is_transfer, key in pending:
        if stop():
            return Status.STOPPED
        if is_transfer:
            i, j, g = key
            st.transfers_checked += 1
            e = evaluate.transfer(poses[i], poses[j], g, should_stop=stop)
            table = graph.transfer
        else:
            i, g, h = key
            st.walks_checked += 1
            e = evaluate.walk(poses[i], g, h, should_stop=stop)
            table = graph.walk
        if e.status is Status.STOPPED:
            return e.status
        table[key] = e.cost if e.valid else None
        if not e.valid:
            break  # the path is broken: find the next cheapest
    return Status.INVALID

"""Rooms and passages first: the regrasps a plan needs, read from the lattice's components.

Where start and goal lie in different connected components of the held assembly's lattice
(:mod:`.lattice`) at every grasp, each plan regrasps; on a large cluttered floor (an office's
SLAM map) the places where it can are a few box poses at the mouth of a corridor, which
random samples of the object roadmap seldom hit. The lattice knows them: a box pose that
two components hold, one at each of two grasps (or the two sides of one grasp parity), is a
place where the robot may let go of the box at one grasp and take it at the other.

:func:`component_steps` bins every lattice state's *box* pose (position to ``cell`` m, yaw
modulo pi to ``yaw_bins``), joins the components met in one bin, and finds the fewest
component changes from the start's components to the goal's (a breadth-first search): the
coarse plan over rooms and passages. :func:`regrasp_lattice_path` then refines it: per leg
the lattice route at one grasp to a box pose of the next meeting bin, made real by certified
transfers (:func:`~.chain.shortened`), then the regrasp's walk certified there
(:meth:`~pivot_ompl.planners.evaluation.Evaluator.walk`), trying a few poses per meeting.
Every motion of the path returned passed its full check; nothing is assumed from the bins.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Evaluator, Found, Status
from pivot_ompl.planners.objects.roadmap import half_turn
from pivot_ompl.planners.routes.chain import corners, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.lattice import HEADING_YAWS, N_HEADINGS

Stop = Callable[[], bool]
State = tuple[Pose, int]
#: A component: ``(parity, label)``.
Component = tuple[int, int]


@dataclass
class ComponentSteps:
    """The fewest component changes from start to goal, and where each may happen.

    Attributes:
        components: the components in order, the start's first and the goal's last.
        meetings: per change, the box poses (exact lattice states' poses, of the component
            left) in the bins both components hold: one of each bin first, then the others.
        bins: per change, its number of bins (the first poses of its meeting).
    """

    components: list[Component] = field(default_factory=list)
    meetings: list[list[Pose]] = field(default_factory=list)
    bins: list[int] = field(default_factory=list)


def _box_poses(lattice: TransferLattice, parity: int, should_stop: Stop | None
               ) -> tuple[np.ndarray, np.ndarray]:
    """Every free lattice state's box pose at grasp ``parity`` (``(n, 3)``) and its component.

    In the scene (the lattice's frame turned out: :attr:`~.lattice.TransferLattice.frame`).
    """
    f, m = lattice.field, lattice.checker.model
    cell_ids, labels = lattice.components(parity, should_stop)
    cells = np.flatnonzero(cell_ids >= 0)  # cell id i is cells[i]
    ix, iy = np.divmod(cells, f.ny)
    x0, y0 = f.position(0, 0)
    cx, cy = x0 + ix * lattice.resolution, y0 + iy * lattice.resolution
    r = m.half_extent(parity)
    turn = m.object_from_car((0.0, 0.0, 0.0), parity)[2]  # box yaw at car heading 0
    lab = labels.reshape(-1, N_HEADINGS)
    poses, comps = [], []
    for h in range(N_HEADINGS):
        ok = lab[:, h] >= 0
        yaw = HEADING_YAWS[h]
        poses.append(np.column_stack([cx[ok] + r * math.cos(yaw), cy[ok] + r * math.sin(yaw),
                                      np.full(int(ok.sum()), wrap_angle(yaw + turn))]))
        comps.append(lab[ok, h])
    return lattice.frame.poses_out(np.concatenate(poses)), np.concatenate(comps)


def _meeting(bin_keys: np.ndarray, components: np.ndarray) -> dict[int, dict[int, None]]:
    """The components meeting each one, in the order of the first bin they share.

    ``bin_keys`` (non-decreasing) and ``components``: one row per component a bin holds, each
    bin's in ascending order. The pairs ``(a, b)`` are met bin by bin, ``a`` then ``b`` in
    the bin's order; each pair is kept where first met.
    """
    n = len(bin_keys)
    if n == 0:
        return {}
    starts = np.flatnonzero(np.diff(bin_keys, prepend=bin_keys[0] - 1) != 0)
    sizes = np.diff(np.append(starts, n))
    size_of, start_of = np.repeat(sizes, sizes), np.repeat(starts, sizes)  # per row
    a_rows = np.repeat(np.arange(n), size_of)
    b_rows = np.arange(len(a_rows)) - np.repeat(np.cumsum(size_of) - size_of, size_of) \
        + np.repeat(start_of, size_of)
    other = a_rows != b_rows
    a, b = components[a_rows[other]], components[b_rows[other]]
    _, first = np.unique(a * (int(components.max()) + 1) + b, return_index=True)
    adjacent: dict[int, dict[int, None]] = {}
    for i in np.sort(first).tolist():
        adjacent.setdefault(int(a[i]), {}).setdefault(int(b[i]))
    return adjacent


def component_steps(lattice: TransferLattice, start: Pose, goal: Pose, *,
                    start_grasps: list[int], goal_grasps: list[int], cell: float,
                    yaw_bins: int, max_changes: int, should_stop: Stop | None = None
                    ) -> ComponentSteps | None:
    """The coarse plan over the lattice's components (module docstring); ``None``: none.

    ``None`` also when it needs more than ``max_changes`` changes, or none (one grasp
    suffices: the regrasp-free tries' case).

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    x0, y0, x1, y1 = lattice.checker.world.bounds
    nby = int((y1 - y0) / cell) + 2
    keys, comps, poses = [], [], []
    for parity in (0, 1):
        p, labels = _box_poses(lattice, parity, should_stop)
        bx = np.floor((p[:, 0] - x0) / cell).astype(np.int64)
        by = np.floor((p[:, 1] - y0) / cell).astype(np.int64)
        yb = np.floor(np.mod(p[:, 2], math.pi) / math.pi * yaw_bins).astype(np.int64) % yaw_bins
        keys.append((bx * nby + by) * yaw_bins + yb)
        comps.append(labels.astype(np.int64) * 2 + parity)
        poses.append(p)
    key, comp, pose = np.concatenate(keys), np.concatenate(comps), np.concatenate(poses)
    order = np.lexsort((comp, key))
    key, comp = key[order], comp[order]  # the poses read through order, where wanted
    # the bins holding two components or more
    pair_starts = np.flatnonzero((np.diff(key, prepend=-1) != 0) | (np.diff(comp, prepend=-1) != 0))
    bins, count = np.unique(key[pair_starts], return_counts=True)
    shared = bins[count > 1]
    sel = np.flatnonzero(np.isin(key, shared))  # rows in shared bins, by (bin, component)
    pairs = sel[(np.diff(key[sel], prepend=-1) != 0) | (np.diff(comp[sel], prepend=-1) != 0)]
    adjacent = _meeting(key[pairs], comp[pairs])

    def code(c: Component) -> int:
        return c[1] * 2 + c[0]

    ends = [{code((g % 2, lab)) for g in grasps
             for lab in lattice.joined_components(q, g, should_stop)}
            for q, grasps in ((start, start_grasps), (goal, goal_grasps))]
    if ends[0] & ends[1] or not ends[0] or not ends[1]:
        return None
    back: dict[int, int] = {c: -1 for c in ends[0]}
    todo = deque((c, 0) for c in ends[0])
    reached = -1
    while todo and reached < 0:
        c, depth = todo.popleft()
        if depth >= max_changes:
            continue
        for d in adjacent.get(c, {}):
            if d not in back:
                back[d] = c
                if d in ends[1]:
                    reached = d
                    break
                todo.append((d, depth + 1))
    if reached < 0:
        return None
    chain = [reached]
    while back[chain[-1]] >= 0:
        chain.append(back[chain[-1]])
    chain.reverse()
    steps = ComponentSteps([(c % 2, c // 2) for c in chain])
    for a, b in zip(chain, chain[1:], strict=False):
        both = np.intersect1d(key[pairs[comp[pairs] == a]], key[pairs[comp[pairs] == b]])
        rows = sel[(comp[sel] == a) & np.isin(key[sel], both)]  # a's, ascending
        first = np.ones(len(rows), dtype=bool)  # the first of each bin
        first[1:] = key[rows[1:]] != key[rows[:-1]]
        steps.meetings.append([(float(q[0]), float(q[1]), float(q[2]))
                               for q in pose[order[np.concatenate([rows[first], rows[~first]])]]])
        steps.bins.append(int(first.sum()))
    return steps


def meeting_places(steps: ComponentSteps) -> tuple[tuple[float, float], ...]:
    """The positions (m) of every change's first poses, one of each bin it may happen in."""
    return tuple((q[0], q[1]) for meeting, n in zip(steps.meetings, steps.bins, strict=True)
                 for q in meeting[:n])


@dataclass
class RegraspLatticeStats:
    """Figures of the try.

    Attributes:
        changes: component changes of the coarse plan (``-1``: none found).
        legs: legs made real.
        walks: regrasp walks checked.
    """

    changes: int = -1
    legs: int = 0
    walks: int = 0


def regrasp_lattice_path(checker: PivotChecker, lattice: TransferLattice, costs: CostModel,
                         start: Pose, goal: Pose, *, start_grasps: list[int],
                         goal_grasps: list[int], grasps: tuple[int, ...], run_spacing: int,
                         max_changes: int = 4, tries: int = 6, cell: float = 0.2,
                         yaw_bins: int = 8, weight: float = 1.0, should_stop: Stop,
                         stats: RegraspLatticeStats | None = None,
                         on_steps: Callable[[ComponentSteps], None] | None = None
                         ) -> Found[list[State]]:
    """A certified path regrasping where the lattice's components meet (module docstring).

    ``start_grasps``, ``goal_grasps``: the grasps valid (and allowed) at the ends; ``grasps``:
    those the robot may use. ``tries``: meeting poses tried per change (nearest the leg's
    start and the goal first, one per bin before a second of one). ``weight``: the lattice
    routes' heuristic inflation (the search passes its lattice's, the re-routing's
    (:mod:`.refine`): a leg's route is then searched once, not again by the re-routing); a
    leg whose route at ``weight`` fails its checks is routed again at weight 1.
    ``on_steps``: told the coarse plan (:func:`component_steps`) as soon as it is found,
    before its legs are made real (a plan's prover refines its bound there first).
    ``VALID`` with the states (a regrasp: two states at one pose), ``INVALID``, ``STOPPED``.
    """
    stats = stats if stats is not None else RegraspLatticeStats()
    if should_stop():  # the bins cost about a second on a large floor: not when stopped
        return Found(Status.STOPPED)
    try:
        steps = component_steps(lattice, start, goal, start_grasps=start_grasps,
                                goal_grasps=goal_grasps, cell=cell, yaw_bins=yaw_bins,
                                max_changes=max_changes, should_stop=should_stop)
        if steps is None:
            return Found(Status.INVALID)
        stats.changes = len(steps.meetings)
        if on_steps is not None:
            on_steps(steps)
        evaluate = Evaluator(checker, costs)
        legs = _Legs(evaluate, lattice, run_spacing, weight, should_stop)
        return _legs(legs, steps, start, goal, start_grasps, goal_grasps, grasps, tries, stats)
    except Interrupted:
        return Found(Status.STOPPED)


@dataclass
class _Legs:
    """How a leg is made real: the lattice route at one grasp, then certified transfers."""

    evaluate: Evaluator
    lattice: TransferLattice
    run_spacing: int
    weight: float
    should_stop: Stop

    def leg(self, a: Pose, b: Pose, grasp: int) -> Found[list[State]]:
        """The lattice route from ``a`` to ``b`` at ``grasp``, made real.

        At :attr:`weight`, then, where that route's chain fails, at the cheapest routes'
        weight 1.
        """
        found: Found[list[State]] = Found(Status.INVALID)
        for weight in dict.fromkeys((self.weight, 1.0)):
            found = self._leg(a, b, grasp, weight)
            if found.status is not Status.INVALID:
                break
        return found

    def _leg(self, a: Pose, b: Pose, grasp: int, weight: float) -> Found[list[State]]:
        poses, cost = self.lattice.route(a, b, grasp, should_stop=self.should_stop,
                                         weight=weight)
        if len(poses) < 2 or not math.isfinite(cost):
            return Found(Status.INVALID)
        found = shortened(self.evaluate, corners(poses, spacing=self.run_spacing), grasp,
                          self.should_stop)
        if found.path is None:
            return Found(found.status)
        return Found(Status.VALID, [(q, grasp) for q in found.path[0]])


def _legs(legs: _Legs, steps: ComponentSteps, start: Pose, goal: Pose, start_grasps: list[int],
          goal_grasps: list[int], grasps: tuple[int, ...], tries: int,
          stats: RegraspLatticeStats) -> Found[list[State]]:
    """Each leg and regrasp in turn, greedily (the first meeting pose that passes)."""
    evaluate, lattice, should_stop = legs.evaluate, legs.lattice, legs.should_stop
    ck = evaluate.checker
    here, held = start, [g for g in start_grasps if g % 2 == steps.components[0][0]]
    states: list[State] = []
    for i, meeting in enumerate(steps.meetings):
        parity, label = steps.components[i + 1]
        nxt = [g for g in grasps if g % 2 == parity]
        n = steps.bins[i]  # one pose per bin first, nearest the leg's start and goal first
        meeting = sorted(meeting[:n], key=lambda q: math.dist(q[:2], here[:2])
                         + math.dist(q[:2], goal[:2])) + meeting[n:]
        found = None
        for q, g in ((q, g) for q in meeting[:tries] for g in held):
            if should_stop():
                return Found(Status.STOPPED)
            t = q if g < 2 else half_turn(q)  # the meeting's state at grasp g
            if not ck.state_valid(t, g):
                continue
            # the grasps the regrasp may take there, known before the leg is routed: a
            # meeting pose none of them joins to the next component costs no leg
            takes = [g2 for g2 in nxt if ck.state_valid(t, g2)
                     and label in lattice.joined_components(t, g2, should_stop)]
            if not takes:
                continue
            leg = legs.leg(here, t, g)
            if leg.status is Status.STOPPED:
                return Found(Status.STOPPED)
            if leg.path is None:
                continue
            for g2 in takes:
                stats.walks += 1
                if evaluate.walk(t, g, g2, should_stop=should_stop).valid:
                    found = (leg.path, t, g2)
                    break
            if found is not None:
                break
        if found is None:
            return Found(Status.INVALID)
        states += found[0]
        stats.legs += 1
        here, held = found[1], [found[2]]
    for g in held:
        if g not in goal_grasps:
            continue
        leg = legs.leg(here, goal, g)
        if leg.status is Status.STOPPED:
            return Found(Status.STOPPED)
        if leg.path is not None:
            stats.legs += 1
            return Found(Status.VALID, states + leg.path)
    return Found(Status.INVALID)

"""Each transfer phase of a path re-routed along the lattice's cheapest route, when cheaper.

A phase (consecutive states of one grasp, from one regrasp or end to the next) found by the
multiplexed search follows the roadmap's few nodes. :func:`refine_phases` plans the phase
again on the held assembly's lattice (:class:`~.lattice.TransferLattice`: pushes, pulls and
turns in place, the cheapest route the lattice knows), then shortens that route: the
cheapest chain of certified transfers between its poses (each pose joined to the poses 1, 2,
4, ... further on and to the end), found lazily. The phase keeps
the cheaper of the two (seconds, :class:`~pivot_ompl.cost.CostModel`); a route that the exact
checks refuse somewhere leaves the phase as it was. The path's regrasps and grasps are kept:
its structure is the search's; the optimiser afterwards may still change it.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.se2 import Pose, wrap_angle

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]


@dataclass
class RefineStats:
    """What :func:`refine_phases` did.

    Attributes:
        phases: transfer phases looked at.
        rerouted: phases replaced by a cheaper lattice route.
        seconds_saved: cost saved (s).
    """

    phases: int = 0
    rerouted: int = 0
    seconds_saved: float = 0.0


def refine_phases(checker: PivotChecker, lattice: TransferLattice, states: list[State], *,
                  costs: CostModel, should_stop: Stop,
                  stats: RefineStats | None = None) -> list[State]:
    """``states`` with each transfer phase re-routed where the lattice's route is cheaper.

    Stopped by ``should_stop`` (polled between checks), it returns what it has so far: a
    valid path, never costlier than ``states``.
    """
    st = stats if stats is not None else RefineStats()
    out: list[State] = []
    i, n = 0, len(states)
    while i < n:
        j = i
        while j + 1 < n and states[j + 1][1] == states[i][1]:
            j += 1
        phase = states[i:j + 1]
        if j > i and not should_stop():
            st.phases += 1
            try:
                phase = _rerouted(checker, lattice, phase, costs, should_stop, st)
            except Interrupted:
                pass
        out.extend(phase if not out or out[-1] != phase[0] else phase[1:])
        i = j + 1
    return out


def _seconds(checker: PivotChecker, poses: list[Pose], grasp: int, costs: CostModel) -> float:
    total = 0.0
    for a, b in zip(poses, poses[1:], strict=False):
        e = checker.transfer(a, b, grasp)
        if not e.valid:
            return math.inf
        total += costs.rotations(r.angle for r in e.sequence.rotations)
    return total


def _rerouted(checker: PivotChecker, lattice: TransferLattice, phase: list[State],
              costs: CostModel, should_stop: Stop, st: RefineStats) -> list[State]:
    grasp = phase[0][1]
    poses = [q for q, _ in phase]
    before = _seconds(checker, poses, grasp, costs)
    route = _corners(lattice.route(poses[0], poses[-1], grasp, should_stop=should_stop))
    if len(route) < 2:
        return phase
    short, seconds = _shortened(checker, route, grasp, costs, should_stop)
    if short and seconds < before - 1e-9:
        st.rerouted += 1
        st.seconds_saved += before - seconds
        log.debug("phase at grasp %d re-routed: %.0f -> %.0f s", grasp, before, seconds)
        return [(q, grasp) for q in short]
    return phase


#: Along a straight run of the route, a pose is kept every this many lattice motions.
RUN_SPACING = 6


def _corners(route: list[Pose]) -> list[Pose]:
    """The route's poses worth joining by transfers.

    Its ends, the poses where it starts or stops turning, and every :data:`RUN_SPACING` th
    pose of a long straight run.
    """
    if len(route) < 3:
        return route
    keep = [0]
    for k in range(1, len(route) - 1):
        a, b, c = route[k - 1], route[k], route[k + 1]
        turning_in = abs(b[2] - a[2]) > 1e-9
        turning_out = abs(c[2] - b[2]) > 1e-9
        if turning_in != turning_out or k - keep[-1] >= RUN_SPACING:
            keep.append(k)
    keep.append(len(route) - 1)
    return [route[k] for k in keep]


def _shortened(checker: PivotChecker, route: list[Pose], grasp: int, costs: CostModel,
               should_stop: Stop) -> tuple[list[Pose], float]:
    """The cheapest chain of certified transfers along the route; ``([], inf)`` if none.

    Candidate transfers join route pose ``i`` to ``i + 1, i + 2, i + 4, ...`` and to the
    end. Lazily: the cheapest chain by estimated costs (a transfer's reference path length
    at the push rate, :meth:`~pivot_ompl.cost.CostModel.transfer_estimate`, until it is
    checked), its unchecked transfers checked (the cheap test first), again until every
    transfer of it is checked.
    """
    n = len(route)
    m, alpha = checker.model, checker.scene.alpha_max
    ell = m.edge_half_length(grasp)
    cars = [m.car_pose(q, grasp) for q in route]
    ends = {i: sorted({min(n - 1, i + (1 << k)) for k in range(n.bit_length() + 1)} - {i})
            for i in range(n - 1)}
    checked: dict[tuple[int, int], float] = {}

    paths = checker.steering.paths

    def bound(i: int, j: int) -> float:
        a, b = cars[i], cars[j]
        if paths.is_spin(a, b):
            return costs.spin_estimate(wrap_angle(b[2] - a[2]), alpha)
        return costs.transfer_estimate(paths.distance(a, b), ell, alpha)

    while True:
        best = [math.inf] * n
        back = [-1] * n
        best[0] = 0.0
        for i in range(n - 1):  # a DAG: the route's order
            if not math.isfinite(best[i]):
                continue
            for j in ends[i]:
                c = checked.get((i, j))
                v = best[i] + (bound(i, j) if c is None else c)
                if v < best[j]:
                    best[j], back[j] = v, i
        if not math.isfinite(best[-1]):
            return [], math.inf
        chain = [n - 1]
        while chain[-1] != 0:
            chain.append(back[chain[-1]])
        chain.reverse()
        pending = [(i, j) for i, j in zip(chain, chain[1:], strict=False)
                   if (i, j) not in checked]
        if not pending:
            return [route[i] for i in chain], best[-1]
        for i, j in pending:
            if should_stop():
                raise Interrupted("route refinement")
            c = math.inf
            if j == i + 1 or checker.path_free(route[i], route[j], grasp):
                e = checker.transfer(route[i], route[j], grasp, should_stop=should_stop)
                if e.valid:
                    c = costs.rotations(r.angle for r in e.sequence.rotations)
                elif should_stop():
                    raise Interrupted("route refinement")
            checked[(i, j)] = c
            if not math.isfinite(c):
                break

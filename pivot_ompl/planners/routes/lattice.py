"""The held assembly's state lattice: straight pushes and pulls, and turns in place.

States are ``(ix, iy, h)``: a car position on the floor grid (spacing ``resolution``) and one
of the 16 lattice headings (:data:`~pivot_ompl.transit.lattice.HEADING_VECTORS`), at one
grasp. Motions from heading ``h``: one grid vector along ``h`` forward (a push) or backward
(a pull), keeping the heading; and a turn in place to the next heading either way (the car
spins about its position, :class:`~pivot_ompl.pivoting.curves.CarPaths`). Every motion is a
path the pivot steering converts exactly. A state is free where the assembly fits
(:class:`~pivot_ompl.validity.assembly_field.AssemblyField`, a turn also at its half-way
yaw). Costs are seconds (:class:`~pivot_ompl.cost.CostModel`): a push of ``d`` m costs
``d`` times the grasp's push rate, a turn of ``a`` rad ``a`` times the spin rate.

:meth:`TransferLattice.route` is A* between two exact object poses at one grasp (joined to
the nearby lattice states by short paths), guided by the straight distance at the push rate
(admissible); it gives the lattice's cheapest route, a guide whose motions the pivot
checker still certifies.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.lattice import HEADING_VECTORS, HEADING_YAWS, N_HEADINGS
from pivot_ompl.validity.assembly_field import AssemblyField

State = tuple[int, int, int]
_START: State = (-1, -1, -1)
_GOAL: State = (-2, -2, -2)


class TransferLattice:
    """Routes of the held assembly over the lattice (see the module docstring).

    Args:
        checker: the scene's model and world.
        costs: the cost model (seconds).
        resolution: grid spacing (m).
        max_expansions: states expanded before a query gives up.
    """

    def __init__(self, checker: PivotChecker, costs: CostModel, *, resolution: float = 0.1,
                 max_expansions: int = 200_000) -> None:
        """A lattice over the checker's floor."""
        self.checker, self.costs = checker, costs
        self.resolution, self.max_expansions = resolution, max_expansions
        self.field = AssemblyField(checker.model, checker.world, resolution)
        alpha = checker.scene.alpha_max
        m = checker.model
        self._push = {g: costs.push_rate(m.edge_half_length(g), alpha) for g in range(4)}
        d = costs.durations
        #: seconds per radian turned in place: three rotations per ``2 alpha`` of turn
        self._spin = d.per_pivot * 3.0 / (2.0 * alpha) + d.per_radian
        self._steps = [resolution * math.hypot(*v) for v in HEADING_VECTORS]
        self._turns = [abs(wrap_angle(HEADING_YAWS[(h + 1) % N_HEADINGS] - HEADING_YAWS[h]))
                       for h in range(N_HEADINGS)]
        self.expansions = 0

    def car(self, s: State) -> Pose:
        """The car pose of lattice state ``s``."""
        x, y = self.field.position(s[0], s[1])
        return (x, y, HEADING_YAWS[s[2]])

    def route(self, start: Pose, goal: Pose, grasp: int, *,
              should_stop: Callable[[], bool] | None = None) -> list[Pose]:
        """Object poses of the cheapest lattice route from ``start`` to ``goal`` at ``grasp``.

        Ends exact (the given poses); ``[]`` when the lattice has no route.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        m = self.checker.model
        ca, cb = m.car_pose(start, grasp), m.car_pose(goal, grasp)
        parity = grasp % 2
        starts = self._attach(ca, parity, grasp)
        goals = self._attach(cb, parity, grasp)
        if not starts or not goals:
            return []
        rate = self._push[grasp]
        fits = self.field.fits
        nx, ny = self.field.nx, self.field.ny
        steps, turns, spin = self._steps, self._turns, self._spin
        counter = [0]

        def free(ix: int, iy: int, k: int) -> bool:
            return 0 <= ix < nx and 0 <= iy < ny and bool(fits(parity, k)[ix, iy])

        def neighbours(u: State) -> Iterator[tuple[State, float]]:
            if u == _START:
                yield from starts.items()
                return
            counter[0] += 1
            if counter[0] > self.max_expansions:
                return
            if counter[0] % 256 == 0 and should_stop is not None and should_stop():
                raise Interrupted("transfer lattice")
            ix, iy, h = u
            vx, vy = HEADING_VECTORS[h]
            for sgn in (1, -1):
                jx, jy = ix + sgn * vx, iy + sgn * vy
                if free(jx, jy, 2 * h):
                    yield (jx, jy, h), steps[h] * rate
            if free(ix, iy, 2 * h + 1) and free(ix, iy, 2 * ((h + 1) % N_HEADINGS)):
                yield (ix, iy, (h + 1) % N_HEADINGS), turns[h] * spin
            hb = (h - 1) % N_HEADINGS
            if free(ix, iy, 2 * hb + 1) and free(ix, iy, 2 * hb):
                yield (ix, iy, hb), turns[hb] * spin
            c = goals.get(u)
            if c is not None:
                yield _GOAL, c

        gx, gy = cb[0], cb[1]

        def heuristic(u: State) -> float:
            if u[0] < 0:
                return 0.0
            x, y = self.field.position(u[0], u[1])
            return rate * math.hypot(x - gx, y - gy)

        try:
            states = astar([_START], {_GOAL}, neighbours, heuristic)
        finally:
            self.expansions += counter[0]
        if not states:
            return []
        return [start] + [m.object_from_car(self.car(s), grasp) for s in states[1:-1]] + [goal]

    def _attach(self, car: Pose, parity: int, grasp: int) -> dict[State, float]:
        """Free lattice states near ``car`` (the two nearest headings), with a cost guess."""
        fx, fy = self.field.cell(car[0], car[1])
        near = sorted(range(N_HEADINGS),
                      key=lambda h: abs(wrap_angle(HEADING_YAWS[h] - car[2])))[:2]
        out: dict[State, float] = {}
        for ix in range(math.floor(fx - 1.5), math.ceil(fx + 1.5) + 1):
            for iy in range(math.floor(fy - 1.5), math.ceil(fy + 1.5) + 1):
                if math.hypot(ix - fx, iy - fy) > 1.5:
                    continue
                for h in near:
                    if not self.field.state_fits(ix, iy, 2 * h, parity):
                        continue
                    x, y = self.field.position(ix, iy)
                    d = math.hypot(x - car[0], y - car[1])
                    out[(ix, iy, h)] = d * self._push[grasp] + \
                        abs(wrap_angle(HEADING_YAWS[h] - car[2])) * self._spin
        return out

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
the nearby lattice states by short paths; asked with ``leads``, an end between two headings
only where the lattice could turn across its heading, maybe after a straight push along it:
:mod:`.lattice_ends`), guided by the straight distance at the push rate
plus the heading still to turn at the spin rate (admissible: pushes do not turn, turns do
not move the car), inflated by ``weight``; a push beside a wall is priced higher in the
search (:data:`~.lattice_search.TIGHT_PUSH`): a guide the pivot checker certifies. A query
whose ends lie in different connected components of the lattice (computed once per grasp
parity, scipy) has no route and costs nothing.

The grid and its headings lie in the scene's walls' frame (:mod:`.lattice_frame`), so that a
turned copy of a scene gets the original's lattice; poses and routes are the scene's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from shapely.geometry.base import BaseGeometry

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.routes.guide import graph_distances, move_graph
from pivot_ompl.planners.routes.lattice_components import lattice_labels, turn_room
from pivot_ompl.planners.routes.lattice_ends import end_joins
from pivot_ompl.planners.routes.lattice_frame import LatticeFrame, lattice_frame
from pivot_ompl.planners.routes.lattice_region import within_distance
from pivot_ompl.planners.routes.lattice_search import TIGHT_PUSH, lattice_astar, route_cost
from pivot_ompl.planners.routes.lattice_spacing import MAX_CELLS as MAX_CELLS
from pivot_ompl.planners.routes.lattice_spacing import lattice_spacing
from pivot_ompl.planners.routes.shared_fields import (
    ROUTES_KEPT,
    assembly_field,
    shared_components,
    shared_routes,
)
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
        resolution: grid spacing (m); coarser on floors of more than :data:`MAX_CELLS`
            grid positions (:func:`~.lattice_spacing.lattice_spacing`: the spacing that
            gives that many, or a whole multiple of an occupancy map's cell below it).
        max_expansions: states expanded before a query gives up.
        weight: inflation of the A* heuristic (a route costs at most this factor more than
            the lattice's cheapest).
        region: the box centres a plan may visit (e.g.
            :meth:`~pivot_ompl.planners.objects.samplers.PoseSampler.region`), or ``None``
            for the whole floor: the lattice then holds only the car positions within the
            box's half extent (and one cell) of it. Routes are complete at the lattice's
            resolution over those states; the rest of the bounds' rectangle (e.g. the open
            corners round a turned building, which grow with the square of its length)
            costs nothing.
        turned: lay the lattice in the walls' frame (:mod:`.lattice_frame`); ``False``: in
            the scene's own frame whatever its walls' direction.

    Attributes:
        frame: where the lattice lies (its grid, :attr:`field` and headings): the scene's
            walls' frame, or its own (:meth:`~.lattice_frame.LatticeFrame.car_in`). Routes,
            poses and ``region`` are the scene's.
    """

    def __init__(self, checker: PivotChecker, costs: CostModel, *, resolution: float = 0.1,
                 max_expansions: int = 200_000, weight: float = 1.0,
                 region: BaseGeometry | None = None, turned: bool = True) -> None:
        """A lattice over the checker's floor (within reach of ``region``)."""
        self.checker, self.costs = checker, costs
        self.region = region
        self._mask: np.ndarray | None = None
        self.frame = lattice_frame(checker, resolution=resolution) if turned else LatticeFrame()
        world = checker.world if self.frame.world is None else self.frame.world
        resolution = lattice_spacing(world, resolution)
        self.resolution, self.max_expansions, self.weight = resolution, max_expansions, weight
        # the scene's field, shared with its later plans; within a region, paying for the
        # pieces round the region alone
        self.field = assembly_field(checker, resolution, region=region, area=self._mask_over,
                                    frame=self.frame)
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
        #: routes by (start, goal, grasp, weight)
        self._routes: dict[tuple[Pose, Pose, int, float, bool], tuple[list[Pose], float]] = \
            shared_routes(self.field, region, (*self._push.values(), self._spin, TIGHT_PUSH,
                                               max_expansions))
        self._asked: set[tuple[Pose, Pose, int, float, bool]] = set()  # by this lattice
        self._labels: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._floors: dict[int, Any] = {}
        #: the last floor distances per parity, by the goal joins' cells they were asked for
        #: (a route and its :meth:`way_bound` ask the same)
        self._ways: dict[int, tuple[frozenset[int], np.ndarray]] = {}
        self._grids: dict[tuple[int, int], bytes] = {}
        self._rooms: dict[tuple[int, int], np.ndarray] = {}
        #: routes made real (:func:`~.chain.made_real`'s ``cache``), shared by the callers
        self.chains: dict[tuple, tuple[list[Pose], float] | None] = {}

    def car(self, s: State) -> Pose:
        """The car pose of lattice state ``s`` (in the scene)."""
        x, y = self.field.position(s[0], s[1])
        return self.frame.car_out((x, y, HEADING_YAWS[s[2]]))

    def route(self, start: Pose, goal: Pose, grasp: int, *,
              should_stop: Callable[[], bool] | None = None,
              weight: float | None = None, leads: bool = False) -> tuple[list[Pose], float]:
        """The cheapest lattice route from ``start`` to ``goal`` at ``grasp``, and its cost.

        Object poses, the ends exact (the given poses), and the lattice's seconds; ``([],
        inf)`` when the lattice has no route. Routes are kept (asked again, they are free).
        The heuristic's distance is the floor's way to the goal where longer than the straight
        line (:meth:`_floor_distances`): far fewer states expanded across rooms and passages.
        ``weight``: the heuristic's inflation for this query (default: the lattice's).
        ``leads``: an end between two headings joins only states that can turn across it,
        maybe through a straight push along it (:func:`.end_joins`); the default joins the
        near states.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        weight = self.weight if weight is None else weight
        key = (start, goal, grasp, weight, leads)
        hit = self._routes.get(key)
        if key not in self._asked and should_stop is not None and should_stop():
            raise Interrupted("lattice route")  # as when searched: another plan's is not free
        self._asked.add(key)
        if hit is None:
            hit = self._route(start, goal, grasp, should_stop, weight, leads)
            if len(self._routes) >= ROUTES_KEPT:
                self._routes.clear()
            self._routes[key] = hit
        return hit

    def way_bound(self, start: Pose, goal: Pose, grasp: int, *,
                  should_stop: Callable[[], bool] | None = None) -> float:
        """The pushes' cost (s) along the floor's way from ``start`` to ``goal`` at ``grasp``.

        The grid distance over positions free at some heading (:meth:`_floor_distances`)
        at the push rate: no lattice route costs less, and one that costs much more is a
        detour the lattice takes because it turns only in place; ``inf`` where no way joins
        them.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        m, parity, f, car_in = self.checker.model, grasp % 2, self.field, self.frame.car_in
        starts = self._attach(car_in(m.car_pose(start, grasp)), parity, grasp, should_stop)
        goals = self._attach(car_in(m.car_pose(goal, grasp)), parity, grasp, should_stop)
        if not starts or not goals:
            return math.inf
        cell_ids, _ = self._components(parity, should_stop)
        way = self._floor_distances(parity, goals, should_stop)
        d = min(float(way[cell_ids[u[0] * f.ny + u[1]]]) for u in starts)
        return self._push[grasp] * d

    def lower_bound(self, start: Pose, goal: Pose, grasp: int) -> float:
        """A cost no lattice route from ``start`` to ``goal`` at ``grasp`` is below (s).

        The straight distance between the two cars at the push rate plus the heading between
        them at the spin rate: every route's joins and pushes move its car that far, and its
        joins and turns turn it that much. No search, no field.
        """
        m = self.checker.model
        ca, cb = m.car_pose(start, grasp), m.car_pose(goal, grasp)
        return (self._push[grasp] * math.hypot(cb[0] - ca[0], cb[1] - ca[1])
                + self._spin * abs(wrap_angle(cb[2] - ca[2])))

    def _route(self, start: Pose, goal: Pose, grasp: int,
               should_stop: Callable[[], bool] | None,
               weight: float, leads: bool) -> tuple[list[Pose], float]:
        m, car_in = self.checker.model, self.frame.car_in
        ca, cb = car_in(m.car_pose(start, grasp)), car_in(m.car_pose(goal, grasp))
        parity = grasp % 2
        starts, lead_a = self._joins(ca, parity, grasp, should_stop, leads)
        goals, lead_b = self._joins(cb, parity, grasp, should_stop, leads)
        if not starts or not goals:
            return [], math.inf
        cell_ids, labels = self._components(parity, should_stop)
        ny = self.field.ny

        def label(u: State) -> int:
            cid = int(cell_ids[u[0] * ny + u[1]])
            return -1 if cid < 0 else int(labels[cid * N_HEADINGS + u[2]])

        if not {label(u) for u in starts} & {label(u) for u in goals}:
            return [], math.inf
        rate = self._push[grasp]
        spin = self._spin
        gx, gy, gh = cb
        way = self._floor_distances(parity, goals, should_stop)

        def cell_part(ix: int, iy: int) -> float:
            # pushes move the car without turning it, turns turn it without moving it: the
            # heuristic is a push part per cell and a turn part per heading; the car moves
            # at least its floor distance to the goal's joins (:meth:`_floor_distances`),
            # not below the straight line; inf: no way to the goal's joins from this cell
            x, y = self.field.position(ix, iy)
            return rate * max(math.hypot(x - gx, y - gy), float(way[cell_ids[ix * ny + iy]]))

        grids = [self._grid(parity, k, should_stop) for k in range(2 * N_HEADINGS)]
        push, turn = [step * rate for step in self._steps], [t * spin for t in self._turns]
        states, expanded = lattice_astar(
            starts, goals, grids=grids, shape=(self.field.nx, ny), push=push, turn=turn,
            cell_part=cell_part,
            turning=[spin * abs(wrap_angle(HEADING_YAWS[h] - gh)) for h in range(N_HEADINGS)],
            weight=weight, max_expansions=self.max_expansions, should_stop=should_stop)
        self.expansions += expanded
        if not states:
            return [], math.inf
        out = self.frame.car_out
        head = [out(lead_a[states[1]])] if states[1] in lead_a else []
        tail = [out(lead_b[states[-2]])] if states[-2] in lead_b else []
        cars = [*head, *map(self.car, states[1:-1]), *tail]
        poses = [start, *(m.object_from_car(c, grasp) for c in cars), goal]
        return poses, route_cost(states, starts, goals, grids=grids, ny=ny, push=push, turn=turn)

    def components(self, parity: int, should_stop: Callable[[], bool] | None = None
                   ) -> tuple[np.ndarray, np.ndarray]:
        """The connected components of the lattice's states of ``parity`` (kept).

        ``(cell_ids, labels)``: see :meth:`_components`.

        Raises:
            Interrupted: ``should_stop()`` became true.
        """
        return self._components(parity, should_stop)

    def joined_components(self, obj: Pose, grasp: int,
                          should_stop: Callable[[], bool] | None = None) -> set[int]:
        """The components (of ``grasp``'s parity) of the states ``obj`` at ``grasp`` joins."""
        parity, ny, m = grasp % 2, self.field.ny, self.checker.model
        cell_ids, labels = self._components(parity, should_stop)
        out = set()
        car = self.frame.car_in(m.car_pose(obj, grasp))
        for ix, iy, h in self._attach(car, parity, grasp, should_stop):
            cid = int(cell_ids[ix * ny + iy])
            if cid >= 0 and labels[cid * N_HEADINGS + h] >= 0:
                out.add(int(labels[cid * N_HEADINGS + h]))
        return out

    def _grid(self, parity: int, k: int, should_stop: Callable[[], bool] | None) -> bytes:
        """The field's ``fits(parity, k)`` as bytes, row-major (kept: cheap to index)."""
        key = (parity, k)
        grid = self._grids.get(key)
        if grid is None:
            grid = self._grids[key] = np.ascontiguousarray(
                self._fits(parity, k, should_stop), dtype=np.uint8).tobytes()
        return grid

    def _fits(self, parity: int, k: int,
              should_stop: Callable[[], bool] | None) -> np.ndarray:
        """The field's ``fits(parity, k)`` within the lattice's region, ``(nx, ny)``."""
        fits = self.field.fits(parity, k, should_stop=should_stop)
        return fits if self.region is None else fits & self.in_region()

    def turn_room(self, parity: int, h: int,
                  should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Where the lattice turns between heading ``h`` and the next at ``parity`` (kept).

        ``(nx, ny)`` booleans (:func:`~.lattice_components.turn_room` over the lattice's
        grids): the turn moves of the lattice's components, and the room an end between
        headings joins (:func:`.end_joins`).

        Raises:
            Interrupted: ``should_stop()`` said stop while a yaw's grid was computed.
        """
        key = (parity, h % N_HEADINGS)
        room = self._rooms.get(key)
        if room is None:
            room = self._rooms[key] = turn_room(
                lambda k: self._fits(parity, k, should_stop), key[1])
        return room

    def in_region(self) -> np.ndarray:
        """The grid positions the lattice holds (``(nx, ny)`` booleans, kept)."""
        return self._mask_over(self.field)

    def _mask_over(self, f: AssemblyField) -> np.ndarray:
        """Grid positions of ``f`` in reach of the region (all if none), kept: one per floor."""
        if self._mask is None:
            if self.region is None:
                self._mask = np.ones((f.nx, f.ny), dtype=bool)
            else:
                m = self.checker.model
                reach = max(m.half_extent(g) for g in range(4)) + 1.5 * self.resolution
                x0, y0 = f.position(0, 0)
                xs = x0 + self.resolution * np.arange(f.nx)
                ys = y0 + self.resolution * np.arange(f.ny)
                self._mask = within_distance(self.frame.region_in(self.region), xs, ys, reach)
        return self._mask

    def _components(self, parity: int,
                    should_stop: Callable[[], bool] | None) -> tuple[np.ndarray, np.ndarray]:
        """Connected component of every lattice state of ``parity`` (kept).

        Returned as ``(cell_ids, labels)``: ``cell_ids[ix * ny + iy]`` numbers the cells free
        at some heading (``-1`` elsewhere), and ``labels[cell_id * N_HEADINGS + h]`` is the
        component of state ``(ix, iy, h)``, ``-1`` where it is not free. Every array but
        ``cell_ids`` follows the free floor, not the bounds' rectangle (a turned row of rooms
        fills a small part of it, and the rectangle grows with the square of its length).
        """
        hit = self._labels.get(parity)
        if hit is None:
            if should_stop is not None and should_stop():  # as when computed: stopped
                raise Interrupted("lattice components")
            hit = self._labels[parity] = shared_components(
                self.field, parity, self.region, lambda: self._labelled(parity, should_stop))
        return hit

    def _labelled(self, parity: int,
                  should_stop: Callable[[], bool] | None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`_components` computed (:func:`.lattice_labels`)."""
        return lattice_labels(lambda k: self._fits(parity, k, should_stop),
                              (self.field.nx, self.field.ny), should_stop)

    def _floor_distances(self, parity: int, goals: dict[State, float],
                         should_stop: Callable[[], bool] | None) -> np.ndarray:
        """Per free cell (``cell_ids``' numbering), its shortest way to a goal join's cell (m).

        Over the cells free at some heading, with the lattice's push vectors as moves
        (:func:`~.guide.move_graph`, kept per parity): every push of a lattice route is such
        a move, so no route from a cell to the goal's joins is shorter; at the push rate it is
        the A* heuristic where it exceeds the straight line (admissible and consistent), and
        ``inf`` where no way joins the cell to the goal. ``[-1]`` (no cell) is 0. The last
        answer per parity is kept (a route and its :meth:`way_bound` ask the same goal).
        """
        cell_ids, _ = self._components(parity, should_stop)
        graph = self._floors.get(parity)
        if graph is None:
            graph = self._floors[parity] = move_graph(
                cell_ids, self.field.nx, self.field.ny, HEADING_VECTORS[:N_HEADINGS // 2],
                should_stop)
        ny = self.field.ny
        sources = frozenset(int(cell_ids[u[0] * ny + u[1]]) for u in goals)
        hit = self._ways.get(parity)
        if hit is not None and hit[0] == sources:
            return hit[1]
        way = np.append(self.resolution * graph_distances(graph, sources, should_stop), 0.0)
        way.flags.writeable = False  # shared by the queries that ask again
        self._ways[parity] = (sources, way)
        return way

    def _attach(self, car: Pose, parity: int, grasp: int,
                should_stop: Callable[[], bool] | None) -> dict[State, float]:
        """Free lattice states near ``car`` (in the frame; the two nearest headings), costed."""
        return self._joins(car, parity, grasp, should_stop, False)[0]

    def _joins(self, car: Pose, parity: int, grasp: int,
               should_stop: Callable[[], bool] | None, leads: bool
               ) -> tuple[dict[State, float], dict[State, Pose]]:
        """:func:`.end_joins` of ``car`` (in the frame): the states, costs and leads' cars."""
        return end_joins(self.field, car, parity, push=self._push[grasp], spin=self._spin,
                         region=self.in_region(), leads=leads, should_stop=should_stop,
                         turns=lambda h: self.turn_room(parity, h, should_stop))

"""The regrasp planner's algorithm (the regrasp paper, Fig. 7), over named parts.

:class:`RegraspSearch` orchestrates; each stage is a part of its own:

1. the **regrasp-free tries** (:mod:`.direct`: a single-grasp RRT-Connect, then the held
   assembly's lattice route), which end planning where one grasp suffices;
2. the start and goal, and the scene's **slots** (:mod:`.objects.slots`) seeded into the
   object roadmap (:class:`~.objects.roadmap.Roadmap`);
3. the **Visibility PRM** on the box alone (:class:`~.objects.visibility.VisibilityRoadmap`),
   recording **critical configurations** (:class:`~.objects.critical.CriticalConfigurations`);
4. **bridge tests** for narrow passages (:class:`~.objects.bridge.BridgeTest`);
5. **diffusion** (:class:`~.objects.diffusion.Diffusion`), with bridge tests mixed in;
6. after each batch of new object nodes, their **multiplexing** into the manipulation and
   regrasping roadmaps (:class:`~.multiplex.graph.MultiplexedGraph`) and the **lazy search**
   with the full checks of the path found (:class:`~.multiplex.search.PathSearch`);
7. the **path optimiser** (:mod:`.optimiser`) on the path found.

The termination condition is an argument of every call that takes time, down to the pivot
steering and the walk search. Calling :meth:`RegraspSearch.run` again continues with the same
roadmaps and caches (OMPL's semantics: solving again continues).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from dataclasses import replace

import numpy as np

from pivot_ompl.analysis.bound_cache import cached_bound
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.config import RegraspConfig, quality_scale
from pivot_ompl.planners.corridor import band_first, corridor_lattice
from pivot_ompl.planners.direct import DirectStats, direct_path, route_weight
from pivot_ompl.planners.eliminate import EliminationReport, eliminate_regrasps, lattice_router
from pivot_ompl.planners.evaluation import Found, Status
from pivot_ompl.planners.expectation import Expectation
from pivot_ompl.planners.grasp_choice import choose_grasps
from pivot_ompl.planners.improve import Budget, ImproveStats, improve, time_share
from pivot_ompl.planners.multiplex.graph import MultiplexedGraph, Node
from pivot_ompl.planners.multiplex.search import PathSearch
from pivot_ompl.planners.objects.bridge import BridgeTest
from pivot_ompl.planners.objects.critical import CriticalConfigurations
from pivot_ompl.planners.objects.diffusion import Diffusion
from pivot_ompl.planners.objects.passage_band import PassageBand
from pivot_ompl.planners.objects.roadmap import PoseIndex, Roadmap, canonical
from pivot_ompl.planners.objects.samplers import PoseSampler
from pivot_ompl.planners.objects.visibility import VisibilityRoadmap
from pivot_ompl.planners.regrasp_stats import RegraspStats
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.regrasp_lattice import RegraspLatticeStats, regrasp_lattice_path
from pivot_ompl.se2 import Pose

Stop = Callable[[], bool]
State = tuple[Pose, int]
#: No path yet: the roadmaps must grow before a search can find one.
NOT_YET: Found[list[Node]] = Found(Status.INVALID)


def _searching(found: Found[list[Node]], should_stop: Stop) -> bool:
    """The search goes on: no path yet, and time left."""
    return found.status is Status.INVALID and not should_stop()


class RegraspSearch:
    """One query's roadmaps, graph and search (see the module docstring).

    Args:
        checker: validity of states, pivot edges and walks.
        start, goal: object poses.
        config: the planner's configuration.
        rng: random generator (the only source of randomness).
        start_grasp: the grasp the robot holds the box with at the start: every path starts
            with it (a walk from it to another grasp at the start is a regrasp edge, priced
            and checked as any); ``None``: any grasp valid at the start.

    Attributes:
        roadmap: the object roadmap.
        critical: the critical configurations recorded in it.
        visibility: the Visibility PRM over it.
        graph: the multiplexed graph.
        paths: its search.
        stats: figures of the runs so far.
        expected: tells its listener the plan's regrasps and places once the regrasp-free
            tries have ended (:mod:`.expectation`).
    """

    roadmap: Roadmap
    critical: CriticalConfigurations
    visibility: VisibilityRoadmap[Pose]
    graph: MultiplexedGraph
    paths: PathSearch
    stats: RegraspStats

    def __init__(self, checker: PivotChecker, start: Pose, goal: Pose, config: RegraspConfig,
                 rng: np.random.Generator, *, start_grasp: int | None = None) -> None:
        """The parts, empty."""
        self.checker, self.start, self.goal, self.start_grasp = checker, start, goal, start_grasp
        self.config, self.rng = config, rng
        sc, se = config.sampling, config.search
        self.roadmap = Roadmap()
        self.sampler = PoseSampler(checker, rng, yaw_range=sc.yaw_range, start=start,
                                   max_rejects=sc.max_rejects)
        self.critical = CriticalConfigurations(checker, self.roadmap, grasps=config.grasps,
                                               spacing=sc.critical_spacing)
        self.visibility = VisibilityRoadmap(
            self.roadmap, sample=self.sampler.box_valid, visible=self.critical.box_visible,
            candidates=self._near_guards, max_failures=sc.guard_failures)
        self.bridge = BridgeTest(checker, self.sampler, sigma=sc.bridge_sigma,
                                 steps=sc.passage_steps)
        self.diffusion = Diffusion(checker, self.sampler, goal, epsilon=sc.epsilon,
                                   goal_bias=sc.goal_bias, critical_bias=sc.critical_bias,
                                   extend_step=sc.extend_step)
        self.graph = MultiplexedGraph(checker, self.roadmap, grasps=config.grasps,
                                      neighbours=se.neighbours, connect_radius=se.connect_radius,
                                      costs=config.cost, turns=se.turns, turn_margin=se.turn_margin)
        self.paths = PathSearch(checker, self.graph, goal, weight=se.weight)
        self.stats = RegraspStats()
        self.passages = PassageBand(checker, start, goal, sc)  #: the passages to seed
        self._stuck = 0  # diffusion steps since the last widening of the passages' band
        self._seeded = PoseIndex(self.roadmap)  # the passage poses seeded, slots' and doors'
        self.lattice: TransferLattice | None = None
        self._band: TransferLattice | None = None
        self._asked_band = False
        self.improved = ImproveStats()
        self._limit: float | None = None  # the solve's time limit (s), if known
        self.elimination = EliminationReport()  #: the last regrasp elimination's report
        self.direct = DirectStats()  #: the regrasp-free tries' figures (:mod:`.direct`)
        self._started = self._tried_direct = False
        self._goal_node = -1
        self.expected = Expectation()
        self._since = 0  # object nodes multiplexed since the last search

    def _near_guards(self, q: Pose, guards: list[int]) -> Iterator[int]:
        """The guards within ``guard_radius`` of ``q``, nearest first."""
        near = self.roadmap.nearest(q, len(guards), among=guards)
        if not near:
            return
        radius = self.config.sampling.guard_radius
        for g, d in zip(near, self.roadmap.distances(near, q), strict=True):
            if d > radius:
                return
            yield g

    # -- the stages --------------------------------------------------------------------
    def prepare(self, should_stop: Stop) -> None:
        """Add start and goal nodes, the slots and the direct edges (the first run does it).

        Once: later calls do nothing.
        """
        if self._started:
            return
        self._started = True
        rm = self.roadmap
        s_i = rm.add(self.start, "start")
        g_i = rm.add(self.goal, "goal")
        self.visibility.adopt_guard(s_i)
        self.visibility.adopt_guard(g_i)
        self.graph.multiplex_pending(lambda: False)  # the ends, whatever the time
        self._seed_passages(should_stop)
        self._goal_node = g_i
        self.graph.set_ends(s_i, g_i, should_stop, start_grasp=self.start_grasp)

    def _seed_passages(self, should_stop: Stop) -> None:
        """Seed the slots and doors of the passages' band at its level (:mod:`.passage_band`)."""
        s, rm = self.stats, self.roadmap
        seeded = self.passages.seed(rm, self._seeded, self.sampler.region(), should_stop)
        s.slots, s.doors = seeded.slots, seeded.doors
        s.slot_nodes, s.door_nodes = s.slot_nodes + seeded.slot_nodes, \
            s.door_nodes + seeded.door_nodes
        self.sampler.focus(self.passages.area())  # the samples too, where it is a band

    def _widened(self, should_stop: Stop) -> Found[list[Node]]:
        """After ``band_patience`` diffusion steps without a path, the band widened and searched."""
        self._stuck += 1
        if self._stuck < self.config.sampling.band_patience or not self.passages.can_widen():
            return NOT_YET
        self._stuck = 0
        self.passages.widen()
        self._seed_passages(should_stop)
        return self._grown(should_stop)

    def restart(self, start: Pose, should_stop: Stop, *, start_grasp: int | None = None) -> None:
        """Search again from a new start over everything grown so far (replanning).

        The obstacles must be those the roadmaps were grown among (the same checker): the
        new start is added and multiplexed, and the next :meth:`run` searches the graph as it
        is, growing it only if no path is found. ``start_grasp``: as for the constructor.
        """
        self.start, self.start_grasp = start, start_grasp
        if not self._started:
            return
        s_i = self.roadmap.add(start, "start")
        self.visibility.adopt_guard(s_i)
        self.graph.multiplex_pending(lambda: False)
        self.graph.set_ends(s_i, self._goal_node, should_stop, start_grasp=start_grasp)

    def _single_grasp(self, should_stop: Stop) -> list[State]:
        """A regrasp-free path (:func:`~.direct.direct_path`) at the grasps valid at both ends.

        The held grasp only, if one is; ``[]`` when there is none, or when a bound the
        cache already holds proves that every plan regrasps (a later plan of a building whose
        proof an earlier plan or ``pivot-ompl bound`` computed: the tries cannot succeed).
        """
        ck = self.checker
        rng = self.rng.spawn(1)[0]  # its own stream: the search's does not depend on the tries
        known = cached_bound(ck.scene)
        if known is not None and known.solvable and (known.regrasps or 0) >= 1:
            return []
        grasps = [g for g in self.config.grasps if ck.state_valid(self.start, g)
                  and ck.state_valid(self.goal, g) and self.start_grasp in (None, g)]
        d, cfg, spacing = self.direct, self.config.single_grasp, self.config.optimiser.run_spacing
        if cfg.lattice and self._area() < cfg.lattice_area:  # the trees' floor: no lattice
            cfg = replace(cfg, lattice=False)
        path = direct_path(ck, self.start, self.goal, grasps=grasps, config=cfg,
                           costs=self.config.cost, rng=rng, lattice=self._lattice,
                           run_spacing=spacing, should_stop=should_stop, stats=d,
                           band=lambda: self._corridor(should_stop))
        s = self.stats
        s.single_grasp_checks, s.single_grasp_solved = d.checks, bool(path)
        s.single_grasp_by, s.time_single_grasp = d.solved_by, d.seconds
        return path

    def _regrasp_lattice(self, should_stop: Stop) -> list[State]:
        """Regrasps where the lattice's components meet, if banded (:mod:`.regrasp_lattice`)."""
        ck, cfg, q0, q1, sg = self.checker, self.config, self.start, self.goal, \
            self.config.single_grasp
        if not (cfg.sampling.regrasp_lattice and self.passages.applies() and sg.lattice
                and self._area() >= sg.lattice_area):
            return []
        ends = [[g for g in cfg.grasps if ck.state_valid(q, g)
                 and (q is q1 or self.start_grasp in (None, g))] for q in (q0, q1)]
        t0, figures, s = time.perf_counter(), RegraspLatticeStats(), self.stats
        found = regrasp_lattice_path(ck, lat := self._lattice(), cfg.cost, q0, q1,
                                     start_grasps=ends[0], goal_grasps=ends[1], grasps=cfg.grasps,
                                     run_spacing=cfg.optimiser.run_spacing, weight=lat.weight,
                                     should_stop=should_stop, stats=figures,
                                     on_steps=self.expected.steps)
        s.regrasp_lattice_solved, s.regrasp_lattice_changes = bool(found.path), figures.changes
        s.time_regrasp_lattice += time.perf_counter() - t0
        return found.path or []

    def _corridor(self, should_stop: Stop) -> TransferLattice | None:
        """The lattice round the floor's way (:mod:`.corridor`) where the lattice try is made."""
        sg = self.config.single_grasp
        if not self._asked_band:
            self._asked_band = True
            self._band = corridor_lattice(
                self.checker, self.config.cost, self.start, self.goal, width=sg.corridor,
                region=self.sampler.region(), weight=route_weight(sg, self._area()),
                should_stop=should_stop) if sg.lattice and self._area() >= sg.lattice_area \
                else None
        return self._band

    def _lattice(self) -> TransferLattice:
        """The held assembly's lattice within the start's reach, made when first asked."""
        if self.lattice is None:
            w = route_weight(self.config.single_grasp, self._area())  # shared with direct
            self.lattice = TransferLattice(self.checker, self.config.cost,
                                           region=self.sampler.region(), weight=w)
        return self.lattice

    def _grown(self, should_stop: Stop) -> Found[list[Node]]:
        """Multiplex the new object nodes; search every ``search.every`` that gave some."""
        self._since += self.graph.multiplex_pending(should_stop)[1]
        if self._since < self.config.search.every:
            return NOT_YET
        self._since = 0
        return self.paths.find(should_stop)

    def _bridge(self, should_stop: Stop) -> Found[list[Node]]:
        """One round of bridge tests; the passage's nodes added and searched at once."""
        nodes = self.bridge.passage(should_stop)
        if not nodes:
            return NOT_YET
        self.stats.passage_nodes += 1
        for q in nodes:
            self.roadmap.add(q, "passage")
        return self.paths.find(should_stop) if self.graph.multiplex_pending(should_stop)[0] \
            else NOT_YET

    def _diffuse(self, should_stop: Stop) -> Found[list[Node]]:
        """One diffusion step (or a bridge test, with probability ``bridge_bias``)."""
        if self.rng.uniform() < self.config.sampling.bridge_bias:
            return self._bridge(should_stop)
        rm = self.roadmap
        q = self.diffusion.target([rm.poses[i] for i in self.critical.indices])
        near = rm.poses[rm.nearest(q, 1)[0]]
        qn = self.diffusion.extend(near, q)
        if qn == near:
            return NOT_YET
        rm.add(canonical(qn), "diffusion")
        self.stats.diffusion_nodes += 1
        return self._grown(should_stop)

    # -- the algorithm -------------------------------------------------------------------
    def run(self, should_stop: Stop, *, limit: float | None = None,
            searching: Stop | None = None) -> list[State]:
        """Plan in ``limit`` s if known (``searching``: the stop until a path is found) or []."""
        sc, t0, stop = self.config.sampling, time.perf_counter(), searching or should_stop
        self._limit = limit
        if not self._started and not self._tried_direct:
            self._tried_direct = True  # before the passages are seeded: they are not needed
            single = self._single_grasp(stop)
            if single:
                self.expected.tell(0)
            direct = single or self._regrasp_lattice(stop)
            if direct:  # re-routed in a short band if the whole lattice is not made
                band = self._corridor(stop) if single and self.lattice is None \
                    and self.config.optimiser.routes else None
                band = band if band is not None and band_first(band) else None
                direct = self._optimised(direct, should_stop, band=band)
                self._fill_stats()
                return direct
        self.expected.tell(None)  # no coarse plan: the count comes with the plan
        self.prepare(stop)
        found = self.paths.find(stop)
        n = 0
        cap = self._visibility_samples()
        while _searching(found, stop) and not self.visibility.done and n < cap:
            n += 1
            self.visibility.step(stop)
            found = self._grown(stop)
        self.stats.time_visibility += time.perf_counter() - t0
        for _ in range(sc.bridge_rounds if self.stats.passage_nodes == 0 else 0):
            if not _searching(found, stop):
                break
            found = self._bridge(stop)
        while _searching(found, stop):
            found = self._diffuse(stop)
            if _searching(found, stop):
                found = self._widened(stop)
        states = self._optimised(self.graph.express(found.path), should_stop) \
            if found.path else []
        self._fill_stats()
        return states

    def _area(self) -> float:
        """The floor (m^2) the box may reach from the start (the bounds' if not known)."""
        region = self.sampler.region()
        x0, y0, x1, y1 = self.checker.world.bounds
        return (x1 - x0) * (y1 - y0) if region is None else float(region.area)

    def _visibility_samples(self) -> int:
        """Samples of the Visibility PRM phase: more on a floor with more to reach."""
        sc = self.config.sampling
        area = self.sampler.focus_area or self._area()  # the band's, if focused
        return max(sc.max_visibility_samples, math.ceil(area / sc.visibility_area))

    def _optimised(self, states: list[State], should_stop: Stop,
                   band: TransferLattice | None = None) -> list[State]:
        """The path improved (:func:`~.improve.improve`) from the held grasp, if any.

        Each step within its budget of checks and the quality share of ``limit`` together;
        re-routed over ``band`` if given, else over the whole lattice.
        """
        cfg = self.config.optimiser
        if not cfg.enabled:
            return states
        t1 = time.perf_counter()
        should_stop = time_share(should_stop, cfg.quality_share, self._limit)
        if cfg.routes and band is None:
            self._lattice()
        lat = band if band is not None else self.lattice
        scale = quality_scale(cfg.quality_share)  # every step's share scaled by it
        floor = max(cfg.min_checks, round(scale * cfg.converge_checks))  # however few searched
        routes_before = self.improved.routes_seconds
        states = improve(self.checker, states, self.config, should_stop=should_stop,
                         routes=Budget(share=scale * cfg.route_share, minimum=floor),
                         optimiser=Budget(share=scale * cfg.check_share, minimum=floor),
                         start_grasp=self.start_grasp, lattice=lat,
                         stats=self.improved)
        self.stats.time_routes += self.improved.routes_seconds - routes_before
        ck, costs = self.checker, self.config.cost
        router = lattice_router(ck, lat, costs, run_spacing=cfg.run_spacing) if lat else None
        extra = Budget(share=scale * cfg.eliminate_share, minimum=max(cfg.eliminate_checks, floor))
        if cfg.eliminate:
            self.elimination = EliminationReport()
            states = eliminate_regrasps(
                ck, states, should_stop=extra.stop(should_stop, ck, states), rng=self.rng,
                costs=costs, checks=cfg.eliminate_checks, step=self.config.single_grasp.step,
                start_grasp=self.start_grasp, report=self.elimination, router=router)
        if cfg.choose_grasps and router is not None:
            states = choose_grasps(ck, states, router=router,
                                   should_stop=extra.stop(should_stop, ck, states),
                                   grasps=self.config.grasps, costs=costs,
                                   start_grasp=self.start_grasp)
        self.stats.time_optimise += time.perf_counter() - t1
        return states

    def _fill_stats(self) -> None:
        self.stats.count(self.roadmap, self.graph, self.paths, self.improved)

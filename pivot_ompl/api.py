"""The Python API: ``pivot_ompl.api.plan(scene, planner="regrasp", time_limit=30.0, seed=0)``."""

from __future__ import annotations

import contextlib
import logging
import math
import time
from pathlib import Path
from typing import Any

from ompl import util as ou

from pivot_ompl.analysis.late_proof import LateProof, NoPlan
from pivot_ompl.analysis.passage import PassageOnce, explain_no_plan
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.prover import Prover, wanted
from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_setup
from pivot_ompl.base.staged_solve import MIN_SOLVE_TIME as MIN_SOLVE_TIME
from pivot_ompl.base.staged_solve import solve_staged
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted, PlanningError, counted
from pivot_ompl.plan_arguments import MAX_SEED as MAX_SEED
from pivot_ompl.plan_arguments import MAX_TIME_LIMIT as MAX_TIME_LIMIT
from pivot_ompl.plan_arguments import check_config, check_plan_arguments
from pivot_ompl.plan_arguments import check_time_limit as check_time_limit
from pivot_ompl.plan_result import PlanResult as PlanResult
from pivot_ompl.plan_result import infeasible_result as infeasible_result
from pivot_ompl.plan_result import path_plan, scene_record, stopped_in_setup
from pivot_ompl.planfile import Plan
from pivot_ompl.planners import (
    OMPL_PLANNERS,
    RegraspConfig,
    RegraspPlanner,
    Resume,
    make_planner,
    parse_spec,
)
from pivot_ompl.planners.explain import explain_plan, regrasp_places
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.repair import State, stored_route
from pivot_ompl.quality import plan_quality
from pivot_ompl.scene import Scene, load_scene

log = logging.getLogger(__name__)

# OMPL's own log (its Info and Debug lines on every solve) is quiet by default; show it with
# ompl.util.setLogLevel(ompl.util.LogLevel.LOG_INFO) or `pivot-ompl --log-level DEBUG`.
ou.setLogLevel(ou.LogLevel.LOG_WARN)

#: Longest a first computation of a scene's lower bounds may take (s); then they are ``null``.
BOUND_TIME_LIMIT = 10.0
#: Share of the limit for the relaxation to prove, before the search, that no plan exists.
PROOF_SHARE = 0.08
#: Shares of the time limit at which the search, still without a path, asks the relaxation
#: once whether any plan exists (:class:`~pivot_ompl.analysis.late_proof.LateProof`), by which
#: the relaxation is stopped, and by which the explanation of a proof is stopped.
LATE_PROOF_BEGIN, LATE_PROOF_END, EXPLAIN_END = 0.02, 0.08, 0.095
#: Shares of the limit from which the held poses' relaxation may be tried, and its own end.
HELD_PROOF_BEGIN, HELD_PROOF_END = 0.04, 0.25
#: Share of the time limit (at most ``FINISH_MAX`` s) kept from the search for the steps after
#: it: converting the path, the lower bounds, and the caller writing the plan. A limit ``T``
#: then ends within ``T`` in :func:`plan`, and within ``T + 5 %`` once the plan is written.
FINISH_SHARE, FINISH_MAX = 0.2, 3.0
#: Share of the time limit (at most ``WRITE_MAX`` s) kept from the lower bounds for writing
#: the plan: they stop that long before the limit's end.
WRITE_SHARE, WRITE_MAX = 0.1, 2.0


def plan(scene: Scene | str | Path, *, planner: str = "regrasp", time_limit: float = 30.0,
         seed: int = 0, simplify: bool = False, regrasp_cost: float | None = None,
         config: RegraspConfig | None = None, bound: bool = True,
         checker: PivotChecker | None = None, resume: RegraspSearch | None = None,
         start_grasp: int | None = None, late_proof: bool | None = None,
         prove: bool | None = None, parallel: bool | None = None) -> PlanResult:
    """Plan a pivoting path (with regrasps where needed) for ``scene``.

    Args:
        scene: a :class:`Scene` or the path of a scene file.
        planner: ``"regrasp"``, ``"visprm"`` or an OMPL planner (``"rrtconnect"``,
            ``"kpiece1"``...; the names are the keys of ``pivot_ompl.planners.PLANNERS``);
            the regrasp planner's parameters may follow in brackets
            (``"regrasp[search.weight=1.5]"``, :mod:`pivot_ompl.planners.registry`).
        time_limit: wall-clock limit (s, > 0) of loading, setup and solve together (and
            of the lower bounds, see ``bound``); above :data:`MAX_TIME_LIMIT`
            (``math.inf`` included) it is :data:`MAX_TIME_LIMIT`.
        seed: seed of our planners' generator (and of OMPL's RNG for OMPL planners),
            0 to :data:`MAX_SEED`.
        simplify: run OMPL's ``PathSimplifier`` on OMPL planners' paths.
        regrasp_cost: the price of one regrasp (s, >= 0) on top of its execution seconds,
            which the regrasp planner's search and optimiser pay (default
            :data:`pivot_ompl.cost.REGRASP_COST`); the quality block reports it.
        config: the regrasp planner's configuration (``regrasp_cost`` overrides its
            ``cost.regrasp``).
        bound: report the scene's lower bounds on regrasps and route length in the quality
            block (:func:`pivot_ompl.analysis.plan_bounds.plan_bounds`: computed once per
            scene geometry, within ``time_limit`` (what the search left of it, less
            :data:`WRITE_SHARE` of it kept for writing the plan), then read from the
            cache), and prove before the search what a narrow passage explains; ``False``:
            ``null`` there and nothing computed.
        checker: a :class:`~pivot_ompl.checking.pivot_checker.PivotChecker` of the same scene
            geometry whose checked motions to reuse (:class:`pivot_ompl.session.PlanningSession`
            passes its own); by default a new one.
        resume: the ``search`` of an earlier result with the same ``checker`` and goal: the
            regrasp planner searches from the new start over its roadmaps (replanning).
        start_grasp: the grasp held at the start (0 to 3): every plan starts with it, other
            grasps reached by walks from it priced as any regrasp; ``None``: any valid grasp.
        late_proof: a search still without a path after :data:`LATE_PROOF_BEGIN` of the
            limit (the regrasp search: and of CPU seconds, or :data:`HELD_PROOF_BEGIN`) asks
            the relaxation once whether any plan exists (``INFEASIBLE`` with the reason when
            none does, :class:`~pivot_ompl.analysis.late_proof.LateProof`); ``None``: ``bound``.
        prove: when the plan regrasps and the cheaper bounds prove fewer, refine the raster
            relaxation where its best path passes narrow places (as ``pivot-ompl bound
            --guided``) with what the limit leaves, so that on large buildings the plan
            carries its proof (seconds, once per building: cached). ``None`` (default): when
            its estimate (:func:`~pivot_ompl.analysis.bound_levels.guided_estimate`) fits
            what the limit leaves; ``True``: whatever the estimate, stopped at the limit
            (rounds done stand); ``False``: never (a refined bound is still read from cache).
        parallel: with ``bound`` and the regrasp planner, prove "no plan" and the lower
            bounds in a process of their own beside the search, from its start
            (:mod:`pivot_ompl.analysis.prover`: the same proofs, on a second core); ``None``
            (default): on two cores or more, with a limit of 5 s or more, where they are
            estimated to take a second or more (:func:`~pivot_ompl.analysis.prover.wanted`);
            ``False``: in the search's process, the late proof in windows of the limit
            (``late_proof``).

    Raises:
        PlanningError: ``INVALID_START``/``INVALID_GOAL`` (no grasp there, or not ``start_grasp``).
        InputError: bad parameters (wrong type or value), naming the parameter.
    """
    time_limit = check_plan_arguments(scene, planner, time_limit, seed, simplify, bound,
                                      start_grasp, late_proof, prove, parallel)
    config = check_config(config, regrasp_cost)
    started, cpu = time.monotonic(), time.process_time()  # the limit counts from here (loading too)
    t0 = time.perf_counter()
    deadline = started + time_limit
    end = deadline - _share(time_limit, WRITE_SHARE, WRITE_MAX)  # the bounds' end
    prover = None

    def proof_over() -> bool:
        return time.monotonic() >= started + PROOF_SHARE * time_limit

    with contextlib.ExitStack() as closing:  # a prover ends with the plan, whatever ends it
        try:
            if not isinstance(scene, Scene):
                scene = load_scene(scene, deadline=deadline)
            base = parse_spec(planner)[0]
            if base == "regrasp" and bound and late_proof is not False and \
                    wanted(scene, parallel, time_limit=time_limit):
                prover = _prover(scene, closing, end=end, prove=prove)
            passages = PassageOnce(scene)  # searched once, for the checks here and the proofs
            if prover is not None:  # its job once the passage is known (before the set-up)
                passages(should_stop=proof_over)
                prover.start(passages)
            if base in OMPL_PLANNERS:
                seed_ompl(seed)
            problem = make_setup(scene, seed=seed, checker=checker, start_grasp=start_grasp,
                                 should_stop=lambda: time.monotonic() >= deadline)
        except Interrupted as e:
            return stopped_in_setup(scene, planner, seed, time_limit, e.what,
                                     time.perf_counter() - t0)
        if bound:
            proof = explain_no_plan(scene, should_stop=proof_over, passages=passages)
            if proof is not None:
                return infeasible_result(scene, planner, seed, time_limit,
                                         NoPlan(proof[0], proof[1]),
                                         {"setup": time.perf_counter() - t0, "solve": 0.0})
        p, config = _planner_for(problem, planner, seed=seed, config=config,
                                 resume=Resume(start_grasp, resume))
        regrasp = isinstance(p, RegraspPlanner)
        own = _late_proof(scene, regrasp=regrasp, bound=bound, late_proof=late_proof,
                          passages=passages, started=started, cpu=cpu, time_limit=time_limit)
        if prover is not None:
            prover.fallback = own
        late = prover if prover is not None else own
        if regrasp:  # its quality share is one of the solve's limit
            p.solve_limit = time_limit - (time.monotonic() - started)
            p.proof = late  # polled by its search; other planners are stopped to ask it
            p.expect = None if prover is None else prover.expect  # what it will regrasp
        t1 = time.perf_counter()
        name = solve_staged(problem.setup,
                            time_limit - _share(time_limit, FINISH_SHARE, FINISH_MAX), started,
                            proof=None if regrasp else late,
                            ask_at=started + LATE_PROOF_BEGIN * time_limit)
        t2 = time.perf_counter()
        if late is not None and late.proof is not None and name != "EXACT_SOLUTION":
            return infeasible_result(scene, planner, seed, time_limit, late.proof,
                                     {"setup": t1 - t0, "solve": t2 - t1})
        if name in ("INVALID_START", "INVALID_GOAL"):
            pose = scene.start if name == "INVALID_START" else scene.goal
            raise PlanningError(name, problem.checker.explain(pose))
        extra = {"planner": planner, "seed": seed, "time_limit": time_limit,
                 **scene_record(scene)}
        result_plan = path_plan(scene, problem, name, extra, simplify=simplify and base in
                                OMPL_PLANNERS, end=end)
        t3 = time.perf_counter()
        timings = {"setup": t1 - t0, "solve": t2 - t1, "convert": t3 - t2}
        result_plan.extra["timings"] = timings
        stats = dict(getattr(p, "stats", {}) or {})
        result_plan.extra["roadmap"] = stats
        if result_plan.phases:
            result_plan.extra["quality"] = _quality(result_plan, scene, config, bound,
                                                    timings, end, prove=prove, prover=prover,
                                                    checker=problem.checker)
    c = problem.checker.counters
    log.info("%s on %s: %s in %.2f s (%s, %s)", planner, scene.name, name, t2 - t1,
             counted(result_plan.pivots, "pivot"), counted(result_plan.regrasps, "regrasp"))
    return PlanResult(name, result_plan, planner, seed, time_limit, timings, stats,
                      {"valid": c.valid, "invalid": c.invalid, "cache_hits": c.cache_hits},
                      p.last_search if isinstance(p, RegraspPlanner) else None, scene)


def _planner_for(problem: Any, planner: str, *, seed: int, config: RegraspConfig,
                 resume: Resume) -> tuple[Any, RegraspConfig]:
    """The planner named ``planner`` set up on ``problem``, and the configuration it uses.

    The regrasp planner starts from ``resume`` (it keeps the search only for this checker
    and goal).
    """
    p = make_planner(planner, problem, seed=seed, config=config, resume=resume)
    if isinstance(p, RegraspPlanner):
        config = p.config
    problem.setup.setPlanner(p)
    problem.setup.setup()
    return p, config


def plan_from_route(scene: Scene, checker: PivotChecker, states: list[State], *,
                    planner: str, seed: int, time_limit: float, timings: dict[str, float],
                    stats: dict[str, Any], config: RegraspConfig | None = None,
                    bound: bool = False, search: RegraspSearch | None = None) -> PlanResult:
    """A solved :class:`PlanResult` of a route found without OMPL's ``solve`` (a repair).

    The plan is written from ``checker``'s checks of the route's edges as :func:`plan`
    writes a solution path (an invalid edge raises :class:`PlanningError`), with the same
    extra fields and quality block; ``timings`` gets ``convert``.
    """
    t0 = time.perf_counter()
    extra = {"planner": planner, "seed": seed, "time_limit": time_limit,
             **scene_record(scene), "route": stored_route(states)}
    result_plan = path_to_plan(scene, checker, states, extra=extra)
    timings["convert"] = time.perf_counter() - t0
    result_plan.extra["timings"] = timings
    result_plan.extra["roadmap"] = stats
    result_plan.extra["quality"] = _quality(result_plan, scene, config or RegraspConfig(),
                                            bound, timings, checker=checker)
    c = checker.counters
    return PlanResult("EXACT_SOLUTION", result_plan, planner, seed, time_limit, timings, stats,
                      {"valid": c.valid, "invalid": c.invalid, "cache_hits": c.cache_hits},
                      search)


def seed_ompl(seed: int) -> None:
    """Seed OMPL's generator of random seeds with ``seed + 1`` (OMPL's seed must be > 0).

    Every OMPL random generator made afterwards (a planner's, a sampler's) draws its own seed
    from it, so each seeded plan is reproducible, the second one in a process too: OMPL's
    "random number generation already started" error for a second seed is silenced, it
    holds only for generators made before.
    """
    level = ou.getLogLevel()
    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    try:
        ou.RNG.setSeed(seed + 1)
    finally:
        ou.setLogLevel(level)


def _share(time_limit: float, share: float, most: float) -> float:
    """``share`` of ``time_limit`` (s), at most ``most`` s."""
    return min(share * time_limit, most)


def _quality(result_plan: Plan, scene: Scene, config: RegraspConfig, bound: bool,
             timings: dict[str, float], end: float = math.inf, *,
             prove: bool | None = None, prover: Prover | None = None,
             checker: PivotChecker | None = None) -> dict[str, Any]:
    """The quality block, with the scene's lower bounds (stopped at ``end``) when ``bound``.

    ``prove`` (:func:`plan`'s): for a plan with regrasps, unless ``False``, the guided
    refinement may run until ``end`` (else the bounds stop after :data:`BOUND_TIME_LIMIT` s).
    ``prover``: the plan's prover, whose bounds are waited for within that time and kept as
    this process's own (``timings["bound"]`` counts the wait). ``checker``: the plan's, which
    names what forces each regrasp (one is made if none is given).
    """
    regrasps, route = None, None
    if bound:
        t0 = time.perf_counter()
        guided = prove is True or (prove is None and result_plan.regrasps > 0)
        bound_end = end if guided else min(end, time.monotonic() + BOUND_TIME_LIMIT)
        places = regrasp_places(result_plan)
        if prover is not None:
            prover.solved(result_plan.regrasps, places)
            prover.wait_bounds(until=bound_end, regrasps=result_plan.regrasps)
        route_length = plan_quality(result_plan)["route_length"]
        regrasps, route = plan_bounds(scene, result_plan.regrasps, route_length=route_length,
                                      should_stop=lambda: time.monotonic() > bound_end,
                                      time_left=lambda: bound_end - time.monotonic(),
                                      guided=guided, guided_by_estimate=prove is None,
                                      places=places)
        timings["bound"] = time.perf_counter() - t0
    q = plan_quality(result_plan, regrasps_lower_bound=regrasps, shortest_route=route,
                     costs=config.cost)
    return {**q, **explain_plan(result_plan, scene, q, checker=checker)}


def _prover(scene: Scene, closing: contextlib.ExitStack, *, end: float,
            prove: bool | None) -> Prover | None:
    """The plan's prover, closed with ``closing``; ``None`` where its process cannot start."""
    try:
        return closing.enter_context(Prover(scene, end=end, prove=prove))
    except OSError as e:  # no interpreter to start: the proofs run in this process
        log.warning("no prover (the proofs run in the plan's process): %s", e)
        return None


def _late_proof(scene: Scene, *, regrasp: bool, bound: bool, late_proof: bool | None,
                passages: PassageOnce, started: float, cpu: float, time_limit: float
                ) -> LateProof | None:
    """The late proof the search asks whether no plan exists, if any (``plan``'s arguments).

    In the search's own process, in windows of the limit (a
    :class:`~pivot_ompl.analysis.prover.Prover` beside it, where ``plan`` starts one, asks
    instead).
    """
    if not (bound if late_proof is None else late_proof):
        return None
    return LateProof(scene, begin=started + LATE_PROOF_BEGIN * time_limit,
                     end=started + LATE_PROOF_END * time_limit,
                     explain_end=started + EXPLAIN_END * time_limit, passages=passages,
                     held_begin=started + HELD_PROOF_BEGIN * time_limit,
                     held_end=started + HELD_PROOF_END * time_limit,
                     work_begin=cpu + LATE_PROOF_BEGIN * time_limit if regrasp else None)

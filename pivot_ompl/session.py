"""Replanning from what the robot sees: a planning session that keeps what it has checked.

A :class:`PlanningSession` plans a scene, then plans again from an observed state: the box
where it really is (drift, a slip), obstacles that appeared or went. It keeps between calls:

* the checked motions (pivot sequences and walks, :class:`~pivot_ompl.checking.pivot_checker
  .PivotChecker`'s caches): all of them while the obstacles stay; after a change only those
  the change cannot have touched (:meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.adopt`:
  a valid motion whose swept region meets an added obstacle, or an invalid one when an
  obstacle went, is checked again);
* while the obstacles stay, the regrasp planner's roadmaps and multiplexed graph: the next
  search starts from the observed pose over them (it grows them only if they hold no path;
  when that finds nothing in half the time left, a new search gets the rest);
* the route of the plan being executed (the last plan, or ``executing=``, a plan file's
  ``route`` field): a replan first repairs it locally from the observed state
  (:func:`~pivot_ompl.planners.repair.repair_route`: a checked transfer from the observed pose
  to the nearest point of the route it can reach directly, ahead of what a change made
  invalid, then the rest of the route, every edge checked against the scene as it is now),
  and searches only when no such repair exists; the repaired route's own states and a few
  after them are polished (the rest was polished when it was planned);
* the motions of the plan being executed (the last plan's, or those ``executing=`` stores):
  each edge's pivot rotations and each walk, offered to the checker
  (:mod:`pivot_ompl.checking.stored`), which uses one only after it passes the checker's own
  checks against the scene as it is now. A box observed where that plan put it, partway
  along a transfer edge, is offered the rest of the edge's rotations from there
  (:func:`~pivot_ompl.checking.stored.passing_rest`): in a gap passed within the
  refinement's resolution of the walls, no new pivot sequence can start at such a pose.

Every plan is checked as a fresh plan would be; only work is saved. Plans start at the
observed box pose; with ``grasp=k`` (the robot holds the box with grasp ``k``) every plan
starts with grasp ``k``: the search starts from ``(box, k)`` alone (``start_grasp`` of
:func:`~pivot_ompl.api.plan`; other grasps are reached by walks from it, priced and checked
as any regrasp), and a repaired route that joins the old one at another grasp starts with
the walk from ``k`` to it and is polished from ``k``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Sequence
from typing import Any

from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.late_proof import LateProof, generic
from pivot_ompl.api import (
    EXPLAIN_END,
    LATE_PROOF_BEGIN,
    LATE_PROOF_END,
    PlanResult,
    check_time_limit,
    infeasible_result,
    plan,
    plan_from_route,
)
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import StoredMotions, passing_rest, stored_motions
from pivot_ompl.errors import InputError, PlanningError
from pivot_ompl.grasp import check_grasp
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.repair import State, polish, repair_route
from pivot_ompl.scene import Obstacle, Scene, load_scene
from pivot_ompl.session_inputs import (
    added_obstacles,
    check_seed,
    check_session,
    listed,
    observed_pose,
    route_of_plan,
)

log = logging.getLogger(__name__)

#: Least time (s) for which a search still starts after a failed repair or resumed search.
MIN_SEARCH_TIME = 0.05
#: Share of a replan's time kept, after added obstacles, to prove that no plan exists when
#: the search finds none (:func:`_proved_infeasible`).
PROOF_SHARE = 0.25


class PlanningSession:
    """Plans of one scene, then plans again from observed states (see the module docstring).

    Args:
        scene: the scene (a :class:`~pivot_ompl.scene.Scene`, a file or a shipped name).
        planner: as for :func:`pivot_ompl.api.plan`.
        config: the regrasp planner's configuration.
        seed: the default seed of every call.
        bound: report the lower bounds in the quality block (computed once per scene; a
            replan's scene is new, so ``False`` by default: replanning stays fast).
        executing: the plan being executed, made for ``scene`` (a new process replanning a
            plan file): the first replan repairs its ``route``; by default the session's
            last plan's.
        repair: repair the route before searching (``False``: every replan searches).

    Attributes:
        scene: the scene as last planned (start at the last observed box pose, obstacles as
            changed).
        last: the last result, ``None`` before the first call.
    """

    def __init__(self, scene: Scene | str, *, planner: str = "regrasp",
                 config: RegraspConfig | None = None, seed: int = 0,
                 bound: bool = False, executing: Plan | None = None,
                 repair: bool = True) -> None:
        """A session; nothing is planned yet."""
        check_session(scene, planner, config, seed, bound, executing, repair)
        self.scene = scene if isinstance(scene, Scene) else load_scene(scene)
        self.planner, self.config, self.seed, self.bound = planner, config, seed, bound
        self.repair = repair
        self.last: PlanResult | None = None
        self._route: list[State] = route_of_plan(executing) if executing is not None else []
        self._plan: Plan | None = executing if self._route else None
        self._stored = stored_motions(executing, self._route) if self._route and \
            executing is not None else StoredMotions()
        self._checker: PivotChecker | None = None
        self._search: RegraspSearch | None = None

    @property
    def checker(self) -> PivotChecker | None:
        """The checker of the scene planned last (``None`` before a plan); kept for replans."""
        return self._checker

    def plan(self, *, time_limit: float = 30.0, seed: int | None = None) -> PlanResult:
        """Plan the scene from its start (or continue from the last observed state)."""
        time_limit = check_time_limit(time_limit)
        check_seed(seed)
        return self._run(self.scene, time_limit, seed, None)

    def replan(self, *, box: Sequence[float] | None = None, grasp: int | None = None,
               robot: Sequence[float] | None = None,
               add_obstacles: Sequence[Obstacle | dict[str, Any]] = (),
               remove_obstacles: Sequence[Obstacle | int] = (), time_limit: float = 30.0,
               seed: int | None = None) -> PlanResult:
        """Plan from the observed state to the goal.

        Args:
            box: the box's observed pose ``(x, y, yaw)``.
            grasp: the grasp the robot holds the box with, or ``None`` (the box rests; the
                plan may start with any grasp).
            robot: where the robot stands, for ``grasp=None``; recorded in the result's
                extra field ``observed_robot`` (the plan starts at a grasp pose; its
                whole-body motion starts at ``robot`` and walks to it).
            add_obstacles: obstacles that appeared (objects or dicts as in a scene file).
            remove_obstacles: obstacles that went (the scene's objects or their indices).
            time_limit: as for :func:`pivot_ompl.api.plan` (s). A search still without a
                path after a small share of it asks the relaxation once whether any plan
                exists (``late_proof`` of :func:`~pivot_ompl.api.plan`); after
                ``add_obstacles``, a search that finds no plan leaves :data:`PROOF_SHARE` of
                it to prove that none exists. When none does the status is ``INFEASIBLE``,
                with the reason and the place (``infeasible_reason``, ``passage``, ``turn``).
            seed: the seed (default the session's).

        Raises:
            InputError: a bad argument, naming it.
            PlanningError: the observed pose is in collision, or the held grasp is not valid
                there (``INVALID_START``).
        """
        start = observed_pose(box, "box")
        if grasp is not None:
            grasp = check_grasp(grasp, field="grasp")
        if robot is not None:
            robot = observed_pose(robot, "robot")
        time_limit = check_time_limit(time_limit)
        check_seed(seed)
        added = added_obstacles(add_obstacles)
        gone = self._removed(listed(remove_obstacles, "remove_obstacles"))
        obstacles = tuple(o for o in self.scene.obstacles if o not in gone) + added
        scene = dataclasses.replace(self.scene, start=start, obstacles=obstacles)
        if self._plan is not None:  # the box where the plan put it: the rest of its edge
            end = time.monotonic() + time_limit
            self._stored.transfers.update(passing_rest(
                self._plan, self._route, start, grasp,
                should_stop=lambda: time.monotonic() > end))
        if self._checker is not None and (added or gone):
            fresh = self._new_checker(scene)
            kept = fresh.adopt(self._checker, added=added, removed=gone)
            log.info("replanning: %d checked motions kept after the change", kept)
            self._checker, self._search = fresh, None  # the roadmaps grew among the old ones
        started = time.monotonic()  # a repair slow to find a route asks once if any plan exists
        late = LateProof(scene, begin=started + LATE_PROOF_BEGIN * time_limit,
                         end=started + LATE_PROOF_END * time_limit,
                         explain_end=started + EXPLAIN_END * time_limit)
        res = self._repaired(scene, start, grasp, time_limit, seed, late)
        if res is None and late.proof is not None:
            res = infeasible_result(scene, self.planner, self.seed if seed is None else seed,
                                    time_limit, late.proof,
                                    {"setup": 0.0, "solve": time.monotonic() - started})
            self._adopt(scene, res)
        elif res is None:
            left = max(MIN_SEARCH_TIME, time_limit - (time.monotonic() - started))
            if not added:
                res = self._run(scene, left, seed, grasp)
            else:  # a change that may leave no plan: the rest of the time to prove it
                res = self._run(scene, max(MIN_SEARCH_TIME, (1.0 - PROOF_SHARE) * left), seed,
                                grasp)
                if not res.solved and res.status != "INFEASIBLE":
                    res = _proved_infeasible(scene, res, deadline=started + time_limit)
        if robot is not None:
            res.plan.extra["observed_robot"] = list(robot)
        return res

    def _repaired(self, scene: Scene, box: tuple[float, float, float], grasp: int | None,
                  time_limit: float, seed: int | None, proof: LateProof) -> PlanResult | None:
        """The route being executed repaired from ``box`` as a result, or ``None``.

        ``proof`` is asked while the repair has no route (``None`` once it proves no plan).
        """
        if not self.repair or not self._route or \
                max(abs(a - b) for a, b in zip(self._route[-1][0], scene.goal, strict=True)) > 1e-9:
            return None  # no route, or one to another goal
        if self._checker is None:
            self._checker = self._new_checker(scene)
        checker = self._checker  # the scene's geometry: only its start differs
        if not checker.box_valid(box) or (grasp is not None and
                                          not checker.state_valid(box, grasp)):
            return None  # the search reports the invalid start
        t0 = time.perf_counter()
        deadline = time.monotonic() + time_limit / 2  # the rest for a search if it fails
        def stop() -> bool:
            return time.monotonic() > deadline

        found = repair_route(checker, self._route, box, grasp,
                             should_stop=lambda: stop() or proof(),
                             seed=self.seed if seed is None else seed,
                             config=(self.config or RegraspConfig()).repair)
        if found.path is None:  # none, or the half of the time ran out: the search's turn
            return None
        rep = found.path
        states, new = rep.states, len(rep.states) - rep.kept_edges
        config = self.config or RegraspConfig()
        if grasp is not None and states[0][1] != grasp:  # the robot walks to the route's grasp
            walk = Evaluator(checker, config.cost).walk(box, grasp, states[0][1],
                                                       should_stop=stop)
            if not walk.valid:  # invalid, or stopped: the search gets the rest of the time
                return None
            states, new = [(box, grasp), *states], new + 1
        # polished from the held grasp (a walk to another is priced as any), else from any
        states = polish(checker, states, config, should_stop=stop, new=new, start_grasp=grasp)
        t1 = time.perf_counter()
        stats = {"repaired": True, "joined_edge": rep.joined, "join_edges_tried": rep.tried,
                 "kept_edges": rep.kept_edges, "time": t1 - t0}
        res = plan_from_route(scene, checker, states, planner=self.planner,
                              seed=self.seed if seed is None else seed, time_limit=time_limit,
                              timings={"setup": 0.0, "solve": t1 - t0}, stats=stats,
                              config=self.config, bound=self.bound, search=self._search)
        self._adopt(scene, res)
        return res

    def _new_checker(self, scene: Scene) -> PivotChecker:
        """A checker of ``scene`` offered the executed plan file's motions (checked on use)."""
        checker = PivotChecker(scene, seed=self.seed)
        checker.offer(self._stored)
        return checker

    def _adopt(self, scene: Scene, res: PlanResult) -> None:
        """Take ``res`` as the last plan (its route to repair next)."""
        self.scene, self.last = scene, res
        if res.solved:  # the plan executed next: its route and motions
            self._route = route_of_plan(res.plan)
            self._plan = res.plan if self._route else None
            self._stored = stored_motions(res.plan, self._route)
            if self._checker is not None:
                self._checker.offer(self._stored)

    def _removed(self, items: Sequence[Obstacle | int]) -> tuple[Obstacle, ...]:
        out = []
        for k, o in enumerate(items):
            if isinstance(o, int) and not isinstance(o, bool):
                if not 0 <= o < len(self.scene.obstacles):
                    raise InputError(f"remove_obstacles[{k}]", o,
                                     f"no obstacle {o} (the scene has "
                                     f"{len(self.scene.obstacles)})")
                out.append(self.scene.obstacles[o])
            elif o in self.scene.obstacles:
                out.append(o)
            else:
                raise InputError(f"remove_obstacles[{k}]", repr(o)[:60],
                                 "is not an obstacle of the scene")
        return tuple(out)

    def _run(self, scene: Scene, time_limit: float, seed: int | None,
             grasp: int | None) -> PlanResult:
        if self._checker is None:
            self._checker = self._new_checker(scene)
        end = time.monotonic() + time_limit
        kw: dict[str, Any] = {"planner": self.planner, "config": self.config,
                              "seed": self.seed if seed is None else seed,
                              "checker": self._checker, "bound": self.bound,
                              "start_grasp": grasp, "late_proof": True}
        resumed = self._search is not None
        res = plan(scene, time_limit=time_limit / 2 if resumed else time_limit,
                   resume=self._search, **kw)
        left = end - time.monotonic()
        if resumed and not res.solved and left > MIN_SEARCH_TIME:
            # the old roadmaps hold no path in half the time: a new search (checks kept)
            log.info("replanning: the resumed search failed; a new one for %.1f s", left)
            res = plan(scene, time_limit=left, resume=None, **kw)
        self._search = res.search
        if res.solved and grasp is not None:
            _check_held(res.plan, grasp)
        self._adopt(scene, res)
        return res


def _check_held(p: Plan, grasp: int) -> None:
    """Raise unless plan ``p`` starts with grasp ``grasp`` (its first phase's grasp).

    Raises:
        PlanningError: ``INVALID_START``, naming the plan's first grasp.
    """
    first = p.phases[0] if p.phases else None
    held = first.from_grasp if isinstance(first, TransitPhase) else \
        first.grasp if isinstance(first, TransferPhase) else grasp
    if held != grasp:
        raise PlanningError("INVALID_START", f"the plan starts with grasp {held}, not with the "
                            f"held grasp {grasp}")


def _proved_infeasible(scene: Scene, res: PlanResult, *, deadline: float) -> PlanResult:
    """``res`` marked ``INFEASIBLE`` when the regrasp bound's relaxation proves no plan exists.

    The relaxation (:func:`~pivot_ompl.analysis.bound_cache.lower_bound`, coarse to fine)
    admits every plan from any grasp, so when it joins no start to the goal no plan exists,
    from the held grasp or any other; the result then says why and where, as
    :func:`~pivot_ompl.api.plan` does (:class:`~pivot_ompl.analysis.late_proof.LateProof`:
    ``infeasible_reason``, ``passage`` or ``turn``, the plan's ``no_plan``). Both run until
    ``deadline`` (``time.monotonic()``); stopped, or finding a path, it leaves ``res`` as it is.
    """
    if lower_bound(scene, should_stop=lambda: time.monotonic() > deadline).solvable is not False:
        return res
    late = LateProof(scene, begin=-math.inf, end=deadline)  # the bound is kept: only the place
    proof = late.proof if late() and late.proof is not None else generic(scene)
    log.info("replanning: no plan exists: %s", proof.reason)
    res.plan.extra.update(proof.fields())
    return dataclasses.replace(res, status="INFEASIBLE", infeasible_reason=proof.reason,
                               passage=proof.passage, turn=proof.turn)

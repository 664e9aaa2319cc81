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
* from a plan file (``executing=``), its stored motions: each edge's pivot rotations and each
  walk, offered to the checker (:mod:`pivot_ompl.checking.stored`), which uses one only
  after it passes the checker's own checks against the scene as it is now.

Every plan is checked as a fresh plan would be; only work is saved. Plans start at the
observed box pose; with ``grasp=k`` (the robot holds the box with grasp ``k``) a plan whose
first transfer uses another grasp starts with the walk from ``k`` to it.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Sequence
from typing import Any

from pivot_ompl.api import PlanResult, plan, plan_from_route
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import StoredMotions, stored_motions
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import InputError, PlanningError
from pivot_ompl.grasp import check_grasp
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase, plan_quality
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.repair import State, polish, repair_route, route_of, stored_route
from pivot_ompl.scene import Obstacle, Scene, check_pose, load_scene, obstacles_from_list

log = logging.getLogger(__name__)

#: Least time (s) for which a search still starts after a failed repair or resumed search.
MIN_SEARCH_TIME = 0.05


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
        self.scene = scene if isinstance(scene, Scene) else load_scene(scene)
        self.planner, self.config, self.seed, self.bound = planner, config, seed, bound
        self.repair = repair
        self.last: PlanResult | None = None
        self._route: list[State] = _route_of_plan(executing) if executing is not None else []
        self._stored = stored_motions(executing, self._route) if self._route and \
            executing is not None else StoredMotions()
        self._checker: PivotChecker | None = None
        self._search: Any = None

    def plan(self, *, time_limit: float = 30.0, seed: int | None = None) -> PlanResult:
        """Plan the scene from its start (or continue from the last observed state)."""
        return self._run(self.scene, time_limit, seed, None)

    def replan(self, *, box: Sequence[float], grasp: int | None = None,
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
            time_limit: as for :func:`pivot_ompl.api.plan` (s).
            seed: the seed (default the session's).

        Raises:
            InputError: a bad argument, naming it.
            PlanningError: the observed pose is in collision (``INVALID_START``).
        """
        start = check_pose(list(box), field="box")
        if grasp is not None:
            grasp = check_grasp(grasp, field="grasp")
        if robot is not None:
            robot = check_pose(list(robot), field="robot")
        added = obstacles_from_list([o for o in add_obstacles if isinstance(o, dict)],
                                    field="add_obstacles")
        added += tuple(o for o in add_obstacles if not isinstance(o, dict))
        gone = self._removed(remove_obstacles)
        obstacles = tuple(o for o in self.scene.obstacles if o not in gone) + added
        scene = dataclasses.replace(self.scene, start=start, obstacles=obstacles)
        if self._checker is not None and (added or gone):
            fresh = self._new_checker(scene)
            kept = fresh.adopt(self._checker, added=added, removed=gone)
            log.info("replanning: %d checked motions kept after the change", kept)
            self._checker, self._search = fresh, None  # the roadmaps grew among the old ones
        elif self._checker is not None:
            self._checker.scene = scene
        started = time.monotonic()
        res = self._repaired(scene, start, grasp, time_limit, seed)
        if res is None:
            res = self._run(scene, max(MIN_SEARCH_TIME, time_limit - (time.monotonic() - started)),
                            seed, grasp)
        if robot is not None:
            res.plan.extra["observed_robot"] = list(robot)
        return res

    def _repaired(self, scene: Scene, box: tuple[float, float, float], grasp: int | None,
                  time_limit: float, seed: int | None) -> PlanResult | None:
        """The route being executed repaired from ``box`` as a result, or ``None``."""
        if not self.repair or not self._route or \
                max(abs(a - b) for a, b in zip(self._route[-1][0], scene.goal, strict=True)) > 1e-9:
            return None  # no route, or one to another goal
        if self._checker is None:
            self._checker = self._new_checker(scene)
        checker = self._checker
        checker.scene = scene
        if not checker.box_valid(box):
            return None  # the search reports the invalid start
        t0 = time.perf_counter()
        deadline = time.monotonic() + time_limit / 2  # the rest for a search if it fails
        def stop() -> bool:
            return time.monotonic() > deadline

        rep = repair_route(checker, self._route, box, grasp, should_stop=stop,
                           seed=self.seed if seed is None else seed)
        if rep is None:
            return None
        cfg = self.config or RegraspConfig()
        # a route that starts with the held grasp is polished from it (a walk to another is
        # priced, not added after); one that starts with another from any (a walk is needed)
        states = polish(checker, rep.states, cfg, should_stop=stop,
                        new=len(rep.states) - rep.kept_edges,
                        held=grasp is not None and rep.states[0][1] == grasp)
        if grasp is not None and states[0][1] != grasp:  # the robot walks to the route's grasp
            if not checker.transit(box, grasp, states[0][1], should_stop=stop).valid:
                return None
            states = [(box, grasp), *states]
        t1 = time.perf_counter()
        stats = {"repaired": True, "joined_edge": rep.joined, "join_edges_tried": rep.tried,
                 "kept_edges": rep.kept_edges, "time": t1 - t0}
        res = plan_from_route(scene, checker, states, planner=self.planner,
                              seed=self.seed if seed is None else seed, time_limit=time_limit,
                              timings={"setup": 0.0, "solve": t1 - t0}, stats=stats,
                              config=self.config, bound=self.bound, search=self._search)
        self._adopt(scene, res, grasp)
        return res

    def _new_checker(self, scene: Scene) -> PivotChecker:
        """A checker of ``scene`` offered the executed plan file's motions (checked on use)."""
        checker = PivotChecker(scene, seed=self.seed)
        checker.offer(self._stored)
        return checker

    def _adopt(self, scene: Scene, res: PlanResult, grasp: int | None) -> None:
        """Take ``res`` as the last plan (its route to repair next)."""
        self.scene, self.last = scene, res
        if res.solved:
            self._route = _route_of_plan(res.plan)
            if grasp is not None:
                self._hold(res, grasp)

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
                              "checker": self._checker, "bound": self.bound}
        resumed = self._search is not None
        res = plan(scene, time_limit=time_limit / 2 if resumed else time_limit,
                   resume=self._search, **kw)
        left = end - time.monotonic()
        if resumed and not res.solved and left > MIN_SEARCH_TIME:
            # the old roadmaps hold no path in half the time: a new search (checks kept)
            log.info("replanning: the resumed search failed; a new one for %.1f s", left)
            res = plan(scene, time_limit=left, resume=None, **kw)
        self._search = res.search
        self._adopt(scene, res, grasp)
        return res

    def _hold(self, res: PlanResult, grasp: int) -> None:
        """Start the plan with the walk from the held grasp to its first transfer's grasp."""
        phases = res.plan.phases
        first = next((p for p in phases if isinstance(p, TransferPhase)), None)
        if first is None or phases[0].type == "transit" or first.grasp == grasp:
            return
        assert self._checker is not None  # noqa: S101 - set by _run
        walk = self._checker.transit(res.plan.start, grasp, first.grasp)
        if not walk.valid:
            raise PlanningError("INVALID_START", f"the robot cannot walk from grasp {grasp} to "
                                f"grasp {first.grasp} round the box at {list(res.plan.start)}")
        res.plan.phases.insert(0, TransitPhase(grasp, first.grasp, walk.robot_path,
                                               res.plan.start))
        self._route.insert(0, (res.plan.start, grasp))
        res.plan.extra["route"] = stored_route(self._route)
        q = res.plan.extra.get("quality")
        if q is not None:  # the block of the plan as it now is
            res.plan.extra["quality"] = plan_quality(
                res.plan, regrasps_lower_bound=q["regrasps_lower_bound"],
                shortest_route=q["shortest_route"], costs=CostModel(regrasp=q["regrasp_cost"]))



def _route_of_plan(p: Plan) -> list[State]:
    """A plan's route (its ``route`` field), ``[]`` for a plan without one."""
    raw = p.extra.get("route")
    if not isinstance(raw, list) or len(raw) < 2:
        return []
    try:
        return route_of(raw)
    except (TypeError, ValueError, IndexError):
        log.warning("the plan's route field is malformed: not repaired")
        return []

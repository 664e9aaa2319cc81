"""What :func:`pivot_ompl.api.plan` returns: :class:`PlanResult`, and the plans of its outcomes.

A solved search's path as a plan (:func:`path_plan`), and the results of a search that never
ran (:func:`stopped_in_setup`) or that the relaxation proved cannot succeed
(:func:`infeasible_result`).
"""

from __future__ import annotations

import logging
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pivot_ompl.analysis.late_proof import NoPlan
from pivot_ompl.analysis.passage import Passage
from pivot_ompl.analysis.turning import TurningPlace
from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.state import read_state
from pivot_ompl.errors import PlanningError
from pivot_ompl.planfile import Plan
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.repair import stored_route
from pivot_ompl.scene import Scene, scene_digest

log = logging.getLogger(__name__)


@dataclass
class PlanResult:
    """The outcome of :func:`plan`.

    Attributes:
        status: OMPL's status name (``"EXACT_SOLUTION"``, ``"TIMEOUT"``, ...).
        plan: the plan (``status "none"`` and no phases when nothing was found).
        planner: planner name.
        seed: seed used.
        time_limit: time limit (s).
        timings: seconds spent in ``setup``, ``solve``, ``convert`` and (solved plans)
            ``bound``, fetching or computing the quality block's lower bounds (within the
            time limit, see :func:`plan`; once per scene, then cached).
        roadmap: planner figures (roadmap sizes, critical configurations...), if any.
        motion_checks: counts of valid and invalid motions and cache hits.
        search: the regrasp planner's roadmaps (for plotting), ``None`` for other planners.
        scene: the scene planned (read from its file when :func:`plan` was given a path;
            ``None`` when the time limit ran out while it was read).
        infeasible_reason: with status ``INFEASIBLE`` (the regrasp bound's relaxation proves
            that no plan exists), one line saying why: which passage, where, its width, what
            needs what (:mod:`pivot_ompl.analysis.passage`); ``None`` otherwise.
        passage: with ``INFEASIBLE``, the passage that blocks every plan, if one does.
        turn: with ``INFEASIBLE``, the place where the held box cannot turn, if that is why
            (:mod:`pivot_ompl.analysis.turning`).
    """

    status: str
    plan: Plan
    planner: str
    seed: int
    time_limit: float
    timings: dict[str, float] = field(default_factory=dict)
    roadmap: dict[str, Any] = field(default_factory=dict)
    motion_checks: dict[str, int] = field(default_factory=dict)
    search: RegraspSearch | None = field(default=None, repr=False)
    scene: Scene | None = field(default=None, repr=False)
    infeasible_reason: str | None = None
    passage: Passage | None = field(default=None, repr=False)
    turn: TurningPlace | None = field(default=None, repr=False)

    @property
    def solved(self) -> bool:
        """Whether an exact solution was found."""
        return self.status == "EXACT_SOLUTION"

    @property
    def pivots(self) -> int:
        """Number of pivot rotations in the plan."""
        return self.plan.pivots

    @property
    def regrasps(self) -> int:
        """Number of regrasps (transit phases) in the plan."""
        return self.plan.regrasps

    def to_json(self, path: str | Path) -> Path:
        """Write the plan as ``pivot-plan/1`` (with planner, seed, timings as extra fields).

        Raises:
            PlanningError: no path reaches the goal (``TIMEOUT``...): nothing is written.
        """
        if not self.solved:
            raise PlanningError(self.status, "no plan reaches the goal, nothing written "
                                "(an approximate path is not a plan)")
        return self.plan.to_json(path)


def stopped_in_setup(scene: Scene | str | os.PathLike, planner: str, seed: int,
                      time_limit: float, what: str, spent: float) -> PlanResult:
    """The ``TIMEOUT`` result of a time limit reached before the search (``what`` stopped)."""
    log.warning("the %.4g s limit ran out while %s: no search", time_limit, what)
    extra = {"planner": planner, "seed": seed, "time_limit": time_limit, "stopped": what}
    if isinstance(scene, Scene):
        m = scene.model
        empty = Plan(scene.name, "none", m.object_size, m.robot_footprint, m.standoff,
                     scene.alpha_max, scene.start, [], extra, robot_model=scene.robot_model)
    else:  # stopped while reading the scene: nothing of it is known
        empty = Plan(Path(scene).stem, "none", (0.0, 0.0, 0.0), (0.0, 0.0), 0.0, 0.0,
                     (0.0, 0.0, 0.0), [], extra)
    timings = {"setup": spent, "solve": 0.0, "convert": 0.0}
    return PlanResult("TIMEOUT", empty, planner, seed, time_limit, timings,
                      scene=scene if isinstance(scene, Scene) else None)


def infeasible_result(scene: Scene, planner: str, seed: int, time_limit: float, proof: NoPlan,
                      timings: dict[str, float]) -> PlanResult:
    """The ``INFEASIBLE`` result of a scene the relaxation proves has no plan (``proof``).

    Its plan has no phases and records the proof's fields (``no_plan``, ``passage`` or
    ``turn``); ``timings`` gets ``convert``.
    """
    timings = {**timings, "convert": 0.0}
    log.info("%s: no plan exists (proven by the relaxation in %.2f s)", scene.name,
             sum(timings.values()))
    extra = {"planner": planner, "seed": seed, "time_limit": time_limit, **scene_record(scene),
             **proof.fields()}
    empty = path_plan(scene, None, "INFEASIBLE", extra, simplify=False)
    return PlanResult("INFEASIBLE", empty, planner, seed, time_limit, timings, scene=scene,
                      infeasible_reason=proof.reason, passage=proof.passage, turn=proof.turn)


def scene_record(scene: Scene) -> dict[str, Any]:
    """What a plan records of its scene: its digest and, planned from a file, its path."""
    out: dict[str, Any] = {"scene_sha256": scene_digest(scene)}
    if scene.source and Path(scene.source).is_file():
        out["scene_path"] = str(Path(scene.source).resolve())
    return out


def path_plan(scene: Scene, problem: Any, status: str, extra: dict[str, Any], *,
                 simplify: bool, end: float = math.inf) -> Plan:
    """The solution path as a plan (``status "none"``, no phases: none), shortened to ``end``."""
    if status == "EXACT_SOLUTION" and (ss := problem.setup).haveExactSolutionPath():
        if simplify:
            ss.simplifySolution()
        path = ss.getSolutionPath()
        states = [read_state(path.getState(i)) for i in range(path.getStateCount())]
        return path_to_plan(scene, problem.checker, states, extra={
            **extra, "route": stored_route(states)}, should_stop=lambda: time.monotonic() >= end)
    return Plan(scene.name, "none", scene.model.object_size, scene.model.robot_footprint,
                scene.model.standoff, scene.alpha_max, scene.start, [], extra,
                robot_model=scene.robot_model)

"""The problem object: one scene's space, space information, validators and ``SimpleSetup``.

:func:`make_problem` builds the OMPL objects of a scene; :func:`make_setup` adds the start and
goal states. The :class:`PivotProblem` owns every Python object OMPL refers to (validators,
projection, setup), so nothing private is stored on OMPL objects: keep the problem alive as
long as any of its OMPL objects is used.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from pivot_ompl.base.motion_validator import PivotMotionValidator
from pivot_ompl.base.space import GRASP_WEIGHT, ensure_projection, make_space
from pivot_ompl.base.state import write_state
from pivot_ompl.base.validity_checker import PivotValidityChecker
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import InputError, PlanningError, require_type
from pivot_ompl.grasp import check_grasp
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose


@dataclass
class PivotProblem:
    """Everything OMPL needs for one scene, owned together.

    Attributes:
        scene: the planning problem.
        space: the compound state space.
        si: its space information (validity checker and motion validator set).
        checker: the pure-Python validity core shared by validators and planners.
        validity: the OMPL ``StateValidityChecker``.
        motion: the OMPL ``MotionValidator``.
        projection: the default projection registered for KPIECE-like planners, if any.
        ss: the ``og.SimpleSetup`` with start and goal (set by :func:`make_setup`).
        start_grasps: the grasps valid at the start (set by :func:`make_setup`).
        goal_grasps: the grasps valid at the goal (set by :func:`make_setup`).
    """

    scene: Scene
    space: ob.CompoundStateSpace
    si: ob.SpaceInformation
    checker: PivotChecker
    validity: PivotValidityChecker
    motion: PivotMotionValidator
    projection: Any = None
    ss: og.SimpleSetup | None = None
    start_grasps: tuple[int, ...] = ()
    goal_grasps: tuple[int, ...] = ()

    def alloc(self, pose: Pose, grasp: int) -> Any:
        """A new state of ``si`` set to ``(pose, grasp)`` (freed with the space information)."""
        s = self.si.allocState()
        write_state(s, pose, grasp)
        return s

    @property
    def setup(self) -> og.SimpleSetup:
        """The ``SimpleSetup`` (raises if the problem was built by :func:`make_problem` alone)."""
        if self.ss is None:
            raise PlanningError("NO_SETUP", "built without start and goal: use make_setup()")
        return self.ss


def make_problem(scene: Scene, *, seed: int = 0, grasp_weight: float = GRASP_WEIGHT,
                 checker: PivotChecker | None = None,
                 should_stop: Callable[[], bool] | None = None) -> PivotProblem:
    """Build the space, space information, validity checker and motion validator of a scene.

    Raises:
        Interrupted: ``should_stop()`` became true while the checker was built.
    """
    checker = checker or PivotChecker(scene, seed=seed, should_stop=should_stop)
    space = make_space(scene, grasp_weight=grasp_weight)
    si = ob.SpaceInformation(space)
    validity = PivotValidityChecker(si, checker)
    motion = PivotMotionValidator(si, checker)
    si.setStateValidityChecker(validity)
    si.setMotionValidator(motion)
    si.setup()
    problem = PivotProblem(scene, space, si, checker, validity, motion)
    problem.projection = ensure_projection(space)
    return problem


def _check_setup_arguments(scene: Any, seed: Any, grasp_weight: Any, start_grasp: Any,
                           goal_grasp: Any, checker: Any, should_stop: Any) -> None:
    """Validate :func:`make_setup`'s arguments, naming the one at fault."""
    require_type(scene, Scene, "scene", "a Scene (pivot_ompl.load_scene(name) gives one)")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**32 - 1:
        raise InputError("seed", seed, f"must be an integer in [0, {2**32 - 2}]")
    if isinstance(grasp_weight, bool) or not isinstance(grasp_weight, int | float) or \
            not 0 <= grasp_weight < math.inf:
        raise InputError("grasp_weight", grasp_weight, "must be a finite number >= 0")
    for name, g in (("start_grasp", start_grasp), ("goal_grasp", goal_grasp)):
        if g is not None:
            check_grasp(g, field=name)
    if checker is not None and not isinstance(checker, PivotChecker):
        raise InputError("checker", type(checker).__name__, "must be a PivotChecker or None")
    if should_stop is not None and not callable(should_stop):
        raise InputError("should_stop", type(should_stop).__name__, "must be callable or None")


def make_setup(scene: Scene, *, seed: int = 0, grasp_weight: float = GRASP_WEIGHT,
               start_grasp: int | None = None, goal_grasp: int | None = None,
               checker: PivotChecker | None = None,
               should_stop: Callable[[], bool] | None = None) -> PivotProblem:
    """The :class:`PivotProblem` of ``scene`` with its ``og.SimpleSetup`` (``problem.ss``).

    The start states are the start pose with every grasp valid there (or ``start_grasp``
    alone); the goal is a ``GoalStates`` holding the goal pose with every valid grasp (or
    ``goal_grasp`` alone). ``checker``: a checker of the same geometry to validate through
    (its caches of checked motions are reused; a planning session passes its own).

    ``should_stop``: polled while the checker's collision world is built (a time limit).

    Raises:
        PlanningError: no grasp is valid at the start, or the box is free there but not the
            robot holding it with ``start_grasp`` (``INVALID_START``), or none at the goal
            (``INVALID_GOAL``).
        Interrupted: ``should_stop()`` became true.
    """
    _check_setup_arguments(scene, seed, grasp_weight, start_grasp, goal_grasp, checker,
                           should_stop)
    problem = make_problem(scene, seed=seed, grasp_weight=grasp_weight, checker=checker,
                           should_stop=should_stop)
    ss = og.SimpleSetup(problem.si)
    ck = problem.checker
    starts = [g for g in range(4) if ck.state_valid(scene.start, g)]
    goals = [g for g in range(4) if ck.state_valid(scene.goal, g)]
    held = [g for g in starts if g == start_grasp] if start_grasp is not None else starts
    if goal_grasp is not None:
        goals = [g for g in goals if g == goal_grasp]
    if starts and not held:  # the box is free, the robot holding it with that grasp is not
        raise PlanningError("INVALID_START", f"the held grasp {start_grasp} is not valid at "
                            f"start {list(scene.start)}: " + ck.explain(scene.start))
    if not starts:
        raise PlanningError("INVALID_START", f"no valid grasp at start {list(scene.start)}: "
                            + ck.explain(scene.start))
    if not goals:
        raise PlanningError("INVALID_GOAL", f"no valid grasp at goal {list(scene.goal)}: "
                            + ck.explain(scene.goal))
    starts = held
    for g in starts:
        ss.addStartState(problem.alloc(scene.start, g))
    goal = ob.GoalStates(problem.si)
    for g in goals:
        goal.addState(problem.alloc(scene.goal, g))
    ss.setGoal(goal)
    problem.ss = ss
    problem.start_grasps = tuple(starts)
    problem.goal_grasps = tuple(goals)
    return problem

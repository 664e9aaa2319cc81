"""The OMPL state space: Reeds-Shepp SE(2) of the box x discrete grasp index.

``CompoundStateSpace`` = ``ReedsSheppStateSpace(turning_radius)`` (component 0) x
``DiscreteStateSpace(0, 3)`` (component 1).

Component 0 holds the **object pose** ``(x, y, yaw)`` (see :mod:`pivot_ompl.grasp`), not the
car. For grasp ``k`` the Reeds-Shepp car that is actually steered is the supporting-edge centre
``car = (x - half_k cos h, y - half_k sin h, h)`` with heading ``h = yaw + k pi/2``
(:meth:`BoxGraspModel.car_pose`); the motion validator converts both ends to cars of the
state's grasp before steering. OMPL's own ``distance``/``interpolate`` act on the object pose
directly (a car rigidly attached at the box centre with heading ``yaw``): a consistent metric
for nearest-neighbour queries and extension, while every edge is validated with the true car.

The distance is ``RS(object poses) + grasp_weight * |k1 - k2|``; interpolating the discrete part
rounds, so the motion validator defines what a grasp change is: the same object pose (to
round-off) and a different grasp.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from .checker import PivotChecker
from .scene import Scene
from .se2 import Pose

#: OMPL's ``StateSpace::SanityChecks`` bits (not exported by the nanobind module).
STATESPACE_DISTANCE_DIFFERENT_STATES = 1 << 1
STATESPACE_DISTANCE_SYMMETRIC = 1 << 2
STATESPACE_INTERPOLATION = 1 << 3
STATESPACE_TRIANGLE_INEQUALITY = 1 << 4
STATESPACE_DISTANCE_BOUND = 1 << 5
STATESPACE_RESPECT_BOUNDS = 1 << 6
STATESPACE_ENFORCE_BOUNDS_NO_OP = 1 << 7
STATESPACE_SERIALIZATION = 1 << 8
#: The checks OMPL runs for Reeds-Shepp spaces: all but interpolation (relaxed as OMPL's own
#: ``ReedsSheppStateSpace::sanityChecks`` does), with ``eps = 0.1``.
SANITY_FLAGS = (STATESPACE_DISTANCE_DIFFERENT_STATES | STATESPACE_DISTANCE_SYMMETRIC
                | STATESPACE_TRIANGLE_INEQUALITY | STATESPACE_DISTANCE_BOUND
                | STATESPACE_RESPECT_BOUNDS | STATESPACE_ENFORCE_BOUNDS_NO_OP
                | STATESPACE_SERIALIZATION)


def sanity_checks(space: ob.StateSpace) -> None:
    """Run OMPL's ``sanityChecks`` on ``space`` with the Reeds-Shepp relaxation (raises)."""
    space.sanityChecks(2.220446049250313e-16, 0.1, SANITY_FLAGS)


#: Default weight of the grasp component in OMPL's distance (m per grasp index step).
GRASP_WEIGHT = 1.0


def make_space(scene: Scene, *, grasp_weight: float = GRASP_WEIGHT) -> ob.CompoundStateSpace:
    """The compound space of ``scene`` (bounds from the scene, the given grasp weight)."""
    space = ob.CompoundStateSpace()
    rs = ob.ReedsSheppStateSpace(scene.turning_radius)
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, scene.bounds[0])
    bounds.setLow(1, scene.bounds[1])
    bounds.setHigh(0, scene.bounds[2])
    bounds.setHigh(1, scene.bounds[3])
    rs.setBounds(bounds)
    space.addSubspace(rs, 1.0)
    space.addSubspace(ob.DiscreteStateSpace(0, 3), grasp_weight)
    space.setName("PivotSpace")
    space.lock()
    return space


def read_state(state: Any) -> tuple[Pose, int]:
    """``(object pose, grasp)`` of a compound state."""
    se2 = state[0]
    return (se2.getX(), se2.getY(), se2.getYaw()), int(state[1].value)


def write_state(state: Any, pose: Pose, grasp: int) -> None:
    """Set a compound state to ``(pose, grasp)``."""
    state[0].setXY(pose[0], pose[1])
    state[0].setYaw(pose[2])
    state[1].value = int(grasp)


@dataclass
class PivotProblem:
    """Everything OMPL needs for one scene, kept alive together.

    Attributes:
        scene: the planning problem.
        space: the compound state space.
        si: its space information (validity checker and motion validator set).
        checker: the pure-Python validity core shared by validators and planners.
        validity: the OMPL ``StateValidityChecker``.
        motion: the OMPL ``MotionValidator``.
    """

    scene: Scene
    space: ob.CompoundStateSpace
    si: ob.SpaceInformation
    checker: PivotChecker
    validity: Any
    motion: Any
    projection: Any = None

    def alloc(self, pose: Pose, grasp: int) -> Any:
        """A new state of ``si`` set to ``(pose, grasp)`` (freed with the space information)."""
        s = self.si.allocState()
        write_state(s, pose, grasp)
        return s


def ensure_projection(space: Any) -> Any:
    """Give the compound space a default projection if it has none (KPIECE1 & co. need one).

    The projection is OMPL's ``SubspaceProjectionEvaluator`` on the Reeds-Shepp component's
    default projection (x, y cells). Returns it (keep it alive) or ``None``.
    """
    if space.hasDefaultProjection():
        return None
    proj = ob.SubspaceProjectionEvaluator(space, 0,
                                          space.getSubspace(0).getDefaultProjection())
    proj.setup()  # the space was set up before: set the projection up (or printing it crashes)
    space.registerDefaultProjection(proj)
    return proj


def make_problem(scene: Scene, *, seed: int = 0, grasp_weight: float = GRASP_WEIGHT,
                 checker: PivotChecker | None = None) -> PivotProblem:
    """Build the space, space information, validity checker and motion validator of a scene."""
    from .motion_validator import PivotMotionValidator
    from .validity import PivotValidityChecker

    space = make_space(scene, grasp_weight=grasp_weight)
    si = ob.SpaceInformation(space)
    checker = checker or PivotChecker(scene, seed=seed)
    validity = PivotValidityChecker(si, checker)
    motion = PivotMotionValidator(si, checker)
    si.setStateValidityChecker(validity)
    si.setMotionValidator(motion)
    si.setup()
    problem = PivotProblem(scene, space, si, checker, validity, motion)
    problem.projection = ensure_projection(space)
    return problem


def make_space_information(scene: Scene, *, seed: int = 0,
                           grasp_weight: float = GRASP_WEIGHT) -> ob.SpaceInformation:
    """The ``SpaceInformation`` of ``scene`` with our validity checker and motion validator.

    The Python validators are kept alive by an attribute of the returned object.
    """
    problem = make_problem(scene, seed=seed, grasp_weight=grasp_weight)
    si = problem.si
    si._pivot_problem = problem  # keep the Python validators alive with it
    return si


def make_setup(scene: Scene, *, seed: int = 0, grasp_weight: float = GRASP_WEIGHT,
               start_grasp: int | None = None, goal_grasp: int | None = None) -> og.SimpleSetup:
    """An ``og.SimpleSetup`` for ``scene``: start and goal object poses, any grasp.

    The start state uses ``start_grasp`` (default: the first grasp valid at the start); the
    goal is a ``GoalStates`` holding the goal pose with every valid grasp, unless
    ``goal_grasp`` is given. The :class:`PivotProblem` is at ``ss._pivot_problem``.

    Raises:
        PlanningError: no grasp is valid at the start (``INVALID_START``) or goal
            (``INVALID_GOAL``).
    """
    from .errors import PlanningError

    problem = make_problem(scene, seed=seed, grasp_weight=grasp_weight)
    ss = og.SimpleSetup(problem.si)
    ss._pivot_problem = problem
    ck = problem.checker
    starts = [g for g in range(4) if ck.state_valid(scene.start, g)]
    goals = [g for g in range(4) if ck.state_valid(scene.goal, g)]
    if start_grasp is not None:
        starts = [g for g in starts if g == start_grasp]
    if goal_grasp is not None:
        goals = [g for g in goals if g == goal_grasp]
    if not starts:
        raise PlanningError("INVALID_START", f"no valid grasp at start {list(scene.start)}: "
                            + ck.explain(scene.start))
    if not goals:
        raise PlanningError("INVALID_GOAL", f"no valid grasp at goal {list(scene.goal)}: "
                            + ck.explain(scene.goal))
    ss.addStartState(problem.alloc(scene.start, starts[0]))
    goal = ob.GoalStates(problem.si)
    for g in goals:
        goal.addState(problem.alloc(scene.goal, g))
    ss.setGoal(goal)
    return ss

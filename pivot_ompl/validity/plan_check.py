"""``pivot-ompl check``: the project's own validator of a ``pivot-plan/1`` plan.

Checks chain continuity (each step starts where the previous ended, each phase where the
previous one left robot and box), pivots at the supporting edge's ends, angle bounds, the rigid
grasp (robot pose = grasp pose of the object pose), start and goal, and, with a scene,
bounds and collisions of every rotation's swept box and holding robot (its footprint, arms
and the inclined box's overhang: ``CollisionWorld.held_distance``) and of every walk (the
walking footprint).

With a scene, the scene is the only authority: the box size, the robot's footprint and
standoff and ``alpha_max`` are the scene's; the plan's copies of them are compared and a
mismatch is a problem. The plan must start at the scene's start, end at its goal and have
status ``exact``. A rotation over ``alpha_max`` or a pose outside the scene's bounds is reported
without sweeping it, so absurd numbers cost no time.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import profile_of
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.validity.certify import SWEEP_TOLERANCE, certify
from pivot_ompl.validity.collision import CollisionWorld

#: Tolerance on continuity and exact arrival (m and rad).
POSE_TOL = 1e-6
#: Problems after which a check stops (a plan that wrong needs no more).
MAX_PROBLEMS = 1000
#: A body may touch the floor's edge (m): round-off of a pose on it is not leaving it.
EDGE_SLACK = 1e-9


@dataclass
class PlanCheckReport:
    """Outcome of :func:`check_plan`: ``ok`` and the list of problems found."""

    problems: list[str] = field(default_factory=list)
    steps: int = 0
    transits: int = 0

    @property
    def ok(self) -> bool:
        """No problem found."""
        return not self.problems


def _close(a: Pose, b: Pose, tol: float = POSE_TOL) -> bool:
    return (abs(a[0] - b[0]) <= tol and abs(a[1] - b[1]) <= tol
            and abs(wrap_angle(a[2] - b[2])) <= tol)


def check_plan(plan: Plan, scene: Scene | None = None, *, collisions: bool = True,
               tolerance: float = SWEEP_TOLERANCE, exact: bool = False) -> PlanCheckReport:
    """Validate ``plan`` (optionally against ``scene``); see the module docstring.

    The poses checked are computed, never read: from the scene's start (the plan's without
    a scene), each rotation turns the computed supporting edge about its computed end nearest
    the written pivot by the written angle. A written pose is only compared with the computed
    one (within :data:`POSE_TOL`), so errors within the tolerance cannot add up along a plan;
    the goal is compared with the computed end.

    Every sweep accepts a motion whose bodies may come within ``tolerance`` of an obstacle
    between two checked samples; with ``exact`` a motion passes only if it is proven to keep
    the clearance at every parameter (:func:`~pivot_ompl.validity.certify.certify` with
    ``exact=True``, the planner's own certificate): a plan that dips by less than the
    tolerance between samples is then refused.
    """
    rep = PlanCheckReport()
    world = CollisionWorld.from_scene(scene) if scene is not None else None
    if scene is not None:
        model = scene.model
        amax = scene.alpha_max
        _check_scene_match(rep, plan, scene)
        obj = scene.start
    else:
        model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff,
                              profile_of(plan.robot_model).height, plan.robot_model)
        amax = plan.alpha_max
        obj = plan.start
    sweep_all = world is not None and collisions
    robot: Pose | None = None
    for pi, ph in enumerate(plan.phases):
        where = f"phases[{pi}]"
        if isinstance(ph, TransferPhase):
            g = ph.grasp
            if not _close(ph.object_start, obj):
                rep.problems.append(f"{where}: object_start {ph.object_start} is not where the "
                                    f"box was left {obj}")
            if robot is not None and not _close(ph.robot_start, robot):
                rep.problems.append(f"{where}: robot_start {ph.robot_start} is not where the "
                                    f"robot was left {robot}")
            if not _close(ph.robot_start, model.robot_pose(obj, g)):
                rep.problems.append(f"{where}: robot_start is not grasp {g} of the object")
            car = model.car_pose(obj, g)
            for si, st in enumerate(ph.steps):
                w = f"{where}.steps[{si}]"
                rep.steps += 1
                sweep = sweep_all
                if not abs(st.angle) <= amax + 1e-9:
                    rep.problems.append(f"{w}: |angle| {abs(st.angle):.6g} > alpha_max {amax:.6g}")
                    sweep = False  # not a rotation the robot may make: no time on sweeping it
                pivot = min(model.pivots(car, g), key=lambda e: math.hypot(
                    st.pivot[0] - e[0], st.pivot[1] - e[1]))
                if not math.hypot(st.pivot[0] - pivot[0], st.pivot[1] - pivot[1]) <= POSE_TOL:
                    rep.problems.append(f"{w}: pivot {st.pivot} is not an end of the "
                                        "supporting edge")
                    sweep = False  # its sweep could span the whole floor: not swept
                new_car = rotate_about(car, pivot, st.angle)
                computed = model.object_from_car(new_car, g)
                if not _close(st.object, computed):
                    rep.problems.append(f"{w}: object {st.object} is not the rotation's result "
                                        f"{computed}")
                if not _close(st.robot, model.robot_pose(computed, g)):
                    rep.problems.append(f"{w}: robot {st.robot} is not rigidly at grasp {g}")
                if sweep and world is not None:
                    _check_rotation(rep, w, world, model, car, pivot, st.angle, g, tolerance,
                                    exact)
                car, obj = new_car, computed  # the chain goes on from the computed pose
                if len(rep.problems) > MAX_PROBLEMS:
                    return rep
            robot = model.robot_pose(obj, g)
        elif isinstance(ph, TransitPhase):
            rep.transits += 1
            robot = _check_transit(rep, where, ph, world if sweep_all else None, model, obj,
                                   robot, tolerance, exact)
        if len(rep.problems) > MAX_PROBLEMS:
            return rep
    if scene is not None and not _close(obj, scene.goal):
        rep.problems.append(f"the plan's rotations end the box at {obj}, not at the scene's "
                            f"goal {scene.goal}")
    return rep


def _check_transit(rep: PlanCheckReport, where: str, ph: TransitPhase,
                   world: CollisionWorld | None, model: BoxGraspModel, obj: Pose,
                   robot: Pose | None, tolerance: float, exact: bool) -> Pose:
    """Check a walk round the resting box at ``obj``; return where it leaves the robot."""
    path = ph.robot_path
    if not _close(ph.object_pose, obj):
        rep.problems.append(f"{where}: object_pose {ph.object_pose} is not where the box "
                            f"rests {obj}")
    if not _close(path[0], model.robot_pose(obj, ph.from_grasp)):
        rep.problems.append(f"{where}: walk does not start at grasp {ph.from_grasp}")
    if robot is not None and not _close(path[0], robot):
        rep.problems.append(f"{where}: walk does not start where the robot was left")
    if not _close(path[-1], model.robot_pose(obj, ph.to_grasp)):
        rep.problems.append(f"{where}: walk does not end at grasp {ph.to_grasp}")
    if world is not None:
        outside = [k for k, q in enumerate(path)
                   if not world.bounds_margin(model.robot_corners(q)) >= -1e-9]
        if outside:  # reported once, not swept: an absurd coordinate costs no time
            rep.problems.append(f"{where}.robot_path[{outside[0]}]: the robot leaves "
                                "the bounds")
            return path[-1]
        for k, (a, b) in enumerate(zip(path, path[1:], strict=False)):
            _check_walk(rep, f"{where}.robot_path[{k}]", world, model, a, b, obj, tolerance,
                        exact)
    return path[-1]


def _check_scene_match(rep: PlanCheckReport, plan: Plan, scene: Scene) -> None:
    """The plan claims the goal, starts and ends at the scene's poses, with its sizes."""
    model = scene.model
    if plan.status != "exact":
        rep.problems.append(f"plan status is {plan.status!r}, not 'exact': it does not "
                            "claim to reach the goal")
    if not _close(plan.start, scene.start):
        rep.problems.append(f"plan starts at {plan.start}, scene start is {scene.start}")
    if not _close(plan.object_end, scene.goal):  # exactly, not its half turn
        rep.problems.append(f"plan ends at {plan.object_end}, scene goal is {scene.goal}")
    for name, a, b in (("object_size", plan.object_size, model.object_size),
                       ("robot_footprint", plan.robot_footprint, model.robot_footprint),
                       ("standoff", (plan.standoff,), (model.standoff,)),
                       ("alpha_max", (plan.alpha_max,), (scene.alpha_max,))):
        if any(abs(x - y) > 1e-9 for x, y in zip(a, b, strict=True)):
            rep.problems.append(f"plan's {name} {list(a)} differs from the scene's {list(b)}")
    if plan.robot_model != scene.robot_model:
        rep.problems.append(f"plan's robot_model {plan.robot_model!r} differs from the "
                            f"scene's {scene.robot_model!r}")


def _check_rotation(rep: PlanCheckReport, where: str, world: CollisionWorld,
                    model: BoxGraspModel, car: Pose, pivot: tuple[float, float], angle: float,
                    g: int, tol: float, exact: bool) -> None:
    """Sweep the box and the holding robot along a rotation: obstacles and the floor's edge.

    Both are one clearance (the smaller of the distance to the obstacles and of the corners'
    to the floor's sides), certified along the whole rotation (:func:`certify`): no sample
    spacing can let a body out of the floor between two samples.
    """
    def held_corners(robot: Pose) -> list[tuple[float, float]]:
        return model.held_corners(robot, g)

    def held_distance(robot: Pose) -> float:
        return world.held_distance(robot, g)

    for body, conv, corners, dist in (
            ("box", model.object_from_car, model.object_corners, world.box_distance),
            ("robot", model.robot_from_car, held_corners, held_distance)):
        reach = max(math.hypot(x - pivot[0], y - pivot[1]) for x, y in corners(conv(car, g)))

        def at(s: float, conv: Callable[[Pose, int], Pose] = conv,
               corners: Callable[[Pose], list[tuple[float, float]]] = corners,
               dist: Callable[[Pose], float] = dist) -> tuple[float, float]:
            p = conv(rotate_about(car, pivot, s * angle), g)
            return (world.bounds_margin(corners(p)) + EDGE_SLACK,
                    dist(p) if world.has_obstacles else math.inf)

        res = certify(lambda s: min(at(s)), reach * abs(angle), tolerance=tol, exact=exact)
        if not res.valid:
            edge, hit = at(res.first_collision)
            what = ("leaves the bounds" if edge <= 0 else "collides" if hit <= 0
                    else "is not proven clear")
            rep.problems.append(f"{where}: {body} {what} (rotation fraction "
                                f"{res.first_collision:.3f})")


def _check_walk(rep: PlanCheckReport, where: str, world: CollisionWorld, model: BoxGraspModel,
                a: Pose, b: Pose, obj: Pose, tol: float, exact: bool) -> None:
    """Sweep a walk's segment (a turn in place included): obstacles, the box, the floor's edge.

    The clearance certified is the smaller of the distances to the obstacles and the resting
    box and of the body's corners to the floor's sides, so the turning body cannot swing out
    of the floor between two checked poses.
    """
    dyaw = wrap_angle(b[2] - a[2])
    lip = math.hypot(b[0] - a[0], b[1] - a[1]) + model.robot_radius() * abs(dyaw)

    def pose(s: float) -> Pose:
        return (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw)

    def clearance(s: float) -> float:
        p = pose(s)
        return min(world.bounds_margin(model.robot_corners(p)) + EDGE_SLACK,
                   world.robot_distance(p),
                   world.robot_box_distance(p, obj))

    res = certify(clearance, max(lip, 1e-12), tolerance=tol, exact=exact)
    if not res.valid:
        edge = world.bounds_margin(model.robot_corners(pose(res.first_collision))) + EDGE_SLACK
        what = ("leaves the bounds" if edge <= 0 else "collides"
                if clearance(res.first_collision) <= 0 else "is not proven clear")
        rep.problems.append(f"{where}: the walking robot {what} (fraction "
                            f"{res.first_collision:.3f})")

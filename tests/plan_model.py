"""An independent model of a plan's validity (shapely), and random and mutated plans.

The model shares with ``check`` only the grasp conventions (where the car, the pivots and
the robot are for a box pose and a grasp, the bodies' outlines). It carries its own pose
chain from the scene's start, and sweeps every rotation and walk by dense samples with
shapely; the bodies keep :data:`~pivot_ompl.validity.collision.KEEP_CLEARANCE` from the
obstacles (the planner's rule), none from the floor's edge or the resting box. It answers
``"valid"``, ``"invalid"`` or ``"unclear"``: a case within the check's stated tolerances
(poses within 1e-6, sweeps within 2 mm) is unclear and not compared.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry import MultiPoint, Polygon, box

from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.scene import Scene, scene_from_dict
from pivot_ompl.validity.collision import KEEP_CLEARANCE

PAPER_BOX = (0.8, 0.6, 1.3)
#: Pose deviations (m, rad): at most CLEAR_POSE is surely accepted, above FAR_POSE surely not.
CLEAR_POSE, FAR_POSE = 0.3e-6, 3e-6
#: Sweeps: penetration surely refused (m: the check's 2 mm and samples' round-off) and the
#: clearance surely accepted (the samples' hulls' sagitta).
DEEP, SAFE = 2.6e-3, 2e-4
#: Largest displacement of a point between two samples (m).
SAMPLE_STEP = 0.01


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _dev(a, b) -> float:
    return max(abs(a[0] - b[0]), abs(a[1] - b[1]), abs(_wrap(a[2] - b[2])))


def _turn(pose, pivot, angle):
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = pose[0] - pivot[0], pose[1] - pivot[1]
    return (pivot[0] + c * dx - s * dy, pivot[1] + s * dx + c * dy, pose[2] + angle)


class _Verdict:
    def __init__(self) -> None:
        self.invalid: list[str] = []
        self.unclear: list[str] = []

    def pose(self, what: str, dev: float) -> None:
        if not dev <= FAR_POSE:
            self.invalid.append(what)
        elif dev > CLEAR_POSE:
            self.unclear.append(what)

    @property
    def answer(self) -> str:
        return "invalid" if self.invalid else "unclear" if self.unclear else "valid"


@dataclass
class _World:
    floor: Polygon
    obstacles: shapely.Geometry
    tall: bool

    def body(self, v: _Verdict, what: str, poses_points: list[list[tuple[float, float]]],
             extra: shapely.Geometry | None = None) -> None:
        """Sample bodies along a motion (convex, each a list of points), in order."""
        obst = self.obstacles if extra is None else shapely.union(self.obstacles, extra)
        deep_obst = obst.buffer(-DEEP) if not obst.is_empty else obst
        deep_floor = self.floor.buffer(DEEP, join_style="mitre")
        safe_floor = self.floor.buffer(-SAFE, join_style="mitre")
        hulls = [MultiPoint(p).convex_hull for p in poses_points]
        for h in hulls:
            if not deep_obst.is_empty and h.intersects(deep_obst):
                v.invalid.append(f"{what} collides")
                return
            if not h.within(deep_floor):
                v.invalid.append(f"{what} leaves the floor")
                return
        for a, b in zip(hulls, hulls[1:] or hulls, strict=False):
            sweep = shapely.union(a, b).convex_hull
            if not sweep.within(safe_floor) or (
                    not obst.is_empty and not sweep.distance(obst) > SAFE):
                v.unclear.append(f"{what} grazes")
                return


def model_verdict(plan: Plan, scene: Scene) -> str:
    """``"valid"``, ``"invalid"`` or ``"unclear"`` (see the module docstring)."""
    m = scene.model
    v = _Verdict()
    if plan.status != "exact":
        v.invalid.append("status")
    v.pose("start", _dev(plan.start, scene.start))
    floor = box(*scene.bounds)
    obst = shapely.union_all([Polygon(_obstacle_points(o)) for o in scene.obstacles]).buffer(
        KEEP_CLEARANCE, quad_segs=32) if scene.obstacles else shapely.GeometryCollection()
    world = _World(floor, obst, True)
    obj = scene.start
    robot = None
    for ph in plan.phases:
        if isinstance(ph, TransferPhase):
            g = ph.grasp
            v.pose("object_start", _dev(ph.object_start, obj))
            v.pose("robot_start", _dev(ph.robot_start, m.robot_pose(obj, g)))
            if robot is not None:
                v.pose("robot continuity", _dev(ph.robot_start, robot))
            car = m.car_pose(obj, g)
            for st in ph.steps:
                if not abs(st.angle) <= scene.alpha_max + 1e-7:
                    v.invalid.append("angle")
                    return v.answer
                ends = m.pivots(car, g)
                d = [math.hypot(st.pivot[0] - e[0], st.pivot[1] - e[1]) for e in ends]
                pivot = ends[int(np.argmin(d))]
                v.pose("pivot", min(d))
                if min(d) > FAR_POSE:
                    return v.answer
                new_car = _turn(car, pivot, st.angle)
                exact = m.object_from_car(new_car, g)
                v.pose("object", _dev(st.object, exact))
                v.pose("robot", _dev(st.robot, m.robot_pose(exact, g)))
                reach = 2.5
                n = max(2, math.ceil(reach * abs(st.angle) / SAMPLE_STEP) + 1)
                cars = [_turn(car, pivot, st.angle * k / (n - 1)) for k in range(n)]
                world.body(v, "box", [m.object_corners(m.object_from_car(c, g)) for c in cars])
                world.body(v, "held robot",
                           [m.held_corners(m.robot_from_car(c, g), g) for c in cars])
                if v.invalid:
                    return v.answer
                car, obj = new_car, exact
            robot = m.robot_pose(obj, g)
        else:
            path = ph.robot_path
            v.pose("object_pose", _dev(ph.object_pose, obj))
            v.pose("walk start", _dev(path[0], m.robot_pose(obj, ph.from_grasp)))
            v.pose("walk end", _dev(path[-1], m.robot_pose(obj, ph.to_grasp)))
            if robot is not None:
                v.pose("walk continuity", _dev(path[0], robot))
            resting = Polygon(m.object_corners(obj))
            radius = m.robot_radius()
            for a, b in zip(path, path[1:], strict=False):
                dyaw = _wrap(b[2] - a[2])
                lip = math.hypot(b[0] - a[0], b[1] - a[1]) + radius * abs(dyaw)
                n = max(2, math.ceil(lip / SAMPLE_STEP) + 1)
                poses = [(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * dyaw)
                         for t in np.linspace(0.0, 1.0, n)]
                world.body(v, "walk", [m.robot_corners(p) for p in poses], extra=resting)
                if v.invalid:
                    return v.answer
            robot = path[-1]
    v.pose("goal", _dev(obj, scene.goal))
    return v.answer


def _obstacle_points(o) -> list[tuple[float, float]]:
    c, s = math.cos(o.yaw), math.sin(o.yaw)
    hx, hy = 0.5 * o.size[0], 0.5 * o.size[1]
    return [(o.center[0] + c * x - s * y, o.center[1] + s * x + c * y)
            for x, y in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))]


# -- random and mutated plans -------------------------------------------------------------

KINDS = ("random", "slide", "teleport", "swing", "graze")


def _scene(bounds, start, goal, obstacles, alpha_max) -> Scene | None:
    doc = {"name": "differential", "bounds": [float(b) for b in bounds],
           "object": {"size": list(PAPER_BOX)}, "start": [start[0], start[1], _wrap(start[2])],
           "goal": [goal[0], goal[1], _wrap(goal[2])], "obstacles": obstacles,
           "pivot": {"alpha_max": alpha_max}}
    try:
        return scene_from_dict(doc, source="<differential>")
    except Exception:  # noqa: BLE001 - an end off the floor: no case
        return None


def _transfer(m, obj, g, rng, steps: int, alpha_max: float) -> tuple[TransferPhase, tuple]:
    car = m.car_pose(obj, g)
    out = []
    sign = 1.0
    for _ in range(steps):
        ends = m.pivots(car, g)
        pivot = ends[0] if sign > 0 else ends[1]
        angle = sign * float(rng.uniform(0.2, 1.0)) * alpha_max
        car = _turn(car, pivot, angle)
        q = m.object_from_car(car, g)
        out.append(TransferStep(pivot, angle, q, m.robot_pose(q, g)))
        sign = -sign
    end = out[-1].object if out else obj
    return TransferPhase(g, m.robot_pose(obj, g), tuple(out), obj, ()), end


def _walk(m, obj, g, h, rng) -> TransitPhase:
    a, b = m.robot_pose(obj, g), m.robot_pose(obj, h)
    back = float(rng.uniform(0.3, 0.9))
    a2 = (a[0] - back * math.cos(a[2]), a[1] - back * math.sin(a[2]), a[2])
    b2 = (b[0] - back * math.cos(b[2]), b[1] - back * math.sin(b[2]), a[2])
    b3 = (b2[0], b2[1], a[2] + _wrap(b[2] - a[2]))
    return TransitPhase(g, h, (a, a2, b2, b3, (b[0], b[1], b3[2])), obj)


def random_case(seed: int, kind: str) -> tuple[Plan, Scene] | None:
    """A plan and its scene of the kind asked (``None`` when the draw gives no scene)."""
    from pivot_ompl.grasp import BoxGraspModel

    rng = np.random.default_rng(seed)
    m = BoxGraspModel(PAPER_BOX)
    alpha_max = math.pi / 8
    w, h = rng.uniform(5.0, 10.0, 2)
    start = (float(rng.uniform(2.0, w - 2.0)), float(rng.uniform(2.0, h - 2.0)),
             float(rng.uniform(-math.pi, math.pi)))
    bounds = [0.0, 0.0, float(w), float(h)]
    obstacles = []
    for _ in range(int(rng.integers(0, 4))):
        obstacles.append({"type": "box", "center": [float(rng.uniform(0, w)),
                                                    float(rng.uniform(0, h))],
                          "size": [float(rng.uniform(0.1, 0.8)), float(rng.uniform(0.1, 0.8))],
                          "yaw": float(rng.uniform(-1.5, 1.5)), "height": 2.0})
    phases: list = []
    obj = start
    g = int(rng.integers(4))
    for p in range(int(rng.integers(1, 3))):
        if p:
            h2 = (g + int(rng.integers(1, 4))) % 4
            phases.append(_walk(m, obj, g, h2, rng))
            g = h2
        ph, obj = _transfer(m, obj, g, rng, int(rng.integers(1, 10)), alpha_max)
        phases.append(ph)
    if kind == "slide":
        phases.append(_slide(m, obj, g, rng))
        obj = phases[-1].steps[-1].object
    elif kind == "teleport":
        phases, obj = _teleport(m, phases, rng, alpha_max)
    elif kind == "swing":
        return _swing(m, rng, alpha_max)
    elif kind == "graze":
        obstacles.append(_graze(m, phases, rng))
    plan = Plan("differential", "exact", m.object_size, m.robot_footprint, m.standoff,
                alpha_max, start, phases, {})
    scene = _scene(bounds, start, obj, obstacles, alpha_max)
    return None if scene is None else (plan, scene)


def _slide(m, obj, g, rng) -> TransferPhase:
    """Zero-angle steps whose written poses drift 0.9 um each: the box slides."""
    n = int(rng.integers(2, 400))
    direction = float(rng.uniform(-math.pi, math.pi))
    steps = []
    q = obj
    for _ in range(n):
        q = (q[0] + 0.9e-6 * math.cos(direction), q[1] + 0.9e-6 * math.sin(direction), q[2])
        car = m.car_pose(q, g)
        steps.append(TransferStep(m.pivots(car, g)[0], 0.0, q, m.robot_pose(q, g)))
    return TransferPhase(g, m.robot_pose(obj, g), tuple(steps), obj, ())


def _teleport(m, phases, rng, alpha_max):
    """One step's written pose moved; the written chain goes on from there."""
    k = [i for i, p in enumerate(phases) if isinstance(p, TransferPhase) and p.steps][-1]
    ph = phases[k]
    j = int(rng.integers(len(ph.steps)))
    jump = float(rng.choice([2e-6, 1e-5, 1e-3, 0.05]))
    d = float(rng.uniform(-math.pi, math.pi))
    st = ph.steps[j]
    q = (st.object[0] + jump * math.cos(d), st.object[1] + jump * math.sin(d), st.object[2])
    steps = [*ph.steps[:j], TransferStep(st.pivot, st.angle, q, m.robot_pose(q, ph.grasp))]
    car = m.car_pose(q, ph.grasp)
    for s in ph.steps[j + 1:]:
        ends = m.pivots(car, ph.grasp)
        pivot = ends[int(np.argmin([math.dist(s.pivot, e) for e in ends]))]
        car = _turn(car, pivot, s.angle)
        q = m.object_from_car(car, ph.grasp)
        steps.append(TransferStep(pivot, s.angle, q, m.robot_pose(q, ph.grasp)))
    phases = [*phases[:k], TransferPhase(ph.grasp, ph.robot_start, tuple(steps),
                                         ph.object_start, ())]
    return phases, q


def _swing(m, rng, alpha_max) -> tuple[Plan, Scene] | None:
    """A walk turning in place near two walls: the ends fit, the middle of the turn may not."""
    g = int(rng.integers(4))
    obj0 = (5.0, 5.0, 0.0)
    r = m.robot_pose(obj0, g)
    obj = (obj0[0], obj0[1], -r[2])  # the robot faces +x
    r = m.robot_pose(obj, g)
    back = (r[0] - float(rng.uniform(0.4, 0.8)), r[1], r[2])
    gap_x, gap_y = rng.uniform(0.0, 0.15, 2)
    turn = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.3, math.pi))
    turned = (back[0], back[1], back[2] + turn)
    corners = [*m.robot_corners(back), *m.robot_corners(turned)]  # both ends fit: the turn?
    bounds = [min(x for x, _ in corners) - gap_x, min(y for _, y in corners) - gap_y,
              back[0] + 6.0, back[1] + 6.0]
    walk = TransitPhase(g, g, (r, back, turned, back, r), obj)
    step, end = _transfer(m, obj, g, rng, 1, alpha_max)
    plan = Plan("differential", "exact", m.object_size, m.robot_footprint, m.standoff,
                alpha_max, obj, [walk, step], {})
    scene = _scene(bounds, obj, end, [], alpha_max)
    return None if scene is None else (plan, scene)


def _bodies(m, phases) -> shapely.Geometry:
    """The union of the bodies' outlines along the plan's rotations and walks (sampled)."""
    hulls = []
    for ph in phases:
        if isinstance(ph, TransferPhase):
            car = m.car_pose(ph.object_start, ph.grasp)
            for st in ph.steps:
                for k in range(9):
                    c = _turn(car, st.pivot, st.angle * k / 8)
                    hulls.append(MultiPoint(m.object_corners(
                        m.object_from_car(c, ph.grasp))).convex_hull)
                    hulls.append(MultiPoint(m.held_corners(
                        m.robot_from_car(c, ph.grasp), ph.grasp)).convex_hull)
                car = m.car_pose(st.object, ph.grasp)
        else:
            for q in ph.robot_path:
                hulls.append(MultiPoint(m.robot_corners(q)).convex_hull)
    return shapely.union_all(hulls)


def _graze(m, phases, rng) -> dict:
    """A small tall obstacle just off (or just into) the bodies' outline along the plan.

    Along a random ray from the box's start, the square is put where it touches the
    bodies' union grown by ``gap`` (shrunk when ``gap < 0``): at ``gap`` from it.
    """
    union = _bodies(m, phases)
    gap = float(rng.choice([-0.02, -0.004, -0.001, 0.0005, 0.001, 0.004, 0.02]))
    target = union.buffer(KEEP_CLEARANCE + gap)
    x0, y0 = phases[0].object_start[:2] if isinstance(phases[0], TransferPhase) else \
        phases[0].object_pose[:2]
    theta = float(rng.uniform(-math.pi, math.pi))
    ux, uy = math.cos(theta), math.sin(theta)
    side, yaw = 0.1, float(rng.uniform(-1.0, 1.0))

    def square(t: float) -> Polygon:
        c = (x0 + t * ux, y0 + t * uy)
        return shapely.affinity.rotate(box(c[0] - side / 2, c[1] - side / 2, c[0] + side / 2,
                                           c[1] + side / 2), yaw, use_radians=True)

    lo, hi = 0.0, 20.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if square(mid).intersects(target):
            lo = mid
        else:
            hi = mid
    c = (x0 + hi * ux, y0 + hi * uy)
    return {"type": "box", "center": [c[0], c[1]], "size": [side, side], "yaw": yaw,
            "height": 2.0}

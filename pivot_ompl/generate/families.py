"""Scene families whose scenes come with a witness plan, built constructively.

Each family lays out the box's path and the robot's regrasp poses first (in a local frame),
places walls, slots, doors, pockets and clutter around them, checks the chain with the
project's own steering and walk planner (:mod:`pivot_ompl.generate.witness`) and, for
``walls`` and ``corridor``, turns the whole scene by a random angle. A layout whose chain
fails is drawn again from the same generator, so a seed always gives the same scene.

Families:

* ``walls``: 1-3 walls at random positions and orientations across a room. Each wall has a
  **slot** only the box passes (narrower than the robot) and a robot **door**
  (``door_width``); half the doors open into a **pocket** closed by a baffle. The witness
  pushes the box into each slot, walks round through the door and pulls the box out.
* ``corridor``: a corridor with 1-3 right-angle bends; at each bend a small square where the
  robot alone walks round the box but robot and box cannot turn: the witness regrasps there.
* ``clutter``: a room with pillars, tables and counters round a one-grasp pivoting path (no
  regrasp needed).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import InputError, counted, require_type
from pivot_ompl.generate.building import building_layout
from pivot_ompl.generate.layout import (
    BOX,
    HELD_FACE_BACK,
    WALL_HEIGHT,
    Retry,
    free_complement,
    make_scene,
    uniform,
)
from pivot_ompl.generate.params import GeneratorParams, check_params
from pivot_ompl.generate.transform import RigidMap, transform_scene
from pivot_ompl.generate.witness import State, build_witness
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, Scene
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.validity.collision import CollisionWorld

log = logging.getLogger(__name__)

#: Clearance kept between clutter and the witness's bodies (m).
CLUTTER_MARGIN = 0.12


@dataclass(frozen=True)
class Generated:
    """A generated scene and its witness plan (checked by ``check_plan``)."""

    scene: Scene
    witness: Plan
    family: str
    seed: int
    attempts: int

    def __post_init__(self) -> None:
        require_type(self.scene, Scene, "Generated.scene", "a Scene")
        require_type(self.witness, Plan, "Generated.witness", "a Plan")
        require_type(self.family, str, "Generated.family", "a family name")
        for name in ("seed", "attempts"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise InputError(f"Generated.{name}", v, "must be a non-negative integer")


def _along(p: tuple[float, float], phi: float, d: float, s: float = 0.0) -> tuple[float, float]:
    """Point ``d`` along direction ``phi`` and ``s`` to its left from ``p``."""
    return (p[0] + d * math.cos(phi) - s * math.sin(phi), p[1] + d * math.sin(phi)
            + s * math.cos(phi))


def _slot_gap(rng: np.random.Generator, p: GeneratorParams) -> float:
    """The gap (m) on each side of the box in a slot."""
    return p.slot_clearance if p.slot_clearance is not None else uniform(rng, p.slot_gap)


# -- walls -------------------------------------------------------------------------------
def _wall_pieces(origin: tuple[float, float], phi: float, t: float, s_lo: float, s_hi: float,
                 holes: list[tuple[float, float]]) -> list[Obstacle]:
    """A wall of thickness ``t`` whose near face passes through ``origin`` with normal ``phi``.

    It spans ``s_lo..s_hi`` along its face, less the ``holes`` (intervals of ``s``).
    """
    out: list[Obstacle] = []
    cur = s_lo
    for a, b in sorted(holes):
        if a > cur:
            out.append(_piece(origin, phi, t, cur, a))
        cur = max(cur, b)
    if s_hi > cur:
        out.append(_piece(origin, phi, t, cur, s_hi))
    return out


def _piece(origin: tuple[float, float], phi: float, t: float, a: float, b: float) -> Obstacle:
    c = _along(origin, phi, 0.5 * t, 0.5 * (a + b))
    return BoxObstacle(c, (t, b - a), phi, WALL_HEIGHT)


def _walls_layout(rng: np.random.Generator, p: GeneratorParams,
                  seed: int) -> tuple[Scene, list[State]]:
    n = int(rng.integers(1, 4)) if p.walls is None else p.walls
    width = float(rng.uniform(6.0, 7.5))
    obstacles: list[Obstacle] = []
    states: list[State] = []
    x = float(rng.uniform(3.6, 4.2))  # near face of the first wall, on the room's midline
    y_prev = float(rng.uniform(1.5, width - 1.5))
    approach: list[tuple[Pose, Pose, Pose]] = []
    for _ in range(n):
        phi = float(rng.uniform(-p.max_tilt, p.max_tilt))
        t = float(rng.uniform(0.3, 0.5))
        ys = float(np.clip(y_prev + rng.uniform(-1.8, 1.8), 1.3, width - 1.3))
        origin = (x, ys)
        cphi = math.cos(phi)
        s_lo = -ys / cphi - 1.0
        s_hi = (width - ys) / cphi + 1.0
        slot = BOX[1] + 2 * _slot_gap(rng, p)
        door = uniform(rng, p.door_width)
        # the door: at least 1.8 m from the slot, inside the room
        sides = [sd for sd in (-1, 1)
                 if (s_lo + 1.2 if sd < 0 else s_hi - 1.2) * sd > 1.8 + 0.5 * door]
        if not sides:
            raise Retry("no room for a door")
        sd = sides[int(rng.integers(len(sides)))]
        far = (s_lo + 1.0 + 0.5 * door + 0.1) if sd < 0 else (s_hi - 1.0 - 0.5 * door - 0.1)
        near = sd * (1.8 + 0.5 * door)
        s_d = float(rng.uniform(min(near, far), max(near, far)))
        holes = [(-0.5 * slot, 0.5 * slot), (s_d - 0.5 * door, s_d + 0.5 * door)]
        obstacles += _wall_pieces(origin, phi, t, s_lo, s_hi, holes)
        if rng.uniform() < 0.5:  # a pocket behind the door, open towards the slot
            depth = float(rng.uniform(1.15, 1.35))
            a = s_d - 0.5 * door - 0.3 if sd > 0 else s_lo
            b = s_hi if sd > 0 else s_d + 0.5 * door + 0.3
            obstacles.append(_piece(_along(origin, phi, t + depth), phi, 0.2, a, b))
        # pushed into the slot until the held face is HELD_FACE_BACK short of the wall: the arms
        # (which reach the grip points on the box's sides) stay out of the slot
        push = _along(origin, phi, BOX[0] / 2 - HELD_FACE_BACK)
        before = _along(origin, phi, -float(rng.uniform(1.2, 1.6)))
        after = _along(origin, phi, t + float(rng.uniform(1.25, 1.5)) + 0.4)
        approach.append(((before[0], before[1], phi), (push[0], push[1], phi),
                         (after[0], after[1], phi)))
        x = after[0] + float(rng.uniform(1.6, 2.4))
        y_prev = ys
    length = x + float(rng.uniform(0.5, 1.2))
    start = (uniform(rng, (0.9, approach[0][0][0] - 0.6)), float(rng.uniform(1.0, width - 1.0)),
             approach[0][0][2] + float(rng.uniform(-0.5, 0.5)))
    last = approach[-1][2]
    goal = (uniform(rng, (last[0] + 0.6, length - 0.9)), float(rng.uniform(1.0, width - 1.0)),
            last[2] + float(rng.uniform(-0.5, 0.5)))
    states.append((start, 0))
    for i, (q_before, q_push, q_after) in enumerate(approach):
        if i > 0:
            states.append((states[-1][0], 0))  # regrasp: behind the box again
        states += [(q_before, 0), (q_push, 0), (q_push, 2), (q_after, 2)]
    states.append((goal, 2))
    scene = make_scene(f"walls_{seed}", (0.0, 0.0, length, width), obstacles, start, goal)
    return scene, states


# -- corridor ----------------------------------------------------------------------------
def _corridor_layout(rng: np.random.Generator, p: GeneratorParams,
                     seed: int) -> tuple[Scene, list[State]]:
    bends = int(rng.integers(1, 4))
    w = uniform(rng, p.corridor_width)
    free: list[tuple[float, float, float, float]] = []
    states: list[State] = []
    pos = (0.0, 0.0)
    heading = 0  # 0: +x, 1: +y (the corridor climbs a staircase)
    leg0 = float(rng.uniform(3.0, 4.0))
    corners: list[tuple[tuple[float, float], int]] = []
    for _ in range(bends):
        leg = leg0 if not corners else float(rng.uniform(2.5, 3.5))
        nxt = (pos[0] + leg, pos[1]) if heading == 0 else (pos[0], pos[1] + leg)
        corners.append((nxt, heading))
        pos = nxt
        heading = 1 - heading
    end_leg = float(rng.uniform(3.0, 4.0))
    end = (pos[0] + end_leg, pos[1]) if heading == 0 else (pos[0], pos[1] + end_leg)
    pts = [(0.0, 0.0)] + [c for c, _ in corners] + [end]
    for a, b in zip(pts, pts[1:], strict=False):
        free.append((min(a[0], b[0]) - 0.5 * w, min(a[1], b[1]) - 0.5 * w,
                     max(a[0], b[0]) + 0.5 * w, max(a[1], b[1]) + 0.5 * w))
    for c, _ in corners:
        j = 0.5 * uniform(rng, p.bend_size)
        free.append((c[0] - j, c[1] - j, c[0] + j, c[1] + j))
    # start and end in small rooms so the box has room to line up
    room = 1.6
    free.append((-room, -room, 0.5 * w + 0.6, room))
    free.append((end[0] - room, end[1] - room, end[0] + room, end[1] + room))
    lo = (min(r[0] for r in free) - 0.3, min(r[1] for r in free) - 0.3)
    free = [(r[0] - lo[0], r[1] - lo[1], r[2] - lo[0], r[3] - lo[1]) for r in free]
    bounds = (0.0, 0.0, max(r[2] for r in free) + 0.3, max(r[3] for r in free) + 0.3)

    def at(q: tuple[float, float], yaw: float) -> Pose:
        return (q[0] - lo[0], q[1] - lo[1], yaw)

    start = at((float(rng.uniform(-0.6, 0.2)), float(rng.uniform(-0.5, 0.5))),
               float(rng.uniform(-0.4, 0.4)))
    states.append((start, 0))
    grasp = 0
    for c, h in corners:
        # box yaw 0 throughout: grasp 0 pushes along +x, grasp 1 along +y
        before = (c[0] - 1.2, c[1]) if h == 0 else (c[0], c[1] - 1.2)
        states.append((at(before, 0.0), grasp))
        states.append((at(c, 0.0), grasp))
        grasp = 1 - grasp
        states.append((at(c, 0.0), grasp))
        after = (c[0] + 1.2, c[1]) if h == 1 else (c[0], c[1] + 1.2)
        states.append((at(after, 0.0), grasp))
    goal = at((end[0] + float(rng.uniform(-0.3, 0.5)) * (heading == 0),
               end[1] + float(rng.uniform(-0.3, 0.5)) * (heading == 1)),
              float(rng.uniform(-0.3, 0.3)))
    states.append((goal, grasp))
    obstacles = free_complement(bounds, free)
    return make_scene(f"corridor_{seed}", bounds, obstacles, start, goal), states


# -- clutter -----------------------------------------------------------------------------
def _clutter_layout(rng: np.random.Generator, p: GeneratorParams,
                    seed: int) -> tuple[Scene, list[State]]:
    bx, by = float(rng.uniform(7.0, 10.0)), float(rng.uniform(5.0, 8.0))
    m = 1.0

    def pose() -> Pose:
        return (float(rng.uniform(m, bx - m)), float(rng.uniform(m, by - m)),
                float(rng.uniform(-math.pi, math.pi)))

    start, goal = pose(), pose()
    if math.hypot(goal[0] - start[0], goal[1] - start[1]) < 3.0:
        raise Retry("start and goal too close")
    g = int(rng.integers(4))
    states: list[State] = [(start, g), (goal, g)]
    empty = make_scene(f"clutter_{seed}", (0.0, 0.0, bx, by), [], start, goal)
    ck = PivotChecker(empty)
    if not ck.transfer(start, goal, g).valid:
        raise Retry("no direct pivoting path")
    bodies = _swept_samples(ck, states)
    obstacles: list[Obstacle] = []
    for _ in range(int(rng.integers(5, 12)) * 4):
        if len(obstacles) >= 12:
            break
        c = (float(rng.uniform(0.3, bx - 0.3)), float(rng.uniform(0.3, by - 0.3)))
        kind = rng.uniform()
        o: Obstacle
        if kind < 0.4:
            o = CylinderObstacle(c, float(rng.uniform(0.15, 0.4)), float(rng.uniform(0.8, 2.5)))
        else:
            o = BoxObstacle(c, (float(rng.uniform(0.4, 1.4)), float(rng.uniform(0.4, 1.0))),
                            float(rng.uniform(-math.pi, math.pi)), float(rng.uniform(0.7, 1.2)))
        if _clear_of(empty, o, bodies):
            obstacles.append(o)
    return make_scene(f"clutter_{seed}", (0.0, 0.0, bx, by), obstacles, start, goal), states


def _swept_samples(ck: PivotChecker, states: list[State]) -> list[tuple[Pose, Pose, int]]:
    """Box and robot poses (and grasp) sampled along the witness's rotations (every 1/4)."""
    m = ck.model
    out: list[tuple[Pose, Pose, int]] = []
    for (pa, g), (pb, _) in zip(states, states[1:], strict=False):
        seq = ck.transfer(pa, pb, g).sequence
        prev = m.car_pose(pa, g)
        for r in seq.rotations:
            for s in (0.0, 0.25, 0.5, 0.75):
                car = rotate_about(prev, r.pivot, s * r.angle)
                out.append((m.object_from_car(car, g), m.robot_from_car(car, g), g))
            prev = r.car
        out.append((m.object_from_car(prev, g), m.robot_from_car(prev, g), g))
    return out


def _clear_of(scene: Scene, o: Obstacle, bodies: list[tuple[Pose, Pose, int]]) -> bool:
    """The obstacle keeps the margin from the box and the holding robot's body (arms too)."""
    w = CollisionWorld(scene.model, scene.bounds)
    w.add_obstacle(o)
    w.setup()
    return all(w.box_distance(b) > CLUTTER_MARGIN and w.held_distance(r, g) > CLUTTER_MARGIN
               for b, r, g in bodies)


Layout = Callable[[np.random.Generator, GeneratorParams, int], tuple[Scene, list[State]]]
def _building(rng: np.random.Generator, p: GeneratorParams,
              seed: int) -> tuple[Scene, list[State]]:
    return building_layout(rng, rooms=p.rooms, layout=p.layout, slot_gap=p.slot_gap,
                           slot_clearance=p.slot_clearance, wide_doors=p.wide_doors, seed=seed,
                           side_corridor=p.side_corridor, side_door=p.side_door)


FAMILIES: dict[str, Layout] = {"walls": _walls_layout, "corridor": _corridor_layout,
                               "clutter": _clutter_layout, "building": _building}
#: Each family's stream of random numbers (fixed: a new family changes no other's scenes).
_STREAM = {"clutter": 0, "corridor": 1, "walls": 2, "building": 3}
_ROTATED = {"walls", "corridor", "building"}


def generate(family: str, seed: int, *, params: GeneratorParams | None = None) -> Generated:
    """A scene of ``family`` and its witness plan, deterministic for ``seed``.

    Raises:
        InputError: a family that is not a known name, a bad seed, ``params`` not a
            :class:`GeneratorParams`, or no valid layout within ``params.attempts``.
    """
    require_type(family, str, "family", f"a family name (one of {sorted(FAMILIES)})")
    if family not in FAMILIES:
        raise InputError("family", family, f"unknown family (known: {sorted(FAMILIES)})")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InputError("seed", seed, "must be a non-negative integer")
    if params is not None:
        require_type(params, GeneratorParams, "params", "a GeneratorParams or None")
    p = params or GeneratorParams()
    check_params(p)
    rng = np.random.default_rng([seed, _STREAM[family]])
    reason = ""
    for attempt in range(1, p.attempts + 1):
        try:
            scene, states = FAMILIES[family](rng, p, seed)
        except Retry as e:
            reason = str(e)
            continue
        if family in _ROTATED and p.rotate:
            b = scene.bounds
            f = RigidMap(float(rng.uniform(-math.pi, math.pi)),
                         (0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])))
            scene = transform_scene(scene, f, name=scene.name)
            states = [(f.pose(q), f.grasp(g)) for q, g in states]
        w = build_witness(scene, states)
        if w.plan is not None:
            log.info("%s seed %d: layout %d holds (%s)", family, seed, attempt,
                     counted(w.plan.regrasps, "regrasp"))
            w.plan.extra["family"] = family
            w.plan.extra["seed"] = seed
            return Generated(scene, w.plan, family, seed, attempt)
        reason = w.reason
        log.debug("%s seed %d: layout %d rejected: %s", family, seed, attempt, reason)
    raise InputError("seed", seed, f"no valid {family} layout in {p.attempts} attempts "
                     f"(last: {reason})")

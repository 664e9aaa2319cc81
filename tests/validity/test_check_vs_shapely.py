"""``check`` never accepts a plan through an obstacle: random degenerate polygons vs shapely.

A straight push across the floor is steered without obstacles; a polygon (repeated and
collinear vertices, either orientation, possibly thin) is dropped on random places. Wherever
shapely says the box's footprint at a step pose meets the polygon, the plan check must refuse
the plan.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import steps_of
from pivot_ompl.planfile import Plan, TransferPhase
from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.plan_check import check_plan

START, GOAL = (1.5, 3.0, 0.0), (6.5, 3.0, 0.0)


def _push(scene) -> Plan:
    m = scene.model
    steering = PivotSteering(turning_radius=scene.turning_radius, alpha_max=scene.alpha_max)
    seq = steering.convert(m.car_pose(START, 0), m.car_pose(GOAL, 0),
                           half_length=m.edge_half_length(0))
    phase = TransferPhase(0, m.robot_pose(START, 0), steps_of(m, seq, 0), START, ())
    return Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, START, [phase], {})


def _polygon(rng: np.random.Generator, cx: float, cy: float, n: int, thin: float,
             repeats: int, clockwise: bool) -> list[list[float]]:
    angles = np.sort(rng.uniform(0, 2 * math.pi, n))
    radii = rng.uniform(thin, 0.6, n)
    pts = [[cx + r * math.cos(a), cy + r * math.sin(a)] for a, r in
           zip(angles, radii, strict=True)]
    k = int(rng.integers(len(pts)))
    a, b = pts[k], pts[(k + 1) % len(pts)]
    pts.insert(k + 1, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])])  # a collinear vertex
    for _ in range(repeats):
        j = int(rng.integers(len(pts)))
        pts.insert(j, list(pts[j]))  # a repeated vertex
    return pts[::-1] if clockwise else pts


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), x=st.floats(2.5, 5.5), y=st.floats(2.2, 3.8),
       n=st.integers(3, 12), thin=st.sampled_from([0.3, 0.01]), repeats=st.integers(0, 2),
       clockwise=st.booleans())
def test_check_refuses_every_push_through_a_polygon(seed, x, y, n, thin, repeats, clockwise):
    rng = np.random.default_rng(seed)
    pts = _polygon(rng, x, y, n, thin, repeats, clockwise)
    poly = shapely.Polygon(pts)
    if not poly.is_valid or poly.area < 1e-4:
        return
    free = make_scene(start=list(START), goal=list(GOAL))
    plan = _push(free)
    assert check_plan(plan, free).ok  # the push itself is a valid plan of the empty floor
    scene = make_scene(start=list(START), goal=list(GOAL),
                       obstacles=[{"type": "polygon", "points": pts, "height": 1.0}])
    m = scene.model
    poses = [plan.phases[0].object_start, *(s.object for s in plan.phases[0].steps)]
    hit = any(shapely.Polygon(rectangle_corners(q, m.object_size[0], m.object_size[1]))
              .intersects(poly) for q in poses)
    rep = check_plan(plan, scene)
    if hit:
        assert not rep.ok
        assert any("collide" in p for p in rep.problems), rep.problems


def _spiky(rng: np.random.Generator, cx: float, cy: float) -> list[list[float]]:
    """A triangle with a spike thinner than round-off (1e-13 m or less: flat triangles)."""
    w = float(rng.choice([1e-14, 1e-13, 1e-12]))
    ln = float(rng.uniform(0.5, 1.5))
    a = float(rng.uniform(-math.pi, math.pi))
    c, s = math.cos(a), math.sin(a)
    local = [(-0.3, -0.3), (0.3, -0.3), (w, 0.0), (0.5 * w, ln), (0.0, 0.0)]
    return [[cx + c * x - s * y, cy + s * x + c * y] for x, y in local]


def _random_push(scene, rng: np.random.Generator):
    m = scene.model
    steering = PivotSteering(turning_radius=scene.turning_radius, alpha_max=scene.alpha_max)
    start = (float(rng.uniform(1.2, 2.0)), float(rng.uniform(2.0, 4.0)),
             float(rng.uniform(-0.6, 0.6)))
    goal = (float(rng.uniform(6.0, 6.8)), float(rng.uniform(2.0, 4.0)),
            float(rng.uniform(-0.6, 0.6)))
    grasp = int(rng.integers(4))
    seq = steering.convert(m.car_pose(start, grasp), m.car_pose(goal, grasp),
                           half_length=m.edge_half_length(grasp))
    steps = steps_of(m, seq, grasp)
    end = steps[-1].object if steps else start
    phase = TransferPhase(grasp, m.robot_pose(start, grasp), steps, start, ())
    return Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, start, [phase], {}), start, end


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), count=st.integers(1, 3))
def test_check_refuses_random_plans_through_random_degenerate_scenes(seed, count):
    """Random pushes (any grasp, curved) across scenes of 1-3 degenerate polygons (repeated
    and collinear vertices, clockwise, thin, spikes thinner than round-off): wherever shapely
    says a box pose of the plan meets a polygon, ``check`` refuses the plan."""
    rng = np.random.default_rng(seed)
    obstacles, shapes = [], []
    for _ in range(count):
        x, y = float(rng.uniform(2.8, 5.2)), float(rng.uniform(1.5, 4.5))
        if rng.random() < 0.4:
            pts = _spiky(rng, x, y)
        else:
            pts = _polygon(rng, x, y, int(rng.integers(3, 12)), float(rng.choice([0.3, 0.01])),
                           int(rng.integers(0, 3)), bool(rng.random() < 0.5))
        poly = shapely.Polygon(pts)
        if not poly.is_valid or abs(sum(  # what the reader refuses
                pts[i][0] * pts[i - 1][1] - pts[i - 1][0] * pts[i][1]
                for i in range(len(pts)))) < 1e-12:
            continue
        obstacles.append({"type": "polygon", "points": pts, "height": 1.0})
        shapes.append(poly)
    free = make_scene(bounds=[0.0, 0.0, 8.0, 6.0])
    plan, start, end = _random_push(free, rng)
    scene = make_scene(start=list(start), goal=list(end), obstacles=obstacles)
    m = scene.model
    poses = [plan.phases[0].object_start, *(s.object for s in plan.phases[0].steps)]
    hit = any(shapely.Polygon(rectangle_corners(q, m.object_size[0], m.object_size[1]))
              .intersects(poly) for q in poses for poly in shapes)
    if hit:
        rep = check_plan(plan, scene)
        assert not rep.ok
        assert any("collide" in p or "invalid" in p for p in rep.problems), rep.problems

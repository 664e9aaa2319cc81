"""The holding robot's planner body: footprint, arms to the grip points, the box's overhang."""

from __future__ import annotations

import math

from factories import PAPER_BOX, make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl import hrp2
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.grasp import GRIP_OFFSET, HOLD_TILT, BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.plan_check import check_plan


def _inside(poly, p, tol=1e-9) -> bool:
    """Point in the convex hull of ``poly`` (any order)."""
    import numpy as np
    from scipy.spatial import ConvexHull

    pts = np.array(poly)
    h = ConvexHull(pts)
    return bool((h.equations[:, :2] @ np.array(p) + h.equations[:, 2] <= tol).all())


def _to_robot(robot, p):
    c, s = math.cos(robot[2]), math.sin(robot[2])
    dx, dy = p[0] - robot[0], p[1] - robot[1]
    return (c * dx + s * dy, -s * dx + c * dy)


sizes = st.tuples(st.floats(0.3, 1.5), st.floats(0.3, 1.5), st.floats(0.6, 1.6))


@settings(max_examples=60, deadline=None)
@given(size=sizes, grasp=st.integers(0, 3))
def test_held_outline_covers_shoulders_grips_and_the_gap(size, grasp):
    m = BoxGraspModel(size)
    outline = m.held_outline(grasp)
    face = 0.5 * m.robot_footprint[0] + m.standoff
    sx, sy = hrp2.SHOULDER_XY
    gy = m.grip_lateral(grasp)
    for p in [(sx, sy), (sx, -sy), (face - GRIP_OFFSET, gy), (face - GRIP_OFFSET, -gy),
              (face, gy + 0.9 * hrp2.HAND_ENVELOPE), (face, -gy - 0.9 * hrp2.HAND_ENVELOPE),
              (face - 0.99 * size[2] * math.sin(HOLD_TILT), 0.99 * m.edge_half_length(grasp)),
              (0.5 * (0.5 * m.robot_footprint[0] + face), 0.0)]:  # the middle of the gap
        assert _inside(outline, p), (p, outline)
    # nothing beyond the held face: the box itself is the box's body
    assert max(x for x, _ in outline) == face


@settings(max_examples=40, deadline=None)
@given(size=sizes, grasp=st.integers(0, 3), car=st.tuples(st.floats(-5, 5), st.floats(-5, 5),
                                                         st.floats(-math.pi, math.pi)))
def test_reach_bounds_cover_the_held_body(size, grasp, car):
    scene = make_scene(object={"size": list(size)})
    checker = PivotChecker(scene)
    m = scene.model
    for pivot in m.pivots(car, grasp):
        far = max(math.hypot(x - pivot[0], y - pivot[1])
                  for x, y in m.held_corners(m.robot_from_car(car, grasp), grasp))
        assert far <= checker.transfers.reach(grasp)[1] + 1e-9


#: Where the pole stands across the gap, as a fraction of the standoff from the robot's front:
#: beyond the walking body's reach (a knee, 0.31 m ahead of the robot pose), short of the face.
GAP_FRACTION = 0.7


def _pole_in_gap(obj, grasp: int, model: BoxGraspModel, *, lateral: float = 0.0):
    """A point in the gap between the robot's front and the held face, beyond the knees."""
    r = model.robot_pose(obj, grasp)
    x = 0.5 * model.robot_footprint[0] + GAP_FRACTION * model.standoff
    c, s = math.cos(r[2]), math.sin(r[2])
    return (r[0] + c * x - s * lateral, r[1] + s * x + c * lateral)


def test_a_pole_between_robot_and_box_invalidates_the_state():
    # the example: a 5 cm pole in the 0.25 m gap used to be a valid state
    obj = (4.0, 3.0, 0.3)
    model = BoxGraspModel(PAPER_BOX)
    for grasp in range(4):
        px, py = _pole_in_gap(obj, grasp, model)
        scene = make_scene(obstacles=[{"type": "cylinder", "center": [px, py],
                                       "radius": 0.025, "height": 1.0}])
        checker = PivotChecker(scene)
        w = checker.world
        r = model.robot_pose(obj, grasp)
        assert w.box_distance(obj) > 0 and w.robot_distance(r) > 0  # box, walking body clear
        assert w.held_distance(r, grasp) <= 0
        assert not checker.state_valid(obj, grasp)
        assert "robot collides" in checker.explain(obj)
        # moved out of the arms' region, it is clear again
        far = _pole_in_gap(obj, grasp, model, lateral=0.6)
        scene = make_scene(obstacles=[{"type": "cylinder", "center": list(far),
                                       "radius": 0.025, "height": 1.0}])
        assert PivotChecker(scene).state_valid(obj, grasp)


def test_check_rejects_a_plan_whose_arms_enter_a_wall():
    model = BoxGraspModel(PAPER_BOX)
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    a, b = (2.0, 3.0, 0.0), (2.6, 3.0, 0.0)
    ph = transfer_phase(model, steering, [a, b], 0)
    plan = Plan("test", "exact", PAPER_BOX, model.robot_footprint, model.standoff,
                math.pi / 8, a, [ph])
    free = make_scene(start=list(a), goal=list(ph.object_end))
    assert check_plan(plan, free).ok
    # a wall post that only the arms reach at the end: between robot front and held face
    px, py = _pole_in_gap(ph.object_end, 0, model, lateral=0.2)
    wall = make_scene(start=list(a), goal=list(ph.object_end), obstacles=[
        {"type": "box", "center": [px, py], "size": [0.06, 0.06], "yaw": 0.0, "height": 2.0}])
    world = CollisionWorld.from_scene(wall)
    end_robot = model.robot_pose(ph.object_end, 0)
    assert world.robot_distance(end_robot) > 0 and world.box_distance(ph.object_end) > 0
    rep = check_plan(plan, wall)
    assert not rep.ok
    assert any("robot collides" in p for p in rep.problems), rep.problems

"""The OMPL space, validity checker and pivot motion validator."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem, make_setup
from pivot_ompl.base.state import read_state, write_state
from pivot_ompl.validity.plan_check import check_plan

WALL = {"type": "box", "center": [4.0, 4.0], "size": [0.3, 4.0], "height": 1.0}


def test_sanity_checks():
    from pivot_ompl.base.space import sanity_checks

    p = make_problem(shipped("cluttered_room"))
    sanity_checks(p.space)


@pytest.mark.parametrize("name", ["cluttered_room", "fig10", "slot"])
def test_distances_stay_within_the_maximum_extent(name):
    """Regression: OMPL's distance-bound sanity check failed at random (a pair 0.7 % beyond
    the Reeds-Shepp extent); seeded pairs stay within 5 % of it, and come near it."""
    p = make_problem(shipped(name))
    ext = p.space.getMaximumExtent()
    x0, y0, x1, y1 = p.scene.bounds
    rng = np.random.default_rng(0)
    a, b = p.si.allocState(), p.si.allocState()
    worst = 0.0
    for _ in range(3000):
        for s in (a, b):
            write_state(s, (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
                            float(rng.uniform(-math.pi, math.pi))), int(rng.integers(4)))
        worst = max(worst, p.space.distance(a, b) / ext)
    assert 0.8 < worst <= 1.05, worst


def test_state_roundtrip_and_validity():
    p = make_problem(make_scene(obstacles=[WALL]))
    s = p.si.allocState()
    write_state(s, (1.5, 3.0, 0.2), 3)
    assert read_state(s) == ((1.5, 3.0, 0.2), 3)
    assert p.si.isValid(s)
    write_state(s, (4.0, 4.0, 0.0), 0)  # box inside the wall
    assert not p.si.isValid(s)
    write_state(s, (2.9, 4.0, 0.0), 2)  # box free, robot (grasp 2, on the +x side) in the wall
    assert p.checker.box_valid((2.9, 4.0, 0.0))
    assert not p.si.isValid(s)
    assert p.validity.clearance(s) < 0


def motion(p, a, ga, b, gb):
    s1, s2 = p.si.allocState(), p.si.allocState()
    write_state(s1, a, ga)
    write_state(s2, b, gb)
    return p.si.checkMotion(s1, s2)


def test_free_motion_valid_and_wall_crossing_invalid():
    p = make_problem(make_scene(obstacles=[WALL]))
    assert motion(p, (1.5, 1.0, 0.0), 0, (6.5, 1.0, 0.0), 0)       # below the wall
    assert not motion(p, (1.5, 4.0, 0.0), 0, (6.5, 4.0, 0.0), 0)   # through it
    assert p.checker.counters.valid >= 1 and p.checker.counters.invalid >= 1


def test_pivot_clipping_a_corner_is_rejected_though_ends_are_free():
    """A pillar sits where the swinging box passes between two pivot steps but not where any
    step ends: sampling the step ends would miss it, the certified sweep does not."""
    scene = make_scene()
    p = make_problem(scene)
    a, b = (2.0, 3.0, 0.0), (4.5, 3.5, 0.6)
    edge = p.checker.transfer(a, b, 0)
    assert edge.valid
    seq = edge.sequence
    m = scene.model
    from pivot_ompl.se2 import rotate_about
    # find a point swept by the box during rotation k but inside no step-end footprint
    target = None
    for k, rot in enumerate(seq.rotations):
        before = seq.rotations[k - 1].car if k else m.car_pose(a, 0)
        mid = m.object_from_car(rotate_about(before, rot.pivot, 0.5 * rot.angle), 0)
        for c in m.object_corners(mid):
            ends = [m.object_from_car(r.car, 0) for r in seq.rotations] + [a]
            if all(_outside(c, e, m) for e in ends):
                target = c
                break
        if target:
            break
    assert target is not None, "no clipping point found"
    pillar = {"type": "cylinder", "center": list(target), "radius": 0.01, "height": 1.0}
    # (the plan of the refined edge is checked below: the scene runs from a to b)
    clipped = make_problem(make_scene(obstacles=[pillar], start=list(a), goal=list(b)))
    assert clipped.checker.state_valid(a, 0) and clipped.checker.state_valid(b, 0)
    for r in seq.rotations:  # every step end is free ...
        assert clipped.checker.world.box_distance(m.object_from_car(r.car, 0)) > 0
    # ... and the motion is rejected, unless the finer subdivision avoids the pillar
    res = clipped.checker.transfer(a, b, 0)
    if res.valid:
        assert any(abs(r.angle) < scene.alpha_max / 1.9 for r in res.sequence.rotations)
        rep = check_plan(path_to_plan(clipped.scene, clipped.checker, [(a, 0), (b, 0)]),
                         clipped.scene)
        assert rep.ok, rep.problems
    else:  # rejected for the pillar: met, or nearer than the clearance-bounded rotations allow
        assert "collides" in res.reason or "of an obstacle" in res.reason, res.reason


def _outside(pt, obj, m, margin=0.03):
    c, s = math.cos(obj[2]), math.sin(obj[2])
    dx, dy = pt[0] - obj[0], pt[1] - obj[1]
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    return abs(lx) > m.object_size[0] / 2 + margin or abs(ly) > m.object_size[1] / 2 + margin


def test_grasp_change_only_at_equal_poses():
    p = make_problem(make_scene())
    q = (4.0, 3.0, 0.3)
    assert motion(p, q, 0, q, 2)
    assert not motion(p, q, 0, (4.0, 3.0 + 1e-6, 0.3), 2)
    assert not motion(p, q, 1, (5.0, 3.0, 0.3), 2)


def test_walk_round_box_is_collision_free():
    p = make_problem(make_scene())
    w = p.checker.transit((4.0, 3.0, 0.3), 0, 2)
    assert w.valid and w.length > 0
    m = p.scene.model
    assert w.robot_path[0] == m.robot_pose((4.0, 3.0, 0.3), 0)
    assert w.robot_path[-1] == m.robot_pose((4.0, 3.0, 0.3), 2)
    for q in w.robot_path:
        assert p.checker.world.robot_box_distance(q, (4.0, 3.0, 0.3)) > 0


def test_walk_blocked_when_box_cannot_be_rounded():
    # box in a dead-end 1 m wide: the robot cannot get round to the far face
    obs = [{"type": "box", "center": [5.0, 2.2], "size": [3.0, 0.2], "height": 1.0},
           {"type": "box", "center": [5.0, 3.8], "size": [3.0, 0.2], "height": 1.0},
           {"type": "box", "center": [6.6, 3.0], "size": [0.2, 1.8], "height": 1.0}]
    p = make_problem(make_scene(obstacles=obs, goal=[5.5, 3.0, 0.0]))
    assert p.checker.state_valid((5.0, 3.0, 0.0), 0)
    assert p.checker.state_valid((5.0, 3.0, 0.0), 2)  # the far grasp pose itself is free
    assert not p.checker.transit((5.0, 3.0, 0.0), 0, 2).valid  # but cannot be reached


@pytest.mark.parametrize("planner", ["rrtconnect", "kpiece1", "visprm"])
def test_ompl_baselines_on_open_scene(planner):
    from ompl import geometric as og

    from pivot_ompl.planners import make_planner

    scene = shipped("cluttered_room")
    problem = make_setup(scene)
    ss = problem.setup
    ss.setPlanner(make_planner(planner, problem, seed=0))
    status = ss.solve(20.0)
    assert str(status) == "Exact solution"
    path = ss.getSolutionPath()
    states = [read_state(path.getState(i)) for i in range(path.getStateCount())]
    assert states[0][0] == pytest.approx(scene.start) and states[-1][0] == pytest.approx(scene.goal)
    plan = path_to_plan(scene, problem.checker, states)
    rep = check_plan(plan, scene)
    assert rep.ok, rep.problems
    del og

"""Transit walks round the resting box: from one grasp pose to the other, every segment free."""

from __future__ import annotations

import pytest
from factories import make_scene

from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.validity.pivot_checker import PivotChecker
from pivot_ompl.validity.plan_check import check_plan

POSE = (4.0, 3.0, 0.3)


@pytest.mark.parametrize(("g1", "g2"), [(0, 1), (0, 2), (1, 3), (3, 2), (2, 0)])
def test_walks_join_the_grasp_poses_and_pass_check(g1, g2):
    scene = make_scene(start=list(POSE), goal=list(POSE))
    ck = PivotChecker(scene, seed=0)
    walk = ck.transit(POSE, g1, g2)
    assert walk.valid
    m = scene.model
    assert walk.robot_path[0] == pytest.approx(m.robot_pose(POSE, g1))
    assert walk.robot_path[-1] == pytest.approx(m.robot_pose(POSE, g2))
    assert walk.length > 0
    plan = Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, POSE,
                [TransferPhase(g1, m.robot_pose(POSE, g1), (), POSE),
                 TransitPhase(g1, g2, walk.robot_path, POSE),
                 TransferPhase(g2, m.robot_pose(POSE, g2), (), POSE)])
    rep = check_plan(plan, scene)
    assert rep.ok, rep.problems


def test_no_walk_through_a_wall_round_the_box():
    # the box stands in a 1.5 m wide corridor closed at one end: beside the box there is
    # 0.45 m, less than the robot's 0.40 m depth plus the 0.08 m kept from the box, so not
    # even a side step gets it round
    walls = [{"type": "box", "center": [4.0, 2.0], "size": [8.0, 0.5], "yaw": 0.0,
              "height": 2.0},
             {"type": "box", "center": [4.0, 4.0], "size": [8.0, 0.5], "yaw": 0.0,
              "height": 2.0},
             {"type": "box", "center": [2.6, 3.0], "size": [0.2, 3.0], "yaw": 0.0,
              "height": 2.0}]
    scene = make_scene(obstacles=walls, start=[4.0, 3.0, 0.0], goal=[6.0, 3.0, 0.0])
    ck = PivotChecker(scene, seed=0)
    assert ck.state_valid((4.0, 3.0, 0.0), 2)
    assert not ck.transit((4.0, 3.0, 0.0), 2, 0).valid


def test_walk_search_honours_the_termination_condition():
    """A large floor's grid takes seconds: the walk stops at the limit and resumes later."""
    import time

    from pivot_ompl.validity.walking import INVALID_WALK

    scene = make_scene(bounds=[0.0, 0.0, 60.0, 60.0], start=[30.0, 30.0, 0.0],
                       goal=[40.0, 30.0, 0.0])
    ck = PivotChecker(scene, seed=0)
    for _ in range(2):
        deadline = time.monotonic() + 0.3
        ck.should_stop = lambda d=deadline: time.monotonic() > d
        t0 = time.monotonic()
        assert ck.transit(scene.start, 0, 2) is INVALID_WALK
        assert time.monotonic() - t0 < 1.5
    done = ck.walker._rows_done
    assert 0 < done < 601  # the rows of both calls are kept, not rebuilt
    assert not ck._walks  # an interrupted walk is not cached

"""Poses along a car's path: clearance carried between poses, answers those of every pose.

The cheap test before a transfer's check skips the query of a body whose clearance at the
last pose exceeds how far it can move to the next; its answer must be every pose's own.
"""

from __future__ import annotations

import math

from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker

#: Posts and a wall across the floor: paths pass them closely or cross them.
OBSTACLES = [{"type": "cylinder", "center": [x, y], "radius": 0.15, "height": 1.0}
             for x in (2.0, 4.0, 6.0) for y in (1.5, 4.5)] + \
    [{"type": "box", "center": [4.0, 3.0], "size": [0.2, 1.2], "height": 1.0}]

CHECKER = PivotChecker(make_scene(obstacles=OBSTACLES), share=False)


def _every_pose(car_a, car_b, grasp: int, ts: list[float], with_robot: bool) -> bool:
    ck = CHECKER
    for c in ck.steering.paths.sample(car_a, car_b, ts):
        obj = ck.model.object_from_car(c, grasp)
        if not (ck.state_valid(obj, grasp) if with_robot else ck.box_valid(obj)):
            return False
    return True


@settings(max_examples=300, deadline=None)
@given(xa=st.floats(0.5, 7.5), ya=st.floats(0.5, 5.5), ha=st.floats(-math.pi, math.pi),
       dx=st.floats(-3.0, 3.0), dy=st.floats(-3.0, 3.0), dh=st.floats(-math.pi, math.pi),
       spin=st.booleans(), grasp=st.integers(0, 3), with_robot=st.booleans(),
       n=st.integers(2, 40))
def test_the_path_test_answers_as_every_pose_tested(xa, ya, ha, dx, dy, dh, spin, grasp,
                                                    with_robot, n):
    a = (xa, ya, ha)
    b = (xa, ya, ha + dh) if spin else (xa + dx, ya + dy, ha + dh)
    ts = [k / n for k in range(1, n)]
    want = _every_pose(a, b, grasp, ts, with_robot)
    assert CHECKER.cars_free(a, b, grasp, ts, with_robot=with_robot) == want


def test_a_path_in_open_floor_queries_few_of_its_poses():
    # regression: every pose of the cheap test was queried for the box and the robot, though
    # in open floor the clearance of one pose already proves the next few free
    ck = PivotChecker(make_scene(), share=False)  # no obstacle but the bounds' sides
    ck2 = PivotChecker(make_scene(obstacles=OBSTACLES[:1]), share=False)
    a, b = (0.6, 5.0, 0.0), (7.0, 5.2, 0.0)  # far from the post at (2, 1.5)
    ts = [k / 40 for k in range(1, 40)]
    assert ck.cars_free(a, b, 0, ts)
    before = ck2.world.queries
    assert ck2.cars_free(a, b, 0, ts)
    assert ck2.world.queries - before < len(ts)  # every pose would be two queries

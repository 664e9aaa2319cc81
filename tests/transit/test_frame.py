"""The walk lattice's frame: turned to the walls, walks mapped back and certified."""

from __future__ import annotations

import math

import pytest
from factories import shipped, walk_problems
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.generate import rotate_scene
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, PolygonObstacle
from pivot_ompl.transit.frame import LatticeFrame, wall_yaw


def _quarter(a: float) -> float:
    """``a`` modulo a quarter turn, in [-pi/4, pi/4)."""
    return (a + 0.25 * math.pi) % (0.5 * math.pi) - 0.25 * math.pi


@settings(max_examples=60, deadline=None)
@given(yaw=st.floats(-math.pi, math.pi), other=st.floats(-math.pi, math.pi),
       n=st.integers(1, 6))
def test_the_walls_direction_is_the_longest_edges_modulo_a_quarter_turn(yaw, other, n):
    """Long walls at ``yaw`` (in any of its four directions) beside shorter boxes at another
    angle and pillars: the frame is the long walls' direction, modulo a quarter turn."""
    walls = [BoxObstacle((3.0 * i, 0.0), (4.0, 0.3), yaw + i * 0.5 * math.pi, 2.0)
             for i in range(n)]
    small = [BoxObstacle((0.0, 5.0), (0.5, 0.5), other, 1.0),
             CylinderObstacle((1.0, 1.0), 2.0, 1.0)]
    got = wall_yaw(walls + small)
    assert -0.25 * math.pi <= got < 0.25 * math.pi
    assert abs(_quarter(got - yaw)) < 1e-6


def test_walls_along_the_axes_give_exactly_no_turn():
    polygon = PolygonObstacle(((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)), 1.0)
    assert wall_yaw([polygon, BoxObstacle((5.0, 5.0), (3.0, 0.2), math.pi / 2, 1.0)]) == 0.0
    assert wall_yaw([CylinderObstacle((0.0, 0.0), 1.0, 1.0)]) == 0.0
    for name in ("fig10", "slot", "corridor", "door"):
        assert PivotChecker(shipped(name)).walker.frame.identity


@given(x=st.floats(-50, 50), y=st.floats(-50, 50), yaw=st.floats(-4, 4),
       turn=st.floats(-math.pi, math.pi))
def test_a_pose_mapped_into_the_frame_and_back_is_itself(x, y, yaw, turn):
    f = LatticeFrame(turn, (3.0, -2.0))
    back = f.out(f.into((x, y, yaw)))
    assert back == pytest.approx((x, y, yaw), abs=1e-9)
    assert f.into((x, y, yaw))[2] == yaw - turn  # not wrapped: yaws stay continuous


def test_building_the_turned_floor_polls_the_stop():
    scene = rotate_scene(shipped("fig10"), 0.4)
    calls = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) > 40  # past the collision world's own polls

    with pytest.raises(Interrupted):
        PivotChecker(scene, should_stop=stop)


@pytest.mark.parametrize("angle", [0.3, 1.0, -2.2])
def test_walks_on_a_turned_floor_are_planned_in_its_frame_and_pass_the_check(angle):
    """fig10 turned by ``angle``: the lattice is turned with it, so the walk round the box by
    the wall's door is the one of the unturned floor, turned; it ends exactly at the grasp
    poses and passes the independent check."""
    base = shipped("fig10")
    scene = rotate_scene(base, angle)
    ck = PivotChecker(scene)
    assert abs(_quarter(ck.walker.frame.yaw - angle)) < 1e-9
    ck0 = PivotChecker(base)
    obj0 = (3.69, 1.46, 0.0)  # the demo's first regrasp: round by wall A's door
    walk0 = ck0.transit(obj0, 0, 2)
    c = ck.walker.frame.centre
    dx, dy = obj0[0] - c[0], obj0[1] - c[1]
    ca, sa = math.cos(angle), math.sin(angle)
    obj = (c[0] + ca * dx - sa * dy, c[1] + sa * dx + ca * dy, angle)
    walk = ck.transit(obj, 0, 2)
    assert walk0.valid and walk.valid
    m = scene.model
    assert walk.robot_path[0] == m.robot_pose(obj, 0)
    assert walk.robot_path[-1] == m.robot_pose(obj, 2)
    assert walk_problems(scene, obj, 0, 2, walk) == []
    assert walk.cost <= 1.25 * walk0.cost  # the grid lies otherwise on the walls: not equal


def test_the_cached_floor_distances_hold_at_most_their_byte_budget(monkeypatch):
    """A whole-floor field per cached query: their number is bounded by DISTANCE_BYTES
    (at least two kept), so a large floor does not keep 64 of them."""
    import numpy as np

    from pivot_ompl.transit import guides

    scene = shipped("fig10")
    probe = PivotChecker(scene).walker
    per_field = 8 * probe.field.grid.nx * probe.field.grid.ny
    monkeypatch.setattr(guides, "DISTANCE_BYTES", 3 * per_field)
    ck = PivotChecker(scene)
    rng = np.random.default_rng(0)
    x0, y0, x1, y1 = scene.bounds
    walks = 0
    while walks < 8:
        obj = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)), 0.0)
        if ck.state_valid(obj, 0) and ck.state_valid(obj, 2):
            ck.transit(obj, 0, 2)
            walks += 1
            assert ck.walker.cached_fields()[0] <= 3
    assert ck.walker.cached_fields()[0] == 3

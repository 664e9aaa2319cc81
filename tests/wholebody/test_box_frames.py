"""The held box's frames: rotations about a vertical, the grips in the world."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.wholebody.box import BoxHold, rot_y, rot_z, rotation_about_vertical, transform

coords = st.floats(-50.0, 50.0)
angles = st.floats(-7.0, 7.0)


@given(coords, coords, angles, coords, coords, st.floats(0.0, 2.0))
def test_a_rotation_about_a_vertical_keeps_its_axis_and_turns_by_its_angle(px, py, a, x, y, z):
    T = rotation_about_vertical((px, py), a)
    assert T.shape == (4, 4) and np.array_equal(T[3], [0.0, 0.0, 0.0, 1.0])
    assert np.allclose(T[:3, :3], rot_z(a), atol=1e-15)
    assert np.allclose(T @ [px, py, z, 1.0], [px, py, z, 1.0], atol=1e-12)  # the axis stays
    moved = T @ [x, y, z, 1.0]
    r = math.hypot(x - px, y - py)
    assert math.hypot(moved[0] - px, moved[1] - py) == pytest.approx(r, abs=1e-9)
    if r > 1e-6:  # turned by the angle about the pivot
        turn = math.atan2(moved[1] - py, moved[0] - px) - math.atan2(y - py, x - px)
        assert math.remainder(turn - a, 2 * math.pi) == pytest.approx(0.0, abs=1e-7)


@given(st.integers(0, 3), st.floats(0.0, 0.3), coords, coords, angles)
def test_the_grips_ride_in_the_tilted_grasp_frame(grasp, tilt, x, y, yaw):
    hold = BoxHold((0.8, 0.4, 1.0))
    G = hold.T_world_G((x, y, yaw), grasp)
    left, right = hold.T_world_hands(G, grasp, tilt)
    Tt = G @ transform(rot_y(-tilt), (0.0, 0.0, 0.0))
    want_l, want_r = hold.T_G_hands(grasp)
    assert np.allclose(left, Tt @ want_l, atol=1e-12)
    assert np.allclose(right, Tt @ want_r, atol=1e-12)
    assert left.flags.writeable  # the caller's own array, not the cache's

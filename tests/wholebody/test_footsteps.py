"""Footstep planning without a robot: limits per step, alternating feet, the path's end reached."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.wholebody.footsteps import (
    Footstep,
    chunks,
    feet_frames,
    left_flies_first,
    path_footsteps,
    pivot_footsteps,
    planar,
    relative,
    stance_pose,
)
from pivot_ompl.wholebody.settings import WalkSettings

EPS = 1e-9


def _landings_within_limits(steps: list[Footstep], s: WalkSettings) -> None:
    """Each landing beside the foot it steps past, within the per-foot limits."""
    for support, fly in zip(steps[1:], steps[2:], strict=False):
        assert support.left != fly.left  # the feet alternate
        dx, dy, dth = relative(planar(support.frame), planar(fly.frame))
        sign = 1.0 if fly.left else -1.0
        out = sign * dy - s.feet_spacing  # > 0: outside the nominal place
        assert -s.max_dx_backward - EPS <= dx <= s.max_dx_forward + EPS
        assert -s.foot_dy_in - EPS <= out <= s.foot_dy_out + EPS
        assert abs(dth) <= s.foot_dtheta + EPS


def _stances(steps: list[Footstep], s: WalkSettings) -> list[Pose]:
    """The robot pose of every double support: the start and after each landing."""
    feet = {steps[0].left: steps[0].frame, steps[1].left: steps[1].frame}
    out = [stance_pose(feet[True], feet[False], s)]
    for f in steps[2:]:
        feet[f.left] = f.frame
        out.append(stance_pose(feet[True], feet[False], s))
    return out


def _ends_at(steps: list[Footstep], pose: Pose, s: WalkSettings) -> None:
    last = {f.left: f.frame for f in steps}
    want_l, want_r = feet_frames(pose, s)
    assert np.allclose(last[True], want_l, atol=1e-9)
    assert np.allclose(last[False], want_r, atol=1e-9)


@settings(max_examples=20, deadline=None)
@given(length=st.floats(0.2, 2.0), back=st.booleans(), forward=st.floats(0.06, 0.15),
       backward=st.floats(0.04, 0.08))
def test_straight_walks_keep_every_robot_pose_step_within_the_scene_limits(
        length, back, forward, backward):
    walk = WalkParameters(step_forward=forward, step_backward=backward)
    s = WalkSettings.from_walk(walk)
    start = (0.0, 0.0, 0.0)
    end = (-length if back else length, 0.0, 0.0)
    steps = path_footsteps([end], feet=feet_frames(start, s), settings=s)
    _landings_within_limits(steps, s)
    _ends_at(steps, end, s)
    stances = _stances(steps, s)
    for a, b in zip(stances, stances[1:], strict=False):
        dx, dy, dth = relative(a, b)
        assert -walk.step_backward - EPS <= dx <= walk.step_forward + EPS
        assert abs(dy) < 1e-9 and abs(dth) < 1e-9
    # the limits bind: no fewer steps than the distance allows
    assert len(steps) - 2 >= length / (walk.step_backward if back else walk.step_forward)


def test_smaller_forward_steps_take_more_steps_than_hrp2s():
    path = [(1.0, 0.0, 0.0), (1.0, -0.4, 0.5)]
    counts = {}
    for forward in (0.15, 0.10):
        s = WalkSettings.from_walk(WalkParameters(step_forward=forward))
        steps = path_footsteps(path, feet=feet_frames((0.0, 0.0, 0.0), s), settings=s)
        _landings_within_limits(steps, s)
        _ends_at(steps, path[-1], s)
        assert max(relative(planar(a.frame), planar(b.frame))[0]
                   for a, b in zip(steps[1:], steps[2:], strict=False)) <= forward + EPS
        counts[forward] = len(steps)
    assert counts[0.10] > counts[0.15]


def test_hrp2_walk_model_gives_the_default_settings():
    assert WalkSettings.from_walk(WalkParameters()) == WalkSettings()


def test_narrow_scene_limits_shrink_the_legs_lateral_and_yaw_range():
    s = WalkSettings.from_walk(WalkParameters(step_lateral=0.03, step_turn=0.125))
    d = WalkSettings()
    assert s.foot_dy_out == pytest.approx(0.5 * d.foot_dy_out)
    assert s.foot_dtheta == pytest.approx(0.5 * d.foot_dtheta)
    wide = WalkSettings.from_walk(WalkParameters(step_lateral=0.5, step_turn=1.0))
    assert (wide.foot_dy_out, wide.foot_dtheta) == (d.foot_dy_out, d.foot_dtheta)


@settings(max_examples=20, deadline=None)
@given(angle=st.floats(-math.pi / 8, math.pi / 8).filter(lambda a: abs(a) > 0.01),
       heading=st.floats(-math.pi, math.pi), step_turn=st.floats(0.15, 0.25))
def test_pivot_arcs_end_with_both_feet_at_the_arcs_end(angle, heading, step_turn):
    s = WalkSettings.from_walk(WalkParameters(step_turn=step_turn))
    start = (0.3, -0.2, heading)
    pivot = (start[0] + 0.6 * math.cos(heading) - 0.4 * math.sin(heading),
             start[1] + 0.6 * math.sin(heading) + 0.4 * math.cos(heading))
    arc = [rotate_about(start, pivot, angle * u / 8) for u in range(9)]
    steps = pivot_footsteps(arc, feet=feet_frames(start, s), settings=s)
    assert 2 <= len(steps) - 2 <= 8
    _landings_within_limits(steps, s)
    _ends_at(steps, arc[-1], s)
    assert steps[2].left == steps[0].left  # the list is led by the flying foot


def test_no_pivot_step_when_the_feet_stand_at_the_end():
    s = WalkSettings()
    pose = (1.0, 2.0, 0.3)
    assert pivot_footsteps([pose, pose], feet=feet_frames(pose, s), settings=s) == []


@settings(max_examples=30, deadline=None)
@given(moves=st.integers(1, 60), max_steps=st.integers(1, 25))
def test_chunks_are_walks_of_at_most_max_steps_led_by_their_current_feet(moves, max_steps):
    steps = list(range(moves + 2))  # two current feet, then the moves
    walks = chunks(steps, max_steps)
    assert all(1 <= len(w) - 2 <= max_steps for w in walks)
    assert walks[0][:2] == [0, 1]
    for a, b in zip(walks, walks[1:], strict=False):
        assert b[:2] == a[-2:]  # a walk starts from the feet the last one ended on
    assert [m for w in walks for m in w[2:]] == steps[2:]


def test_left_foot_leads_towards_the_left_or_a_left_turn():
    s = WalkSettings()
    T_l, T_r = feet_frames((0.0, 0.0, 0.0), s)
    assert left_flies_first(T_l, T_r, (0.0, 0.3, 0.0))
    assert not left_flies_first(T_l, T_r, (0.0, -0.3, 0.0))
    assert left_flies_first(T_l, T_r, (0.5, 0.0, 0.2))
    assert not left_flies_first(T_l, T_r, (0.5, 0.0, -0.2))

"""Whole body: pivot steps walked continuously (two or three footsteps a pivot, no rest)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan
from pivot_ompl.se2 import rotate_about
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.footsteps import relative as _relative
from pivot_ompl.wholebody.motion_checks import check_motion
from pivot_ompl.wholebody.walker import PlacoWalker, WalkSettings

SIZE = (0.8, 0.4, 1.0)
#: Seconds of motion a pivot step of a straight push may cost (three steps of 0.8 s, and the
#: rest at the end of each walk shared by its pivots); the walk before this change took 7.6.
MAX_PER_PIVOT = 2.8


def straight_push(length: float, *, heading: float = 0.0) -> Plan:
    """A straight push of ``length`` m at grasp 0 with alpha_max = 22.5 deg."""
    model = BoxGraspModel(SIZE, standoff=0.25)
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    a = (0.0, 0.0, heading)
    b = (length * math.cos(heading), length * math.sin(heading), heading)
    ph = transfer_phase(model, steering, [a, b], 0)
    return Plan("test", "exact", SIZE, (0.40, 0.70), 0.25, math.pi / 8, a, [ph])


@pytest.fixture(scope="module")
def walker():
    return PlacoWalker(WalkSettings(), (0.0, 0.0, 0.0))


def _pivot_footsteps(walker, plan):
    """Footsteps of every pivot of the plan's first phase, chained as in one walk."""
    ph = plan.phases[0]
    feet = walker.feet_frames(ph.robot_start)
    fly, before, out = None, ph.robot_start, []
    for step in ph.steps:
        arc = [rotate_about(before, step.pivot, step.angle * u / 8) for u in range(9)]
        fs = walker.pivot_footsteps(arc, feet=feet, fly_left=fly)
        out.append(fs)
        if not fs:
            break
        left = [np.array(f.frame) for f in fs if str(f.side) == "left"]
        right = [np.array(f.frame) for f in fs if str(f.side) == "right"]
        feet = (left[-1], right[-1])
        fly = str(fs[-1].side) != "left"
        before = step.robot
    return out


@settings(max_examples=8, deadline=None)
@given(heading=st.floats(-math.pi, math.pi), length=st.floats(0.3, 1.2))
def test_pivots_take_two_or_three_alternating_steps(walker, heading, length):
    plan = straight_push(length, heading=heading)
    s = walker.settings
    sides: list[str] = []
    for step, fs in zip(plan.phases[0].steps, _pivot_footsteps(walker, plan), strict=True):
        assert 2 <= len(fs) - 2 <= 3  # footsteps led by the two current feet
        sides += [str(f.side) for f in fs[2:]]
        frames = {str(f.side): np.array(f.frame) for f in fs}  # the last of each side
        want_l, want_r = walker.feet_frames(step.robot)
        assert np.allclose(frames["left"], want_l, atol=1e-9)
        assert np.allclose(frames["right"], want_r, atol=1e-9)
        for a, b in zip(fs[1:], fs[2:], strict=False):  # landing beside the support foot
            Ta, Tb = np.array(a.frame), np.array(b.frame)
            pa = (Ta[0, 3], Ta[1, 3], math.atan2(Ta[1, 0], Ta[0, 0]))
            pb = (Tb[0, 3], Tb[1, 3], math.atan2(Tb[1, 0], Tb[0, 0]))
            dx, dy, dth = _relative(pa, pb)
            assert abs(dth) <= s.foot_dtheta + 1e-9
            assert -s.max_dx_backward - 1e-9 <= dx <= s.max_dx_forward + 1e-9
            assert s.feet_spacing - s.foot_dy_in - 1e-9 <= abs(dy)
            assert abs(dy) <= s.feet_spacing + s.foot_dy_out + 1e-9
    assert all(a != b for a, b in zip(sides, sides[1:], strict=False))  # one walk alternates


@pytest.fixture(scope="module")
def push():
    plan = straight_push(1.0)
    motion, stats = generate_motion(plan)
    return plan, motion, stats


def test_a_straight_push_costs_under_max_per_pivot(push):
    plan, motion, _ = push
    pivots = len(plan.phases[0].steps)
    assert pivots >= 8
    in_pivots = float(np.count_nonzero(motion.step >= 0)) * motion.dt
    assert in_pivots / pivots <= MAX_PER_PIVOT, (in_pivots, pivots)


def test_a_straight_push_passes_every_check(push):
    plan, motion, _ = push
    report = check_motion(motion, plan)
    assert report.passed, report.table()


def test_breakdown_accounts_for_every_second_and_the_fit_for_the_total(push):
    from pivot_ompl.quality import plan_quality
    from pivot_ompl.wholebody.durations import duration_breakdown, fit_duration_model

    plan, motion, _ = push
    split = duration_breakdown(motion, plan)
    assert len(split.pivots) == plan.pivots
    seconds = sum(s for _, s in split.pivots) + sum(split.transfer_rest)
    assert seconds == pytest.approx(motion.duration, abs=2 * motion.dt)
    fitted = fit_duration_model(split)
    estimate = plan_quality(plan, durations=fitted)["duration_estimate"]
    assert estimate == pytest.approx(motion.duration, rel=0.01)


def test_the_plans_duration_estimate_is_honest_for_a_straight_push(push):
    from pivot_ompl.quality import plan_quality

    plan, motion, _ = push
    estimate = plan_quality(plan)["duration_estimate"]
    assert abs(estimate - motion.duration) <= 0.15 * motion.duration, (estimate, motion.duration)

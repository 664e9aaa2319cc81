"""Turns in place: the spin path between two car poses at one position, and its pivots."""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.pivoting.curves import SPIN_RADIUS, CarPaths
from pivot_ompl.pivoting.spin_chain import spin_chain
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.se2 import wrap_angle

AMAX = math.pi / 8
poses = st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi))


@settings(max_examples=60, deadline=None)
@given(p=poses, turn=st.floats(0.05, math.pi), ell=st.sampled_from([0.2, 0.3, 0.4]),
       sign=st.sampled_from([1.0, -1.0]))
def test_a_spin_reaches_its_goal_exactly_and_stays_at_its_place(p, turn, ell, sign):
    steering = PivotSteering(turning_radius=2.0, alpha_max=AMAX)
    goal = (p[0], p[1], wrap_angle(p[2] + sign * turn))
    assert steering.paths.is_spin(p, goal)
    seq = steering.convert(p, goal, half_length=ell)
    end = seq.rotations[-1].car
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9
    assert all(abs(r.angle) <= AMAX + 1e-9 for r in seq.rotations)
    # the car never strays from its place by more than an edge end's arc of a rotation
    for r in seq.rotations:
        assert math.hypot(r.car[0] - p[0], r.car[1] - p[1]) <= 2 * ell * math.sin(AMAX) + 1e-9
    # three rotations per piece of at most 2 alpha: a half turn takes about 12
    assert len(seq.rotations) <= 3 * math.ceil(turn / (2 * AMAX) - 1e-9)


def test_spin_path_interpolates_the_heading_the_short_way():
    paths = CarPaths(turning_radius=2.0)
    a, b = (1.0, 2.0, 3.0), (1.0, 2.0, -3.0)  # 0.28 rad counter-clockwise across pi
    mid = paths.interpolate(a, b, 0.5)
    assert mid[:2] == (1.0, 2.0) and abs(wrap_angle(mid[2] - math.pi)) < 1e-12
    assert paths.distance(a, b) == SPIN_RADIUS * abs(wrap_angle(b[2] - a[2]))
    assert not paths.is_spin(a, (1.0 + 1e-6, 2.0, -3.0))  # elsewhere: Reeds-Shepp
    assert not paths.is_spin(a, a)


@settings(max_examples=80, deadline=None)
@given(exponent=st.floats(-13.0, -6.0), sign=st.sampled_from([1.0, -1.0]),
       grasp=st.integers(0, 3))
def test_a_box_turned_by_nanoradians_about_its_centre_is_steered(exponent, sign, grasp):
    """The box turned in place by a hair: its car moves by nanometres along the edge (the
    direction only the rotations' bracket reaches) and turns; still a transfer, arriving."""
    from factories import make_scene

    from pivot_ompl.checking.pivot_checker import PivotChecker

    turn = 10.0**exponent  # 1e-13 to 1e-6 rad, as many of each decade
    checker = PivotChecker(make_scene(bounds=[-10.0, -10.0, 10.0, 10.0]))
    edge = checker.transfer((0.0, 0.0, 0.0), (0.0, 0.0, sign * turn), grasp)
    assert edge.valid
    goal = checker.model.car_pose((0.0, 0.0, sign * turn), grasp)
    end = edge.sequence.rotations[-1].car if edge.sequence.rotations else \
        checker.model.car_pose((0.0, 0.0, 0.0), grasp)
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 2e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9


def test_a_box_turned_by_picoradians_about_its_centre_is_steered():
    """The car of grasp 0 (0.4 m from the box centre) turned by 2.5e-11 rad: the example found."""
    steering = PivotSteering(turning_radius=2.0, alpha_max=AMAX)
    yaw = 2.5292362992002202e-11
    goal = (-0.4 * math.cos(yaw), -0.4 * math.sin(yaw), yaw)
    seq = steering.convert((-0.4, 0.0, 0.0), goal, half_length=0.2)
    end = seq.rotations[-1].car if seq.rotations else (-0.4, 0.0, 0.0)
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9


@settings(max_examples=40, deadline=None)
@given(p=poses, turn=st.floats(0.3, math.pi), ell=st.sampled_from([0.2, 0.3, 0.4]),
       sign=st.sampled_from([1.0, -1.0]))
def test_a_spins_rotations_about_one_corner_in_a_row_could_not_merge(p, turn, ell, sign):
    steering = PivotSteering(turning_radius=2.0, alpha_max=AMAX)
    goal = (p[0], p[1], wrap_angle(p[2] + sign * turn))
    seq = steering.convert(p, goal, half_length=ell)
    for a, b in zip(seq.rotations, seq.rotations[1:], strict=False):
        assert a.end != b.end or abs(a.angle + b.angle) > AMAX
    end = seq.rotations[-1].car
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9


@pytest.mark.parametrize("ell", [0.2, 0.3, 0.4])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_half_turn_in_place_takes_nine_rotations(ell, sign):
    """One chain alternating corners, turning one way, closed at its place: one over the 8
    rotations a half turn needs at pi/8.

    Equal spin pieces took 11 (five pieces whose outer rotations merge at every junction,
    2 x 5 + 1); the chain needs no junction, and no pair in it could merge.
    """
    steering = PivotSteering(turning_radius=2.0, alpha_max=AMAX)
    start = (1.0, -2.0, 0.4)
    goal = (1.0, -2.0, wrap_angle(0.4 + sign * (math.pi - 1e-6)))
    seq = steering.convert(start, goal, half_length=ell)
    assert len(seq.rotations) == 9
    ends = [r.end for r in seq.rotations]
    assert all(a != b for a, b in zip(ends, ends[1:], strict=False))
    end = seq.rotations[-1].car
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9


@settings(max_examples=80, deadline=None)
@given(p=poses, turn=st.floats(0.05, math.pi - 1e-6), ell=st.sampled_from([0.15, 0.2, 0.4]),
       sign=st.sampled_from([1.0, -1.0]))
@example(p=(0.0, 0.0, 0.0), turn=0.75 * math.pi, ell=0.15, sign=-1.0)  # 9 with equal pieces
def test_a_spin_takes_at_most_two_rotations_over_what_its_turn_needs(p, turn, ell, sign):
    """Equal pieces took three over (a 135 degree turn: 9 rotations for the 6 it needs)."""
    steering = PivotSteering(turning_radius=2.0, alpha_max=AMAX)
    goal = (p[0], p[1], wrap_angle(p[2] + sign * turn))
    seq = steering.convert(p, goal, half_length=ell)
    assert len(seq.rotations) <= math.ceil(turn / AMAX - 1e-9) + 2
    end = seq.rotations[-1].car
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9


@settings(max_examples=60, deadline=None)
@given(p=poses, turn=st.floats(0.3, math.pi - 1e-6), ell=st.sampled_from([0.15, 0.2, 0.4]),
       sign=st.sampled_from([1.0, -1.0]), share=st.floats(0.05, 1.0))
def test_a_spin_chain_stays_near_its_place_and_arrives(p, turn, ell, sign, share):
    goal = (p[0], p[1], wrap_angle(p[2] + sign * turn))
    bound = share * ell * AMAX
    rots = spin_chain(p, goal, ell, AMAX, max_deviation=bound)
    if rots is None:  # too tight a bound for every chain tried
        return
    assert all(abs(r.angle) <= AMAX + 1e-12 for r in rots)
    for a, b in zip(rots, rots[1:], strict=False):
        assert a.end != b.end or abs(a.angle + b.angle) > AMAX
    for r in rots:
        sagitta = ell * (1.0 - math.cos(0.5 * r.angle))
        assert math.hypot(r.car[0] - p[0], r.car[1] - p[1]) + sagitta <= bound + 1e-12
    end = rots[-1].car
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9

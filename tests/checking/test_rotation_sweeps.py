"""The rotations' kernel: clearances measured lazily, answers those of measured clearances.

A run of rotations is checked with lower bounds of the clearances carried between rotations
(and out of the run); the answer must be the one a check that measures every clearance gives,
and every bound returned must be a lower bound of the measured clearance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.rotation_sweeps import Clearance, RotationSweeps
from pivot_ompl.generate import generate, mirror_scene
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.se2 import rotate_about
from pivot_ompl.validity.certify import certify

#: Posts 1.6 m apart and a wall: runs of rotations often pass one closely or hit it.
OBSTACLES = [{"type": "cylinder", "center": [x, y], "radius": 0.12, "height": 1.0}
             for x in (1.6, 3.2, 4.8, 6.4) for y in (1.5, 3.0, 4.5)] + \
    [{"type": "box", "center": [4.0, 2.2], "size": [0.2, 1.4], "height": 1.0}]

CHECKER = PivotChecker(make_scene(obstacles=OBSTACLES), share=False)


def _run(car, grasp: int, ends: list[int], angles: list[float],
         checker: PivotChecker = CHECKER) -> tuple[Rotation, ...]:
    """Rotations chained from ``car``, each about the given end of the car it starts from."""
    m = checker.model
    out = []
    for end, angle in zip(ends, angles, strict=True):
        pivot = m.pivots(car, grasp)[end]
        car = rotate_about(car, pivot, angle)
        out.append(Rotation(end, pivot, angle, car))
    return tuple(out)


def _measured_answer(sweeps: RotationSweeps, car, rots, grasp: int) -> str:
    """The run checked with every clearance measured: ``""`` or the failure."""
    r_box, r_rob = sweeps.reach[grasp]
    prev = car
    for rot in rots:
        bulge = 1.0 - math.cos(0.5 * rot.angle)
        if not (sweeps.in_bounds(prev, grasp, True, r_box * bulge, r_rob * bulge)
                and sweeps.in_bounds(rot.car, grasp, True, r_box * bulge, r_rob * bulge)):
            return "leaves the bounds"
        for dist, reach, why in ((sweeps.box_distance, r_box, "box collides"),
                                 (sweeps.robot_distance, r_rob, "robot collides")):
            def at(s: float, dist=dist, prev=prev, rot=rot) -> float:  # noqa: ANN001
                return dist(rotate_about(prev, rot.pivot, s * rot.angle), grasp)

            if not certify(at, reach * abs(rot.angle), tolerance=sweeps.tolerance,
                           exact=True).valid:
                return why
        prev = rot.car
    return ""


@settings(max_examples=300, deadline=None)
@given(x=st.floats(0.8, 7.2), y=st.floats(0.8, 5.2), h=st.floats(-math.pi, math.pi),
       grasp=st.integers(0, 3), first=st.integers(0, 1),
       angles=st.lists(st.floats(-0.6, 0.6), min_size=1, max_size=6))
def test_a_run_checked_lazily_answers_as_measured_clearances_do(x, y, h, grasp, first,
                                                                 angles):
    sweeps = CHECKER.transfers.sweeps
    car = (x, y, h)
    db, dr = sweeps.box_distance(car, grasp), sweeps.robot_distance(car, grasp)
    if db <= 0 or dr <= 0:
        return
    rots = _run(car, grasp, [(first + k) % 2 for k in range(len(angles))], angles)
    why, (cb, cr) = sweeps.rotations(car, rots, grasp, True, Clearance(db), Clearance(dr))
    assert why == _measured_answer(sweeps, car, rots, grasp)
    if not why:  # the ends: positive lower bounds of the clearances measured at the end
        end = rots[-1].car
        for c, dist in ((cb, sweeps.box_distance), (cr, sweeps.robot_distance)):
            assert c.at in (None, end)
            assert 0.0 < c.value <= dist(end, grasp)  # a bound kept below by the slack
        mb, mr = sweeps.measured((cb, cr), grasp)
        assert (mb.at, mr.at) == (None, None)
        assert mb.value == sweeps.box_distance(end, grasp)
        assert mr.value == sweeps.robot_distance(end, grasp)


def test_a_run_in_open_floor_makes_no_query():
    # regression: the run's last rotation's end was always measured (two queries a run, and
    # again for every piece of an edge), though the next piece's sweeps were free by the
    # bound alone and the edge's last end is never used
    ck = PivotChecker(make_scene(obstacles=OBSTACLES[-1:]), share=False)
    sweeps = ck.transfers.sweeps
    car, grasp = (1.5, 3.0, 0.0), 0
    rots = _run(car, grasp, [0, 1, 0], [0.15, -0.15, 0.15])
    clear = (Clearance(sweeps.box_distance(car, grasp)),
             Clearance(sweeps.robot_distance(car, grasp)))
    assert min(c.value for c in clear) > 0.5  # open floor round the run
    before = ck.world.queries
    why, ends = sweeps.rotations(car, rots, grasp, True, *clear)
    assert why == ""
    assert ck.world.queries == before
    assert all(c.at == rots[-1].car for c in ends)


def test_a_checked_edge_is_the_same_whatever_clearances_were_left_unmeasured():
    # the transfer check's answers on random edges near the posts: every valid edge's
    # rotations pass the check with measured clearances
    rng = np.random.default_rng(11)
    sweeps = CHECKER.transfers.sweeps
    checked = 0
    for _ in range(400):
        a = (float(rng.uniform(1.0, 7.0)), float(rng.uniform(1.0, 5.0)),
             float(rng.uniform(-math.pi, math.pi)))
        b = (a[0] + float(rng.uniform(-0.7, 0.7)), a[1] + float(rng.uniform(-0.7, 0.7)),
             a[2] + float(rng.uniform(-0.4, 0.4)))
        g = int(rng.integers(4))
        if not (CHECKER.state_valid(a, g) and CHECKER.state_valid(b, g)):
            continue
        res = CHECKER.transfer(a, b, g)
        if res.valid:
            checked += 1
            start = res.sequence.start
            assert _measured_answer(sweeps, start, res.sequence.rotations, g) == ""
    assert checked >= 8  # 9 of 27: a sweep within the tolerance of a post is refused


def test_an_edge_start_is_measured_once():
    # regression: every edge check measured its start's clearances again, though a planner's
    # edges share their starts (80 % of the starts of a house map's plan)
    ck = PivotChecker(make_scene(obstacles=OBSTACLES), share=False)
    sweeps = ck.transfers.sweeps
    car, grasp = (2.4, 2.2, 0.3), 1
    box_only = sweeps.start(car, grasp, False)
    assert box_only[0].value == sweeps.box_distance(car, grasp) and box_only[1].value == math.inf
    first = sweeps.start(car, grasp, True)
    before = ck.world.queries
    assert sweeps.start(car, grasp, True) == first
    assert sweeps.start(car, grasp, False)[0] == first[0]
    assert ck.world.queries == before
    assert first == (Clearance(sweeps.box_distance(car, grasp)),
                     Clearance(sweeps.robot_distance(car, grasp)))


def _walls_mirrored() -> PivotChecker:
    """``gen:walls:1`` reflected in the line at 0.3 rad through the floor's centre."""
    return PivotChecker(mirror_scene(generate("walls", 1).scene, 0.3, name="walls_1_mirror"),
                        share=False)


def test_a_rotation_dipping_into_a_wall_between_samples_is_refused():
    # regression: the sweep was accepted once its samples were 2 * tolerance apart with both
    # ends free, and this rotation's box dips 47 micrometres into a wall between two of its
    # samples; the plan then wrote it merged with the next rotation about the same corner,
    # whose sampling fell on the dip, and ``check_plan`` rejected the plan
    ck = _walls_mirrored()
    sweeps = ck.transfers.sweeps
    car, grasp = (6.170718055566062, 4.990205399368035, 3.205720522985961), 0
    first = _run(car, grasp, [1], [-0.10072167790157849], ck)
    both = _run(car, grasp, [1, 1], [-0.10072167790157849, -0.12542190381273777], ck)
    merged = _run(car, grasp, [1], [-0.10072167790157849 - 0.12542190381273777], ck)
    assert merged[0].car == pytest.approx(both[-1].car, abs=1e-12)
    m = ck.model

    def box(s: float) -> float:  # the box's distance along the first rotation
        return sweeps.world.box_distance(m.object_from_car(
            rotate_about(car, first[0].pivot, s * first[0].angle), grasp))

    assert min(box(k / 400) for k in range(401)) < 0.0  # the truth: it collides
    start = sweeps.start(car, grasp, True)
    for rots in (first, both, merged):
        assert sweeps.rotations(car, rots, grasp, True, *start)[0] == "box collides"


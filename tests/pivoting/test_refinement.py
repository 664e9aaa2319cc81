"""Local refinement: only the piece of an edge that collides is converted with smaller angles."""

from __future__ import annotations

import math

import pytest
from factories import make_scene

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.errors import InputError
from pivot_ompl.se2 import rotate_about
from pivot_ompl.validity.plan_check import check_plan

A, B = (2.0, 3.0, 0.0), (6.0, 3.2, 0.3)


def _inside(pt, obj, m, margin=0.02):
    c, s = math.cos(obj[2]), math.sin(obj[2])
    dx, dy = pt[0] - obj[0], pt[1] - obj[1]
    u, v = c * dx + s * dy, -s * dx + c * dy
    hx, hy = 0.5 * m.object_size[0] + margin, 0.5 * m.object_size[1] + margin
    return abs(u) <= hx and abs(v) <= hy


def _clipping_pillar(scene, seq, a, steering):
    """A thin pillar swept by the box in mid-rotation but clear of every step's end pose.

    Clear of the box on the Reeds-Shepp path too (where the refinement starts its
    sub-pieces), so that the refined rotations can pass it.
    """
    m = scene.model
    ts = [i / 400 for i in range(401)]
    ends = [m.object_from_car(r.car, 0) for r in seq.rotations] + [a] + [
        m.object_from_car(c, 0) for c in steering.paths.sample(seq.start, seq.goal, ts)]
    for k, rot in enumerate(seq.rotations[3:], start=3):
        before = seq.rotations[k - 1].car
        mid = m.object_from_car(rotate_about(before, rot.pivot, 0.5 * rot.angle), 0)
        for c in m.object_corners(mid):
            if not any(_inside(c, e, m) for e in ends):
                return {"type": "cylinder", "center": list(c), "radius": 0.005, "height": 1.0}
    raise AssertionError("no clipping point found")


def test_only_the_colliding_piece_is_refined():
    free = make_problem(make_scene(start=list(A), goal=list(B)))
    edge = free.checker.transfer(A, B, 0)
    assert edge.valid
    pillar = _clipping_pillar(free.scene, edge.sequence, A, free.checker.steering)
    scene = make_scene(start=list(A), goal=list(B), obstacles=[pillar])
    clipped = make_problem(scene)
    res = clipped.checker.transfer(A, B, 0)
    assert res.valid, res.reason
    assert clipped.checker.counters.refined_pieces >= 1
    rep = check_plan(path_to_plan(scene, clipped.checker, [(A, 0), (B, 0)]), scene)
    assert rep.ok, rep.problems
    # the coarse rotations elsewhere are kept: the whole edge used to be converted again at
    # alpha_max/2 or less (then no rotation would be larger than alpha_max/2)
    amax = scene.alpha_max
    rots = res.sequence.rotations
    small = sum(abs(r.angle) < 0.5 * amax + 1e-9 for r in rots)
    full = sum(abs(r.angle) > 0.9 * amax for r in rots)
    assert full >= 0.5 * len(edge.sequence.rotations), (full, small, len(rots))
    assert len(rots) <= len(edge.sequence.rotations) + 30


def _past_wall(gap: float):
    """The straight push ``(2, 3) -> (6, 3)`` beside a 1 m wall whose near side is ``gap``
    beyond 0.4 m from the path."""
    wall = {"type": "box", "center": [4.0, 3.0 + 0.4 + gap + 0.1], "size": [1.0, 0.2],
            "height": 1.0}
    return make_scene(start=[2.0, 3.0, 0.0], goal=[6.0, 3.0, 0.0], obstacles=[wall])


def test_a_squeeze_past_a_wall_keeps_the_largest_rotations_that_pass():
    # the rotations beside the wall used to be bounded by the clearance alone (c / r, with
    # r the body's farthest point from the pivot): 775 rotations for this 4 m push; the
    # largest bound whose rotations pass the same checks gives about a third of that (247),
    # and rotations that merge into the one before each stretch fewer still (213)
    scene = _past_wall(0.05)
    problem = make_problem(scene)
    a, b = (2.0, 3.0, 0.0), (6.0, 3.0, 0.0)
    res = problem.checker.transfer(a, b, 0)
    assert res.valid, res.reason
    assert problem.checker.counters.refined_pieces >= 1
    assert len(res.sequence.rotations) <= 230, len(res.sequence.rotations)
    plan = path_to_plan(scene, problem.checker, [(a, 0), (b, 0)])
    rep = check_plan(plan, scene)
    assert rep.ok, rep.problems
    end = plan.phases[-1].steps[-1].object
    assert math.dist(end, b) < 1e-9


def test_a_previous_rotation_that_is_not_one_is_refused():
    steering = make_problem(make_scene()).checker.steering
    with pytest.raises(InputError, match="previous"):
        next(steering.iter_pieces((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), half_length=0.3,
                                  previous=(0.0, 0.0)))

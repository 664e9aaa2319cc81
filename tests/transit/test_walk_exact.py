"""Walks certified exactly: a walk segment passes only if free at every pose along it.

The planner samples a walk segment only until its clearances prove it free; between two
samples 4 mm of motion apart it must not accept a body dipping into the kept margin (1 cm
from the obstacles, ``box_margin`` from the resting box), which a finer sampling would find.
"""

from __future__ import annotations

import functools
import math

import pytest
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.clearance import WalkClearance
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE, CollisionWorld

#: where the robot turns in place: the middle of the 8 x 6 m test floor
CENTRE = (4.0, 3.0)
BOX_MARGIN = 0.08
POST = 0.02  # the post's radius (m)


def _clearance(obstacles: tuple = ()) -> WalkClearance:  # noqa: ANN001
    scene = make_scene(obstacles=list(obstacles))
    return WalkClearance(scene.model, CollisionWorld.from_scene(scene), resolution=0.1,
                         box_margin=BOX_MARGIN, tolerance=SWEEP_TOLERANCE, box_cache=4)


@functools.cache
def _post_at(direction: float, gap: float) -> WalkClearance:
    """A post at ``direction`` from :data:`CENTRE`, ``gap`` beyond the kept centimetre from
    the farthest the walking body reaches turning there."""
    r = _clearance().radius + KEEP_CLEARANCE + gap + POST
    post = [CENTRE[0] + r * math.cos(direction), CENTRE[1] + r * math.sin(direction)]
    return _clearance(({"type": "cylinder", "center": post, "radius": POST, "height": 1.0},))


def _least(clearance, a: Pose, b: Pose, step: float = 2 * SWEEP_TOLERANCE / 64  # noqa: ANN001
           ) -> float:
    """Least ``clearance`` along ``a -> b`` at samples ``step`` m of motion apart or closer.

    Branch and bound on the motion's Lipschitz bound: an interval is sampled further only
    where a lower value could hide between its ends.
    """
    dyaw = wrap_angle(b[2] - a[2])
    lip = math.hypot(b[0] - a[0], b[1] - a[1]) + _clearance().radius * abs(dyaw)

    def at(s: float) -> float:
        return clearance((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw))

    d0, d1 = at(0.0), at(1.0)
    best, stack = min(d0, d1), [(0.0, d0, 1.0, d1)]
    while stack:
        s0, e0, s1, e1 = stack.pop()
        span = lip * (s1 - s0)
        if span <= step or 0.5 * (e0 + e1 - span) >= best:
            continue
        m = 0.5 * (s0 + s1)
        em = at(m)
        best = min(best, em)
        stack += [(m, em, s1, e1), (s0, e0, m, em)]
    return best


def test_a_turn_whose_corner_dips_into_the_kept_centimetre_between_samples_is_refused():
    # the body's front corner passes a post 20 micrometres inside the kept centimetre, over
    # about a millimetre of its 0.43 m arc: turns starting at these yaws put the dip between
    # the samples the tolerance stops at, and some were accepted
    cl = _post_at(0.3, -2e-5)
    dipped = 0
    for k in range(24):
        a = (*CENTRE, -0.9 + 0.0083 * k)
        b = (*CENTRE, a[2] + 0.8)
        if _least(cl.static_exact, a, b) < 0.0:
            dipped += 1
            assert not cl.segment_free(a, b, None)
            assert not cl.free_between(a, b, (1.0, 1.0, 0.0), (cl.static_exact(a), 1.0),
                                       (cl.static_exact(b), 1.0))
    assert dipped == 24  # each turn really passes the post too close


def test_a_turn_whose_corner_dips_into_the_box_margin_between_samples_is_refused():
    # the same turns beside the resting box, its corner pointing at the robot 20 micrometres
    # inside the 8 cm the walks keep from it (the box's clearance is certified apart)
    cl = _clearance()
    w, d = cl.model.object_size[:2]
    half_diagonal, corner = 0.5 * math.hypot(w, d), math.atan2(d, w)
    r = cl.radius + BOX_MARGIN - 2e-5 + half_diagonal
    obj = (CENTRE[0] + r * math.cos(0.3), CENTRE[1] + r * math.sin(0.3), 0.3 + math.pi - corner)

    def to_box(p: Pose) -> float:
        return cl.world.robot_box_distance(p, obj) - BOX_MARGIN

    dipped = 0
    for k in range(24):
        a = (*CENTRE, -0.9 + 0.0083 * k)
        b = (*CENTRE, a[2] + 0.8)
        if _least(to_box, a, b) < 0.0:
            dipped += 1
            assert not cl.segment_free(a, b, obj)
            assert not cl.free_between(a, b, obj, cl.exact_parts(a, obj), cl.exact_parts(b, obj))
    assert dipped >= 12


@settings(max_examples=100, deadline=None)
@given(direction=st.floats(-math.pi, math.pi),
       gap=st.one_of(st.floats(-1e-4, 1e-4), st.floats(1e-4, 5e-3)),
       side=st.sampled_from((-1.0, 1.0)), turn=st.floats(-1.5, 1.5).filter(lambda t: abs(t) > 0.1),
       passing=st.floats(0.05, 0.95),
       move=st.tuples(st.floats(-0.003, 0.003), st.floats(-0.003, 0.003)))
def test_a_certified_walk_keeps_the_centimetre_at_every_pose(direction, gap, side, turn,
                                                              passing, move):
    # a turn (and a step of up to 3 mm) whose front corner passes a post at a fraction
    # ``passing`` of it, the post ``gap`` beyond the kept centimetre
    cl = _post_at(round(direction, 2), round(gap, 6))
    ahead, _, half_width = cl.model.walking_extent()
    yaw = round(direction, 2) - side * math.atan2(half_width, ahead) - passing * turn
    a = (*CENTRE, yaw)
    b = (CENTRE[0] + move[0], CENTRE[1] + move[1], yaw + turn)
    least = _least(cl.static_exact, a, b)
    if cl.segment_free(a, b, None):  # sound: free at every pose a finer sampling reaches
        assert least > 0.0
    if least > 1.5 * SWEEP_TOLERANCE:  # and it still accepts what keeps a clearance
        assert cl.segment_free(a, b, None)


def test_the_kept_centimetre_is_what_the_walk_keeps():
    # the clearance certified is the distance beyond the kept centimetre: the post's gap
    cl = _post_at(0.0, 0.004)
    ahead = cl.model.walking_extent()[0]
    pose = (*CENTRE, 0.0)  # the post straight ahead: the body's front face meets it
    want = cl.radius + 0.004 - ahead
    assert math.isclose(cl.static_exact(pose), want, abs_tol=1e-6)


#: boxes resting where walks pass a door or a corridor, or turn tightly beside the box
#: (the narrow fig10's tight turn): scene, box pose
NEAR_WALLS = [("door", (4.85, 2.0, 0.0)), ("t_junction", (4.85, 2.5, 0.0)),
              ("fig10_narrow", (4.881849527519183, 3.8451219714433633, -1.4253664043695728))]


@pytest.mark.parametrize(("name", "obj"), NEAR_WALLS)
def test_planned_walks_keep_their_margins_at_every_pose(name, obj):
    # every walk between two grasps of the box, its segments searched 64 times finer than
    # the planner's tolerance: clear of the obstacles by the kept centimetre, inside the
    # floor, and the box margin away from the resting box at every pose
    scene = shipped(name)
    ck = PivotChecker(scene, seed=0)
    world, model = ck.world, scene.model
    margin = ck.walker.box_margin
    grasps = [g for g in range(4) if ck.state_valid(obj, g)]
    walks = 0
    for g1 in grasps:
        for g2 in grasps:
            walk = ck.transit(obj, g1, g2) if g1 < g2 else None
            if walk is None or not walk.valid:
                continue
            walks += 1
            for a, b in zip(walk.robot_path, walk.robot_path[1:], strict=False):
                assert _least(lambda p: min(world.robot_distance(p),
                                            world.bounds_margin(model.robot_corners(p))),
                              a, b) > 0.0
                assert _least(lambda p: world.robot_box_distance(p, obj) - margin, a, b) > 0.0
    assert walks >= 1


@pytest.mark.slow
def test_a_walk_passing_with_less_than_the_tolerance_to_spare_is_a_way_not_a_refusal():
    # the layout's only walk round the resting box passes a wall 0.83 mm beyond the kept
    # centimetre (under the 2 mm tolerance): exact certificates bisect below the tolerance
    # and prove it free, so the scene keeps its plan (refused at the tolerance: no plan)
    from pathlib import Path

    from pivot_ompl import plan
    from pivot_ompl.scene import load_scene
    from pivot_ompl.validity.plan_check import check_plan

    scene = load_scene(Path(__file__).parents[1] / "data" / "scenes" / "walls_2_narrow_walk.yaml")
    res = plan(scene, time_limit=60.0, seed=0)
    assert res.solved and res.plan.regrasps == 1
    assert check_plan(res.plan, scene).ok

"""The walk smoothing: cheap refusals of shortcuts, exact costs, certified walks."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from factories import shipped, walk_problems
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import WalkParameters
from pivot_ompl.transit.lattice import chain_cost, forward_chain_cost_bound, motion_cost

#: fig10's box resting beside wall B's door: the walk between its two long sides goes round
#: the wall (10.5 m), the longest walk of the recorded regrasp runs
LONG_WALK_BOX = (8.05, 5.5, 0.0)


@functools.cache
def _walker():
    return PivotChecker(shipped("fig10_narrow"), seed=0).walker


coord = st.floats(-3.0, 3.0)
yaw = st.floats(-7.0, 7.0)
pose = st.tuples(coord, coord, yaw)


def _dubins_walk(a, b):  # noqa: ANN001, ANN202
    """The walker, and the Dubins walk ``a -> b`` as it samples it: length, pieces, poses."""
    wp = _walker()
    length = wp.smoother.dubins.distance(a, b)
    pieces = max(1, math.ceil(length / wp.resolution))
    return wp, length, pieces, wp.smoother.dubins_walk(a, b, length)


@settings(max_examples=200, deadline=None)
@given(st.lists(pose, min_size=2, max_size=12),
       st.floats(1.0, 3.0), st.floats(1.0, 3.0), st.floats(0.0, 2.0))
def test_chain_cost_is_the_sum_of_the_motion_costs(poses, side, back, turn):
    walk = WalkParameters(side_cost=side, back_cost=back, turn_cost=turn)
    want = sum(motion_cost(a, b, walk) for a, b in zip(poses, poses[1:], strict=False))
    assert chain_cost(np.array(poses), walk) == pytest.approx(want, rel=1e-12, abs=1e-12)


@settings(max_examples=300, deadline=None)
@given(pose, pose)
@example((0.0, 0.0, 0.0), (0.0, 0.0, -8.06e-7))  # OMPL gives it an arc of 2.4e-7 m, sampled as none
def test_dubins_cost_bound_never_exceeds_the_sampled_walk(a, b):
    # the bound refuses Dubins shortcuts without sampling them: it must never exceed what
    # the sampled forward walk costs, or a cheaper shortcut would be lost
    wp, length, pieces, pts = _dubins_walk(a, b)
    assert len(pts) == pieces + 1
    bound = forward_chain_cost_bound(length, pieces, b[2] - a[2], wp.walk.turning_radius,
                                     wp.walk)
    assert bound <= chain_cost(pts, wp.walk) + 1e-9


@settings(max_examples=200, deadline=None)
@given(pose, pose)
def test_dubins_probes_are_poses_of_the_sampled_walk(a, b):
    # bit for bit: a probe's clearance is reused when the walk is checked whole
    wp, _, pieces, pts = _dubins_walk(a, b)
    sampled = {tuple(p) for p in pts.tolist()}
    probes = wp.smoother.dubins_probes(a, b, pieces)
    assert len(probes) == len({k for k in (pieces // 2, pieces // 4, 3 * pieces // 4)
                               if 0 < k < pieces})
    assert all(p in sampled for p in probes)


def test_smoothing_a_long_walk_is_cheap_and_the_walk_passes_check(monkeypatch):
    # regression (issue 13): every Dubins shortcut was sampled whole (100 poses and their
    # costs) before its poses were checked, and the second pass queried again what the
    # first had learnt: 1296 clearance queries and 6087 sampled Dubins poses on this walk
    # (now 905 and 364)
    scene = shipped("fig10_narrow")
    ck = PivotChecker(scene, seed=0)
    wp, m = ck.walker, scene.model
    obj = LONG_WALK_BOX
    g1, g2 = 0, 2
    assert m.robot_pose(obj, g1)[0] < obj[0] < m.robot_pose(obj, g2)[0]
    sampled = [0]
    dubins, queries = wp.smoother.dubins, [0]
    sample, interpolate = dubins.sample, dubins.interpolate

    def count_sample(a, b, ts):
        sampled[0] += len(ts)
        return sample(a, b, ts)

    def count_interpolate(a, b, t):
        sampled[0] += 1
        return interpolate(a, b, t)

    monkeypatch.setattr(dubins, "sample", count_sample)
    monkeypatch.setattr(dubins, "interpolate", count_interpolate)
    smooth = type(wp.smoother).smooth
    lattice_cost = []
    world = wp.world

    def counted(self, poses, obj, **kw):
        lattice_cost.append(sum(motion_cost(a, b, self.walk)
                                for a, b in zip(poses, poses[1:], strict=False)))
        q0 = world.queries
        try:
            return smooth(self, poses, obj, **kw)
        finally:
            queries[0] += world.queries - q0

    monkeypatch.setattr(type(wp.smoother), "smooth", counted)
    walk = ck.transit(obj, g1, g2)
    assert walk.valid and walk.length > 9.0
    assert walk.cost <= lattice_cost[0] + 1e-9  # shortcuts only when cheaper
    assert queries[0] <= 1000
    assert sampled[0] <= 1000
    assert walk_problems(scene, obj, g1, g2, walk) == []

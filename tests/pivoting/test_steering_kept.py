"""The steering keeps its paths' lengths and span ends: the same pieces, fresh or not."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.pivoting.steering import PivotSteering

#: One steering for every example: its kept lengths and poses come from earlier examples.
SHARED = PivotSteering(turning_radius=1.2, alpha_max=math.pi / 8)

pose = st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(-math.pi, math.pi))


def _pieces(steering: PivotSteering, a, b, span, alpha):  # noqa: ANN001
    return list(steering.iter_pieces(a, b, half_length=0.3, span=span, alpha_max=alpha))


@settings(max_examples=60, deadline=None)
@given(a=pose, b=pose, t0=st.floats(0.0, 1.0), t1=st.floats(0.0, 1.0),
       factor=st.sampled_from([1.0, 0.5, 0.25]))
def test_a_kept_length_or_span_end_gives_the_pieces_a_fresh_steering_gives(a, b, t0, t1,
                                                                            factor):
    span = (min(t0, t1), max(t0, t1))
    alpha = SHARED.alpha_max * factor
    fresh = PivotSteering(turning_radius=1.2, alpha_max=math.pi / 8)
    want = _pieces(fresh, a, b, span, alpha)
    assert _pieces(SHARED, a, b, span, alpha) == want
    kept = _pieces(SHARED, a, b, span, alpha)  # now from what it kept
    assert kept == want
    if kept:  # the span's ends are the path's poses there
        paths = SHARED.paths
        assert kept[0].start == (a if span[0] == 0.0 else paths.interpolate(a, b, span[0]))
        assert kept[-1].target == (b if span[1] == 1.0 else paths.interpolate(a, b, span[1]))
    # the same path at another bound: the kept length and span ends serve it
    assert _pieces(SHARED, a, b, span, 0.5 * alpha) == _pieces(fresh, a, b, span, 0.5 * alpha)



@settings(max_examples=60, deadline=None)
@given(a=pose, b=pose, spin=st.booleans(), ts=st.lists(st.floats(0.0, 1.0), max_size=6))
def test_a_path_along_is_its_interpolation(a, b, spin, ts):
    paths = SHARED.paths
    if spin:
        b = (a[0], a[1], b[2])
    point = paths.along(a, b)
    assert [point(t) for t in ts] == [paths.interpolate(a, b, t) for t in ts]


def test_a_pose_changed_in_place_is_read_again():
    # the curves keep the last two poses they were given: only tuples, which cannot change
    rs = SHARED.paths.rs
    a, b = [0.0, 0.0, 0.0], (2.0, 1.0, 0.5)
    first = rs.distance(a, b)
    a[0] = 1.0
    assert rs.distance(a, b) == rs.distance((1.0, 0.0, 0.0), b) != first

"""The duration model fitted to a motion's seconds per plan element."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.wholebody.durations import DurationBreakdown, fit_duration_model


@settings(deadline=None)  # no timing in unit tests (a loaded machine tripped the 200 ms)
@given(a=st.floats(0.5, 5.0), b=st.floats(0.0, 20.0), c=st.floats(0.0, 30.0),
       w=st.floats(0.5, 30.0))
def test_fit_recovers_exact_linear_costs(a, b, c, w):
    angles = [0.1, 0.2, 0.39, 0.3, 0.05]
    lengths = [0.5, 1.3, 10.4]
    bd = DurationBreakdown(total=0.0, pivots=[(x, a + b * x) for x in angles],
                           transfer_rest=[4.0, 6.0], transits=[(x, c + w * x) for x in lengths])
    d = fit_duration_model(bd)
    assert d.per_pivot == pytest.approx(a, abs=1e-6)
    assert d.per_radian == pytest.approx(b, abs=1e-6)
    assert d.per_transit == pytest.approx(c, abs=1e-6)
    assert d.per_walk_m == pytest.approx(w, abs=1e-6)
    assert d.per_transfer == pytest.approx(5.0)


def test_fit_keeps_coefficients_non_negative():
    bd = DurationBreakdown(total=0.0, pivots=[(0.1, 3.0), (0.4, 2.0), (0.2, 2.8)],
                           transits=[(1.0, 20.0), (10.0, 15.0)])
    d = fit_duration_model(bd)
    assert min(d.per_pivot, d.per_radian, d.per_transit, d.per_walk_m) >= 0.0

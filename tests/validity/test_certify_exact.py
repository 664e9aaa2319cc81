"""``certify(exact=True)``: a motion certified is free at every parameter, not only sampled."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.validity.certify import EXACT_MARGIN, EXACT_REFINE, certify


def _dip(at: float, depth: float, slope: float = 1.0):  # noqa: ANN202
    """A clearance along a motion of Lipschitz bound ``slope``: one V-shaped dip at ``at``."""
    return lambda s: slope * abs(s - at) - depth


def test_a_dip_between_samples_passes_the_tolerance_but_not_the_exact_check():
    # the dip (20 micrometres deep) lies between the samples 1/16 apart that end the
    # bisection at the tolerance: the default accepts it, the exact check does not
    clear = _dip(0.5 + 1 / 32, 2e-5, slope=0.09)
    assert clear(0.5 + 1 / 32) < 0
    assert certify(clear, 0.09, tolerance=0.003).valid
    res = certify(clear, 0.09, tolerance=0.003, exact=True)
    assert not res.valid and 0.5 <= res.first_collision <= 0.5 + 1 / 16


@settings(max_examples=300, deadline=None)
@given(at=st.floats(0.0, 1.0), depth=st.floats(-0.01, 0.01), slope=st.floats(0.001, 2.0),
       tol=st.floats(1e-4, 0.01))
def test_the_exact_check_passes_only_free_motions_and_every_clear_one(at, depth, slope, tol):
    clear = _dip(at, depth, slope)
    res = certify(clear, slope, tolerance=tol, exact=True)
    if res.valid:  # free everywhere: the dip's bottom too
        assert clear(at) > 0
    if -depth > tol / EXACT_REFINE + 2 * EXACT_MARGIN:  # clear by a fraction of the tolerance
        assert res.valid
    assert certify(clear, slope, tolerance=tol).valid or not res.valid  # never looser


def test_a_motion_clear_by_less_than_the_tolerance_is_certified_not_refused():
    # a body sliding along a wall half a millimetre from it, the tolerance 2 mm: the exact
    # check bisects below the tolerance until the clearances prove it free (a gap a walk
    # passes with half a millimetre to spare is a way, not a refusal)
    def clear(s: float) -> float:
        return 5e-4 + 1e-3 * abs(s - 0.37)

    res = certify(clear, 0.8, tolerance=0.002, exact=True)
    assert res.valid

"""benchmarks/walk_clearance.py: the least clearance of a motion, searched by branch and bound."""

from __future__ import annotations

from factories import benchmark_script
from hypothesis import given, settings
from hypothesis import strategies as st


@settings(max_examples=200, deadline=None)
@given(at=st.floats(0.0, 1.0), depth=st.floats(-0.01, 0.01), slope=st.floats(0.01, 2.0))
def test_the_search_finds_a_v_shaped_dip_within_its_step(at, depth, slope):
    # a clearance of Lipschitz bound ``slope`` with one dip at ``at``: the search's least is
    # no higher than the dip's bottom plus half a step of motion, and never below it
    least = benchmark_script("walk_clearance").least
    step = 1e-4
    found = least(lambda s: slope * abs(s - at) - depth, slope, step)
    assert -depth - 1e-12 <= found <= -depth + 0.5 * step + 1e-12

"""Perturbation texts: what they parse to, random slips drawn from the seed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.errors import InputError
from pivot_ompl.physics import FrictionPatch, Slip, parse_perturbations


@given(n=st.integers(0, 40), pivots=st.integers(0, 60), seed=st.integers(0, 2**31 - 1))
def test_random_slips(n, pivots, seed):
    p = parse_perturbations([f"slip:{n}"], pivots=pivots, rng=np.random.default_rng(seed))
    assert len(p.slips) == min(n, pivots)
    at = [s.pivot for s in p.slips]
    assert at == sorted(set(at)) and all(0 <= k < pivots for k in at)
    for s in p.slips:
        assert 0.02 - 1e-12 <= math.hypot(s.dx, s.dy) <= 0.05 + 1e-12
        assert abs(s.dyaw) <= math.radians(2.0)
    again = parse_perturbations([f"slip:{n}"], pivots=pivots, rng=np.random.default_rng(seed))
    assert again == p


def test_explicit_forms():
    p = parse_perturbations(["slip@4:0.03,-0.01,0.02", "patch:1,2,0.5,0.2", "mass:0.05,0,0"],
                            pivots=10, rng=np.random.default_rng(0))
    assert p.slips == (Slip(4, 0.03, -0.01, 0.02),)
    assert p.patches == (FrictionPatch(1.0, 2.0, 0.5, 0.2),)
    assert p.com_offset == (0.05, 0.0, 0.0)
    assert p.friction_at(1.2, 2.2, 0.5) == 0.2 and p.friction_at(3.0, 3.0, 0.5) == 0.5
    assert p.slip_at(4) is not None and p.slip_at(3) is None


@pytest.mark.parametrize("spec", ["slip:x", "slip:-1", "slip@-1:0,0", "slip@2:1,1",
                                  "slip@2:0,0,1", "patch:0,0,1", "patch:0,0,1,0",
                                  "mass:0,0", "mass:nan,0,0", "nudge"])
def test_bad_specs_are_named(spec):
    with pytest.raises(InputError) as e:
        parse_perturbations([spec], pivots=10, rng=np.random.default_rng(0))
    assert e.value.field == "--perturb" and e.value.value == spec

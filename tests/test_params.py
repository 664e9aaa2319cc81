"""Parameters declared with their ranges: the range text, its checks, the field's metadata."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.errors import InputError
from pivot_ompl.params import Range, check_value, knob, range_of


@dataclass(frozen=True)
class _Demo:
    count: int = knob(8, low=1, high=1000)
    share: float = knob(0.5, high=1.0)
    gap: float = knob(0.2, low_open=True)
    steps: tuple[float, ...] = knob((0.5, 1.0))
    plain: float = 2.0


def test_a_knob_keeps_its_default_and_puts_its_range_in_the_metadata():
    d = _Demo()
    assert (d.count, d.share, d.gap, d.steps) == (8, 0.5, 0.2, (0.5, 1.0))
    got = {f.name: range_of(f.metadata) for f in fields(_Demo)}
    assert str(got["count"]) == "[1, 1000] integer"
    assert str(got["share"]) == "[0, 1]"
    assert str(got["gap"]) == "(0, inf)"
    assert got["steps"] == Range() and got["plain"] == Range()


@given(x=st.floats(allow_nan=True, allow_infinity=True))
def test_a_value_passes_exactly_when_it_lies_in_the_range(x):
    rng = Range(low=0.2, high=3.0, low_open=True)
    inside = math.isfinite(x) and 0.2 < x <= 3.0
    assert (rng.problem(x) is None) == inside
    if inside:
        check_value("demo.x", x, rng)
    else:
        with pytest.raises(InputError) as e:
            check_value("demo.x", x, rng)
        assert e.value.field == "demo.x"


def test_the_floor_is_checked_first_and_flags_never():
    rng = Range(low=1.0)
    with pytest.raises(InputError, match="must be finite and >= 0"):
        check_value("a", -2.0, rng)
    with pytest.raises(InputError, match="must be >= 1"):
        check_value("a", 0.5, rng)
    check_value("a", 0.5, rng, floor_only=True)
    check_value("flag", True, rng)
    with pytest.raises(InputError, match="must be finite"):
        check_value("t", (1.0, math.nan), rng)


def test_a_range_below_zero_is_refused_when_declared():
    with pytest.raises(ValueError):
        Range(low=-1.0)

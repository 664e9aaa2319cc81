"""The steering stops when its termination condition says so; the checker does not cache it."""

from __future__ import annotations

import math

import pytest
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.pivoting.steering import PivotSteering


def test_steering_polls_its_stop_condition():
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    calls = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) > 3

    with pytest.raises(Interrupted):
        steering.convert((0.0, 0.0, 0.0), (50.0, 0.0, 0.0), half_length=0.3, should_stop=stop)
    assert len(calls) == 4


def test_an_interrupted_edge_is_neither_valid_nor_invalid_and_not_cached():
    ck = PivotChecker(make_scene(), seed=0)
    a, b = (1.5, 3.0, 0.0), (6.0, 3.0, 0.0)
    with pytest.raises(Interrupted):
        ck.transfer(a, b, 0, should_stop=lambda: True)
    assert ck.counters.valid + ck.counters.invalid == 0
    assert ck.transfer(a, b, 0).valid

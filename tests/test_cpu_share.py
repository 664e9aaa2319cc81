"""The load-scaled limit of tests whose premise is a core's worth of CPU."""

from __future__ import annotations

import pytest
from cpu_share import MOST, RUNS, WHOLE, with_cpu_limit
from hypothesis import given
from hypothesis import strategies as st


class _Machine:
    """Clocks of a run that takes ``need`` CPU seconds with ``share`` of a core."""

    def __init__(self, need: float, shares: list[float]):
        self.need, self.shares, self.wall, self.cpu, self.limits = need, shares, 0.0, 0.0, []

    def run(self, limit: float) -> str:
        share = self.shares[min(len(self.limits), len(self.shares) - 1)]
        self.limits.append(limit)
        took = min(limit, self.need / share)
        self.wall += took
        self.cpu += took * share
        return "INFEASIBLE" if took < limit else "TIMEOUT"


def _done(out: str, took: float, limit: float) -> bool:
    return out == "INFEASIBLE" and took <= 0.1 * limit


def _go(m: _Machine, limit: float = 30.0):
    return with_cpu_limit(m.run, limit, _done, wall=lambda: m.wall, cpu=lambda: m.cpu)


def test_a_run_with_its_core_is_the_one_asserted_even_failing():
    m = _Machine(need=5.0, shares=[1.0])  # too slow on a whole core: a real failure
    out, took, limit = _go(m)
    assert m.limits == [30.0] and limit == 30.0 and out == "INFEASIBLE" and took == 5.0


@given(share=st.floats(0.12, WHOLE - 1e-3))
def test_a_run_short_of_cpu_is_run_again_with_the_limit_its_share_scales(share):
    m = _Machine(need=2.9, shares=[share, share])  # 2.9 s of CPU: within a tenth of 30 s
    out, took, limit = _go(m)
    assert m.limits[0] == 30.0 and len(m.limits) == 2
    assert limit == m.limits[1] == pytest.approx(30.0 / share)  # a core's worth of CPU
    assert out == "INFEASIBLE" and took <= 0.1 * limit


def test_never_more_than_its_runs_nor_beyond_the_most_limit():
    m = _Machine(need=1000.0, shares=[0.05])
    out, _, limit = _go(m)
    assert out == "TIMEOUT" and len(m.limits) == RUNS and max(m.limits) <= MOST * 30.0
    assert limit == m.limits[-1]


def test_a_run_that_is_done_is_not_run_again():
    m = _Machine(need=0.6, shares=[0.3])
    out, took, limit = _go(m)
    assert m.limits == [30.0] and out == "INFEASIBLE" and took < 3.0

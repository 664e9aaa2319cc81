"""The raster's turning place checks no regrasp beyond a reached goal: where the raster joins
start and goal nothing is proven, so it walks no more than the raster bound does."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.analysis import regrasp_walk
from pivot_ompl.analysis.raster_bound import raster_lower_bound
from pivot_ompl.analysis.turning_raster import raster_turning_place


@pytest.mark.parametrize("name", ["fig10", "door", "slot"])
def test_a_joined_raster_checks_no_more_walks_than_the_raster_bound(monkeypatch, name):
    calls = [0]
    real = regrasp_walk.WalkRelaxation.may_regrasp

    def counted(self, *args, **kwargs):
        calls[0] += 1
        return real(self, *args, **kwargs)

    monkeypatch.setattr(regrasp_walk.WalkRelaxation, "may_regrasp", counted)
    scene = shipped(name)
    assert raster_turning_place(scene) is None  # these scenes have plans
    turning = calls[0]
    calls[0] = 0
    assert raster_lower_bound(scene).solvable
    assert turning <= calls[0]

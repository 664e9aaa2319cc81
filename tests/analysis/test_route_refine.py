"""The layered route bound on finer cells: asked where a plan's route ratio is high."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.analysis import bound_cache
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.route_refine import REFINE_RATIO


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty memory cache and disk cache folder."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    bound_cache.clear_memory()
    return tmp_path


def test_finer_cells_only_past_the_ratio_and_longer_there(fresh):
    # the walls layout whose one regrasp must happen beside its narrow gap: 8 cm cells cut
    # the corner the regrasp's place forces, 5 cm cells less
    scene = shipped("walls_2_narrow_walk")
    regrasps, coarse = plan_bounds(scene, 1)  # no route given: no ratio, no finer cells
    assert regrasps == 1 and coarse is not None
    _, below = plan_bounds(scene, 1, route_length=0.99 * REFINE_RATIO * coarse)
    assert below == coarse  # a ratio under the threshold: the route as it was
    long_plan = 2.0 * coarse
    _, finer = plan_bounds(scene, 1, route_length=long_plan)
    assert finer is not None and coarse < finer <= long_plan

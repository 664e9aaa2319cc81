"""The coarsest raster the late proof builds (while the search has no path) is the one the
plan's bound reads: the same bound as built afresh, taken once, and let go by plan_bounds."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.analysis import bound_levels
from pivot_ompl.analysis.bound_levels import COARSE, scaled_lower_bound
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.turning_raster import raster_turning_place
from pivot_ompl.scene.shared import shared_value


@pytest.mark.parametrize("name", ["fig10", "door"])
def test_the_late_proofs_raster_gives_the_bound_a_fresh_one_gives(monkeypatch, name):
    scene = shipped(name)
    fresh = scaled_lower_bound(scene, target=5, refine_seconds=0.0)
    assert raster_turning_place(scene) is None  # joined: nothing proven, the raster kept
    assert shared_value(scene, COARSE) is not None
    built: list[int] = []
    real = bound_levels.raster_cover
    monkeypatch.setattr(bound_levels, "raster_cover",
                        lambda *a, **k: built.append(1) or real(*a, **k))
    kept = scaled_lower_bound(scene, target=5, refine_seconds=0.0)
    assert not built  # read, not built again
    assert (kept.solvable, kept.regrasps, kept.shortest_route) == (
        fresh.solvable, fresh.regrasps, fresh.shortest_route)
    assert shared_value(scene, COARSE) is None  # taken once


def test_plan_bounds_lets_the_kept_raster_go(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    scene = shipped("corridor")
    assert raster_turning_place(scene) is None
    assert shared_value(scene, COARSE) is not None
    plan_bounds(scene, 0)  # no regrasp: no raster bound asked
    assert shared_value(scene, COARSE) is None

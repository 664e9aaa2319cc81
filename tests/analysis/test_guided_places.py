"""The guided refinement started round a plan's regrasp places: wherever the places are, the
bound stays a lower bound (between the coarse raster's and the exact polygons'), the places'
window is the cells within the radius, and ``plan`` hands the refinement its regrasp places."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import shipped

from pivot_ompl import api, plan
from pivot_ompl.analysis import bound_levels
from pivot_ompl.analysis.guided_refine import (
    PLACE_RADIUS,
    GuidedRound,
    guided_lower_bound,
    place_window,
)
from pivot_ompl.analysis.raster_bound import CELL, raster_lower_bound
from pivot_ompl.analysis.raster_cover import raster_cover
from pivot_ompl.planners.explain import regrasp_places

#: The exact polygon bounds of the shipped scenes (``pivot-ompl bound NAME --exhaustive``).
EXACT = {"slot": 1, "fig10": 2, "door": 1}


@pytest.mark.parametrize(("name", "seed"), [("slot", 0), ("door", 1), ("fig10", 2)])
def test_places_anywhere_keep_the_bound_between_the_coarse_and_the_exact_ones(name, seed):
    scene = shipped(name)
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = scene.bounds
    places = tuple((float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)))
                   for _ in range(int(rng.integers(1, 4))))
    coarse = raster_lower_bound(scene)
    trace: list[GuidedRound] = []
    guided = guided_lower_bound(scene, places=places, trace=trace)
    assert guided is not None and guided.solvable
    assert coarse.regrasps <= guided.regrasps <= EXACT[name]
    windows = [r.window for r in trace]
    assert windows == sorted(windows)  # each round only refines


def test_the_places_window_is_the_cells_within_the_radius():
    scene = shipped("fig10")
    cover = raster_cover(scene, cell=CELL)
    assert cover is not None
    r = cover.raster
    x0, y0, x1, y1 = scene.bounds
    places = ((x0, y0), (0.5 * (x0 + x1), 0.5 * (y0 + y1)), (x1 + 0.3, y1))
    got = place_window(cover, places)
    want = np.zeros(r.shape, dtype=bool)
    for x, y in places:
        want |= np.hypot(r.gx - x, r.gy - y) <= PLACE_RADIUS
    assert want.any() and np.array_equal(got, want)
    assert not place_window(cover, ()).any()


def test_a_plan_hands_the_refinement_its_regrasp_places(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    asked: list[tuple[tuple[float, float], ...]] = []
    real_bounds = api.plan_bounds

    def bounds_spy(*args, **kwargs):
        asked.append(kwargs.get("places", ()))
        return real_bounds(*args, **kwargs)

    monkeypatch.setattr(api, "plan_bounds", bounds_spy)
    result = plan(shipped("fig10"), time_limit=30.0, seed=0)
    assert result.plan is not None and result.plan.regrasps > 0
    places = regrasp_places(result.plan)
    assert len(places) == result.plan.regrasps and asked == [places]


def test_the_levels_hand_the_places_to_the_refinement(monkeypatch):
    seen: list[tuple[tuple[float, float], ...]] = []
    real = bound_levels.guided_lower_bound

    def spy(*args, **kwargs):
        seen.append(kwargs.get("places", ()))
        return real(*args, **kwargs)

    monkeypatch.setattr(bound_levels, "guided_lower_bound", spy)
    # the refinement's path (a floor this small would get the held poses' count instead)
    monkeypatch.setattr(bound_levels, "may_pose", lambda *a, **k: False)
    monkeypatch.setattr(bound_levels, "LEVEL_SECONDS", 0.0)  # nor the finer rasters
    places = ((1.0, 2.0), (3.0, -1.0))
    found = bound_levels.scaled_lower_bound(shipped("slot"), target=1, refine_seconds=0.0,
                                            guided_seconds=math.inf, places=places)
    assert seen == [places] and found.regrasps == 1


def test_places_told_between_rounds_join_the_next_window_and_a_told_count_ends_them():
    scene = shipped("fig10")
    cover = raster_cover(scene, cell=CELL)
    x0, y0, x1, y1 = scene.bounds
    places = ((0.5 * (x0 + x1), 0.5 * (y0 + y1)),)
    asked: list[int] = []

    def hint() -> tuple[int | None, tuple[tuple[float, float], ...]]:
        asked.append(1)
        return None, places  # told from the first round on: refined in the second

    trace: list[GuidedRound] = []
    told = guided_lower_bound(scene, cover=cover, trace=trace, hint=hint)
    assert told is not None and asked and len(trace) >= 2
    assert trace[1].window >= int(place_window(cover, places).sum())
    assert raster_lower_bound(scene).regrasps <= told.regrasps <= EXACT["fig10"]
    trace.clear()  # a count told is aimed at: reached by the coarse graph, no refined round
    guided_lower_bound(scene, cover=cover, trace=trace, hint=lambda: (0, ()))
    assert len(trace) == 1

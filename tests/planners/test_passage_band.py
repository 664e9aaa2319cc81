"""Passages seeded along the box's coarse routes: the band, the passages kept, the focus."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.config import SamplingConfig
from pivot_ompl.planners.objects.floor_band import BandRegion, FloorBand
from pivot_ompl.planners.objects.passage_band import PassageBand, choose_passages, thinned
from pivot_ompl.planners.objects.samplers import PoseSampler
from pivot_ompl.planners.objects.slots import Passage, doors, find_passages, slots


def _box(x0: float, y0: float, x1: float, y1: float) -> dict:
    return {"type": "box", "center": [0.5 * (x0 + x1), 0.5 * (y0 + y1)],
            "size": [x1 - x0, y1 - y0], "yaw": 0.0, "height": 2.0}


def _wall_with_two_doors(specks: bool = False):
    """A 20 x 10 m floor cut by a wall at x = 10 with 1.2 m doors at y = 2 and y = 9.

    ``specks``: two 0.2 m specks 1.2 m apart in the open west room, at y = 6.
    """
    obstacles = [_box(9.85, 0.0, 10.15, 1.4), _box(9.85, 2.6, 10.15, 8.4),
                 _box(9.85, 9.6, 10.15, 10.0)]
    if specks:
        obstacles += [_box(4.0, 5.9, 4.2, 6.1), _box(5.4, 5.9, 5.6, 6.1)]
    return make_scene(bounds=[0.0, 0.0, 20.0, 10.0], start=[5.0, 2.0, 0.0],
                      goal=[15.0, 2.0, 0.0], obstacles=obstacles)


def _band(scene, **kw) -> tuple[PivotChecker, FloorBand]:
    ck = PivotChecker(scene, seed=0)
    args = {"cell": 0.1, "max_cells": 1_000_000, "penalty": 20.0, "margin": 1.0} | kw
    return ck, FloorBand(ck, scene.start, scene.goal, should_stop=lambda: False, **args)


def _door_at(found: list[Passage], y: float) -> list[Passage]:
    return [p for p in found if abs(p.center[0] - 10.0) < 0.2 and abs(p.center[1] - y) < 0.2]


def test_the_band_holds_the_near_door_and_not_the_far_one():
    scene = _wall_with_two_doors()
    ck, band = _band(scene)
    assert band.joined()
    assert band.best == pytest.approx(10.0, abs=0.5)  # straight through the near door
    region = band.region(0.1)
    assert region.holds(5.0, 2.0) and region.holds(15.0, 2.0) and region.holds(10.0, 2.0)
    assert not region.holds(10.0, 9.0)
    every = doors(ck, play=0.5)
    assert _door_at(every, 2.0) and _door_at(every, 9.0)
    near = doors(ck, play=0.5, within=region)
    assert _door_at(near, 2.0) and not _door_at(near, 9.0)
    # the widest slack reaches the far door's route too
    assert band.region(2.0).holds(10.0, 9.0)
    assert band.region(math.inf).cells == band.region(math.inf).mask.size


def test_a_floor_whose_ends_are_not_joined_gives_the_whole_floor():
    walled = make_scene(bounds=[0.0, 0.0, 20.0, 10.0], start=[5.0, 2.0, 0.0],
                        goal=[15.0, 2.0, 0.0], obstacles=[_box(9.85, 0.0, 10.15, 10.0)])
    _, band = _band(walled)
    assert not band.joined()
    assert band.region(0.1).cells == band.region(0.1).mask.size


def test_a_gap_between_specks_is_bypassed_and_a_door_is_not():
    scene = _wall_with_two_doors(specks=True)
    ck, band = _band(scene)
    found = doors(ck, play=0.5)
    specks = [p for p in found if abs(p.center[1] - 6.0) < 0.2 and abs(p.center[0] - 4.8) < 0.2]
    assert specks, found
    assert all(band.bypassed(p, reach=2.5) for p in specks)
    assert not any(band.bypassed(p, reach=2.5) for p in _door_at(found, 2.0))
    chosen = choose_passages(found, band, reach=2.5, spacing=0.5, cap=10)
    assert _door_at(chosen, 2.0) and not [p for p in chosen if p in specks]


def test_a_cap_keeps_the_passages_on_the_cheapest_route():
    scene = _wall_with_two_doors()
    ck, band = _band(scene)
    chosen = choose_passages(doors(ck, play=0.5), band, reach=2.5, spacing=0.5, cap=1)
    assert len(chosen) == 1 and _door_at(chosen, 2.0)


def test_thinning_keeps_the_narrowest_of_near_equal_passages():
    a = Passage((0.0, 0.0), 0.0, 1.0, 0.3)
    b = Passage((0.2, 0.0), 0.1, 0.9, 0.3)   # near, same axis, narrower: kept instead of a
    c = Passage((0.1, 0.1), 1.5, 1.2, 0.3)   # near but square to them: kept
    d = Passage((2.0, 0.0), 0.0, 1.1, 0.3)   # far: kept
    assert thinned([a, b, c, d], 0.5) == [b, d, c]


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_passages_within_an_area_are_those_whose_centre_it_holds(seed):
    rng = np.random.default_rng(seed)
    specks = [_box(x, y, x + 0.3, y + 0.3) for x, y in rng.uniform(0.5, 7.5, size=(25, 2))]
    scene = make_scene(bounds=[0.0, 0.0, 8.0, 8.0], start=[0.4, 0.4, 0.0],
                       goal=[7.6, 7.6, 0.0], obstacles=specks)
    mask = rng.uniform(size=(16, 16)) < 0.3
    region = BandRegion(mask, (0.0, 0.0), 0.5)
    every = find_passages(scene, min_width=0.4, max_width=2.0)
    within = find_passages(scene, min_width=0.4, max_width=2.0, within=region)
    assert within == [p for p in every if region.holds(*p.center)]


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_a_focused_sampler_draws_in_its_area_only(seed):
    rng = np.random.default_rng(seed)
    mask = rng.uniform(size=(20, 10)) < 0.2
    mask[3, 4] = True
    region = BandRegion(mask, (0.0, 0.0), 0.4)
    ck = PivotChecker(make_scene(), seed=0)
    sampler = PoseSampler(ck, np.random.default_rng(seed), yaw_range=math.pi, max_rejects=10)
    sampler.focus(region)
    assert sampler.focus_area == pytest.approx(region.cells * 0.16)
    for _ in range(50):
        x, y, yaw = sampler.reachable()
        assert region.holds(x, y) and -math.pi <= yaw < math.pi


def test_a_small_floor_seeds_every_passage_as_before():
    scene = _wall_with_two_doors()
    ck = PivotChecker(scene, seed=0)
    band = PassageBand(ck, scene.start, scene.goal, SamplingConfig())
    assert band.doors(lambda: False) == sorted(doors(ck, play=0.5), key=lambda p: p.width)
    assert band.slots(lambda: False) == sorted(slots(ck, play=0.1), key=lambda p: p.width)
    assert band.band is None and band.area() is None and not band.can_widen()


def test_a_banded_floor_widens_level_by_level_to_the_whole_floor():
    scene = _wall_with_two_doors()
    ck = PivotChecker(scene, seed=0)
    cfg = SamplingConfig(band_area=0.0, band_boxes=0, band_slacks=(0.1, 2.0))
    band = PassageBand(ck, scene.start, scene.goal, cfg)
    first = band.doors(lambda: False)
    assert _door_at(first, 2.0) and not _door_at(first, 9.0)
    assert band.area() is not None and band.can_widen()
    band.widen()
    assert _door_at(band.doors(lambda: False), 9.0)
    band.widen()
    assert band.area() is None and not band.can_widen()  # the whole floor


def test_a_small_floor_crowded_with_passages_gets_the_band():
    # more doors than a level seeds (band_passages) on a floor too small for the band: the
    # band is made after all, and the passages chosen from it (the near door, not the far)
    scene = _wall_with_two_doors()
    ck = PivotChecker(scene, seed=0)
    every = doors(ck, play=0.5)
    cfg = SamplingConfig(band_passages=len(every) - 1, band_slacks=(0.1, 2.0))
    band = PassageBand(ck, scene.start, scene.goal, cfg)
    assert not band.applies()
    chosen = band.doors(lambda: False)
    assert band.band is not None and band.can_widen()
    assert len(chosen) <= cfg.band_passages
    assert _door_at(chosen, 2.0) and not _door_at(chosen, 9.0)
    roomy = PassageBand(ck, scene.start, scene.goal,
                        SamplingConfig(band_passages=len(every), band_slacks=(0.1, 2.0)))
    assert roomy.doors(lambda: False) == sorted(every, key=lambda p: p.width)  # as before
    assert roomy.band is None

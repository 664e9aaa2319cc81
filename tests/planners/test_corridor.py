"""The band round the floor's way that one-grasp plans route in, and the tries' fallback."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from pivot_ompl import scene_from_map
from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig, SingleGraspConfig
from pivot_ompl.planners.corridor import (
    FIRST_AREA,
    MOST,
    band_first,
    corridor_lattice,
    corridor_region,
)
from pivot_ompl.planners.direct import DirectStats, direct_path
from pivot_ompl.planners.follow_route import free_route
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.validity.plan_check import check_plan

HOUSE = Path(__file__).resolve().parents[2] / "scenes" / "maps" / "aws_small_house" / "map.yaml"
SPACING = OptimiserConfig().run_spacing


@pytest.fixture(scope="module")
def house():
    """The AWS small house, across it with a quarter turn (the buildings benchmark's task)."""
    return scene_from_map(HOUSE, start=(-6.0, -3.0, 0.0), goal=(7.0, -1.0, 0.5 * math.pi))


def _grasps(checker, scene):
    return [g for g in range(4) if checker.state_valid(scene.start, g)
            and checker.state_valid(scene.goal, g)]


@pytest.mark.parametrize("width", [0.5, 1.5])
def test_the_band_holds_the_ends_and_the_way_and_nothing_farther(house, width):
    checker = PivotChecker(house)
    band = corridor_region(checker, house.start, house.goal, width=width, region=None,
                           should_stop=lambda: False)
    assert band is not None
    way = free_route(checker, house.start[:2], house.goal[:2], should_stop=lambda: False)
    assert way is not None and way[0] == house.start[:2] and way[-1] == house.goal[:2]
    line = shapely.LineString(way)
    for p in way:  # the whole way, its ends among them, lies in the band
        assert band.covers(shapely.Point(p))
    # every point of the band is within the width of the way (the buffer's chords: inside)
    pts = shapely.get_coordinates(band.boundary)
    assert float(shapely.distance(line, shapely.points(pts)).max()) <= width + 1e-6
    floor = shapely.box(*checker.world.bounds)
    assert band.area <= MOST * floor.area and floor.covers(band)


def test_no_band_at_width_zero_or_where_it_would_cover_most_of_the_floor(house):
    checker = PivotChecker(house)
    for width in (0.0, 100.0):
        assert corridor_region(checker, house.start, house.goal, width=width, region=None,
                               should_stop=lambda: False) is None


def test_the_band_lattice_pays_for_fewer_pieces_and_gives_a_valid_one_grasp_path(house):
    checker = PivotChecker(house)
    band = corridor_lattice(checker, CostModel(), house.start, house.goal, width=1.5,
                            region=None, weight=1.2, should_stop=lambda: False)
    whole = TransferLattice(checker, CostModel(), weight=1.2)
    assert band is not None and len(band.field.pieces) < len(whole.field.pieces)
    stats = DirectStats()
    states = direct_path(checker, house.start, house.goal, grasps=_grasps(checker, house),
                         config=SingleGraspConfig(checks=0), costs=CostModel(),
                         rng=np.random.default_rng(0), lattice=lambda: whole,
                         run_spacing=SPACING, should_stop=lambda: False, stats=stats,
                         band=lambda: band)
    assert stats.solved_by == "lattice" and len({g for _, g in states}) == 1
    assert states[0][0] == house.start and states[-1][0] == house.goal
    assert whole.expansions == 0  # found in the band: the whole floor's lattice never searched
    p = path_to_plan(house, checker, states)
    assert p.regrasps == 0 and check_plan(p, house).ok


def test_a_band_that_misses_the_way_leaves_the_path_to_the_whole_lattice(house):
    """Regression: the band's try failing must not end the tries (the whole lattice's next)."""
    checker = PivotChecker(house)
    start = house.start
    nowhere = shapely.Point(start[0], start[1]).buffer(0.6)  # the start's room corner alone
    band = TransferLattice(checker, CostModel(), region=nowhere, weight=1.2)
    whole = TransferLattice(checker, CostModel(), weight=1.2)
    stats = DirectStats()
    states = direct_path(checker, start, house.goal, grasps=_grasps(checker, house),
                         config=SingleGraspConfig(checks=0), costs=CostModel(),
                         rng=np.random.default_rng(0), lattice=lambda: whole,
                         run_spacing=SPACING, should_stop=lambda: False, stats=stats,
                         band=lambda: band)
    assert stats.solved_by == "lattice"
    assert states and states[0][0] == start and states[-1][0] == house.goal
    far = nowhere.buffer(2.0)  # beyond the band lattice's reach: the whole lattice's route
    assert any(not far.contains(shapely.Point(q[0], q[1])) for q, _ in states)
    p = path_to_plan(house, checker, states)
    assert p.regrasps == 0 and check_plan(p, house).ok


def test_a_long_band_is_tried_after_the_rrt_connect_and_a_short_one_before(house):
    """Regression: a 200 x 200 m hall's band (about 550 m^2) tried first cost 2 s more than
    the RRT-Connect's try, which finds an open floor's path at once: `--time 1` found none."""
    checker = PivotChecker(house)
    lattice = corridor_lattice(checker, CostModel(), house.start, house.goal, width=1.0,
                               region=None, weight=1.0, should_stop=lambda: False)
    assert lattice is not None and lattice.region is not None
    assert lattice.region.area <= FIRST_AREA and band_first(lattice)  # the house: ~40 m^2
    long = TransferLattice(checker, CostModel(),
                           region=shapely.LineString([(0, 0), (275, 0)]).buffer(1.0))
    assert long.region.area > FIRST_AREA and not band_first(long)
    assert not band_first(TransferLattice(checker, CostModel()))  # no band: the whole floor

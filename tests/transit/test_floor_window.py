"""Floor distances in a window round the goals, over the tiles the Dijkstra reaches.

On floors too large for the lattice cost-to-go, a walk's floor distances within a limit are
computed over tiles of the grid loaded as the Dijkstra reaches them
(:mod:`pivot_ompl.transit.floor_window`), never over the whole floor. They must be the whole
floor's: exact within the limit, a lower bound beyond it, ``inf`` only where no walk exists;
and a walk planned with them is the walk planned over the whole floor.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.wall_frame import walls_facing
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.transit.floor_window import TILE, FloorTiles, FloorWindow
from pivot_ompl.transit.planner import WalkPlanner


@pytest.fixture(scope="module")
def corridor():
    """A turned row of four rooms joined by a corridor, and its walk planner."""
    scene = generate("building", 0, params=GeneratorParams(rooms=4, layout="corridor")).scene
    return scene, PivotChecker(scene)


def _uncut(scene):
    """A walk planner of ``scene`` whose grid covers its bounds turned to the walls (not cut
    to the free floor as the checker's is): tiles round the turned building no walk reaches."""
    return WalkPlanner(scene.model, PivotChecker(scene).world, scene.walk,
                       yaw=walls_facing(scene))


def _cell(walker, pose):
    b, res = walker.world.bounds, walker.resolution
    p = walker.frame.into(pose)
    return round((p[0] - b[0]) / res), round((p[1] - b[1]) / res)


def _whole(field, obj, goals, limit):
    saved = field.window_from
    field.window_from = 2**62  # the whole floor's graph
    try:
        return field.distances(obj, goals, limit=limit)
    finally:
        field.window_from = saved


def _windowed(field, obj, goals, limit):
    saved = field.window_from
    field.window_from = 0
    try:
        out = field.distances(obj, goals, limit=limit)
    finally:
        field.window_from = saved
    assert isinstance(out, FloorWindow) and field.stats.windowed
    return out.dense(field.grid.nx, field.grid.ny)


@pytest.mark.parametrize("tile", [TILE, 8])  # 8: the Dijkstra loads tiles in many rounds
@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(t=st.floats(0.0, 1.0), grasp=st.sampled_from([0, 1, 2, 3]),
       limit=st.floats(0.3, 8.0))  # windows smaller than the floor
def test_windowed_distances_are_the_whole_floors(corridor, tile, t, grasp, limit):
    scene, ck = corridor
    if ck.walker.field.tiles.tile != tile:
        ck.walker.field.tiles = FloorTiles(ck.walker.field.grid, tile)
    wp = ck.walker
    field = wp.field
    (x0, y0, _), (x1, y1, _) = scene.start, scene.goal
    obj = (x0 + t * (x1 - x0), y0 + t * (y1 - y0), scene.start[2])  # along the row
    goals = [_cell(wp, scene.model.robot_pose(obj, grasp))]
    fobj = wp.frame.into(obj)
    want = _whole(field, fobj, goals, limit)
    got = _windowed(field, fobj, goals, limit)
    near = want <= limit
    assert np.array_equal(got[near], want[near])  # exact within the limit
    assert np.all(got <= want)  # a lower bound everywhere
    assert np.all(np.isinf(want[np.isinf(got)]))  # inf: no walk for certain
    assert np.all((got[~near] == limit) | np.isinf(got[~near]))


def test_a_windowed_query_loads_only_the_tiles_it_reaches(corridor):
    scene, _ = corridor
    wp = _uncut(scene)  # fresh: no tile loaded yet
    field = wp.field
    obj = scene.start
    goals = [_cell(wp, scene.model.robot_pose(obj, 1))]
    field.window_from = 0
    field.distances(wp.frame.into(obj), goals, limit=3.0)
    tiles = math.ceil(field.grid.nx / TILE) * math.ceil(field.grid.ny / TILE)
    assert 0 < field.tiles.tiles_built <= 9 < tiles
    assert field.graph is None  # the whole floor's graph was never built


def test_a_walk_planned_in_windows_is_the_walk_planned_over_the_whole_floor(corridor):
    scene, _ = corridor
    walks = []
    for window_from in (0, 2**62):
        ck = PivotChecker(scene)
        ck.walker.field.window_from = window_from
        ck.walker.field.tiles = FloorTiles(ck.walker.field.grid, 8)  # many rounds of tiles
        ck.walker.max_field_states = 0  # the floor distances guide the walk
        walks.append(ck.transit(scene.start, 0, 2))
    assert walks[0].valid
    assert walks[0].robot_path == walks[1].robot_path


def test_the_whole_floor_after_windows_reuses_their_tiles_and_sums_each_yaw_once(corridor):
    from pivot_ompl.transit.floor_grid import OPEN_YAWS

    scene, _ = corridor
    ck = PivotChecker(scene)  # fresh: nothing summed yet
    field = ck.walker.field
    field.window_from = 0  # a large floor: windows first, then the whole floor from tiles
    obj = scene.start
    goals = [_cell(ck.walker, scene.model.robot_pose(obj, 1))]
    field.distances(ck.walker.frame.into(obj), goals, limit=3.0)
    built = field.tiles.tiles_built
    got = field.static_open()
    tiles = math.ceil(field.grid.nx / TILE) * math.ceil(field.grid.ny / TILE)
    assert field.tiles.tiles_built == tiles > built  # the tiles built before were kept
    for k in range(len(OPEN_YAWS)):
        field.grid.fits_index(k)  # the whole floor's rasters share the tiles' sums
    assert field.grid.stats.yaws_summed == len(OPEN_YAWS)
    fresh = PivotChecker(scene).walker.field
    fresh.window_from = 2**62  # the whole floor's, a block of yaws at a time
    assert np.array_equal(got, fresh.static_open())


@pytest.mark.parametrize("t", [0.0, 0.3, 0.6])
def test_a_windowed_query_builds_only_tiles_its_dijkstra_leads_into(corridor, monkeypatch, t):
    # regression: every tile of the goals' component inside the window was built first (a
    # labelling), also those no walk within the limit enters: on the Willow Garage office a
    # regrasp walk built 52 tiles where its Dijkstra entered 14
    from pivot_ompl.transit import floor_window

    monkeypatch.setattr(floor_window, "SINGLE_RINGS", 10**6)  # one ring a round throughout
    scene, _ = corridor
    limit, tile = 6.0, 8
    ck = PivotChecker(scene)
    wp, field = ck.walker, ck.walker.field
    field.tiles = FloorTiles(field.grid, tile)
    (x0, y0, _), (x1, y1, _) = scene.start, scene.goal
    obj = (x0 + t * (x1 - x0), y0 + t * (y1 - y0), scene.start[2])
    goals = [_cell(wp, scene.model.robot_pose(obj, 1))]
    fobj = wp.frame.into(obj)
    _windowed(field, fobj, goals, limit)
    want = _whole(field, fobj, goals, limit)
    ix, iy = np.nonzero(want < limit)  # the positions its Dijkstra settles
    reached = set(zip((ix // tile).tolist(), (iy // tile).tolist(), strict=True))
    # a settled position leads into a neighbouring tile, which is loaded with its ring
    allowed = {(a + dx, b + dy) for a, b in reached | {(gx // tile, gy // tile)
                                                      for gx, gy in goals}
               for dx in range(-2, 3) for dy in range(-2, 3)}
    assert field.tiles.built <= allowed


def test_a_limit_beyond_the_floor_floods_only_the_tiles_its_walks_reach(corridor):
    # regression: a finite limit whose window covered the floor built the whole floor's
    # tiles (the bounds' corners round the turned building too); the Willow Garage office's
    # regrasp walk, whose limit doubles past the floor, built 90 tiles where it reaches 80
    scene, _ = corridor
    wp = _uncut(scene)
    field = wp.field
    field.window_from = 0
    obj = wp.frame.into(scene.start)
    goals = [_cell(wp, scene.model.robot_pose(scene.start, 1))]
    limit = 10.0 * max(field.grid.nx, field.grid.ny) * field.grid.resolution
    got = field.distances(obj, goals, limit=limit)
    assert isinstance(got, FloorWindow)
    tiles = math.ceil(field.grid.nx / TILE) * math.ceil(field.grid.ny / TILE)
    assert field.tiles.tiles_built < tiles
    want = _whole(field, obj, goals, math.inf)
    assert np.array_equal(got.dense(field.grid.nx, field.grid.ny), want)


def test_a_window_that_settled_every_position_it_reaches_is_kept_as_the_whole_floors(corridor):
    # a walk whose limit doubled until its window's Dijkstra ran out of positions asked the
    # floor again with a larger limit, to the same distances (the Willow Garage office's
    # regrasp walks: a fifth Dijkstra over the 59 000 positions the fourth had settled)
    scene, ck = corridor
    obj = ck.walker.frame.into(scene.start)
    goal = _cell(ck.walker, scene.model.robot_pose(scene.start, 1))
    want = _whole(ck.walker.field, obj, [goal], math.inf)
    wp = PivotChecker(scene).walker  # its own floor: no whole floor's graph built
    field = wp.field
    field.window_from = 0
    reach = np.where(np.isfinite(want), want, -1.0)
    far = np.unravel_index(int(np.argmax(reach)), reach.shape)  # the farthest walk's start
    starts = {(int(far[0]), int(far[1]), 0): 0.0}
    goals = {(goal[0], goal[1], 0): 0.0}
    got = wp.floor_distances(obj, goals, starts=starts)
    assert isinstance(got, FloorWindow) and math.isinf(got.outside)
    assert np.array_equal(got.dense(field.grid.nx, field.grid.ny), want)
    assert wp.cached_limit(obj, goals) == math.inf
    asked = []
    distances = field.distances
    field.distances = lambda *a, **k: asked.append(k) or distances(*a, **k)
    try:
        again = wp.floor_distances(obj, goals)  # the whole floor's: kept
    finally:
        del field.distances
    assert again is got and not asked

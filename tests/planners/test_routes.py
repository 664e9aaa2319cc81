"""Turns in place and the held assembly's lattice: routes, and regrasps replaced by turns."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig, RegraspConfig, SearchConfig
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.refine import RefineStats, refine
from pivot_ompl.validity.plan_check import check_plan

COSTS = CostModel()
SPACING = OptimiserConfig().run_spacing
OPEN = dict(bounds=[0.0, 0.0, 10.0, 6.0], start=[1.5, 3.0, 0.0], goal=[8.5, 3.0, 0.0])


def test_a_turn_needs_room_and_its_pivots_are_certified():
    ck = PivotChecker(make_scene(**OPEN))
    q = (5.0, 3.0, 0.3)
    t = ck.turned(q, 0, margin=0.05)
    assert t is not None and ck.state_valid(t, 0)
    assert ck.transfer(q, t, 0).valid
    assert ck.turned((1.0, 3.0, 0.0), 0, margin=0.05) is None  # the floor's side is too near


def test_turn_edges_join_the_manipulation_roadmaps_where_there_is_room():
    scene = make_scene(**OPEN)
    on = RegraspSearch(PivotChecker(scene), scene.start, scene.goal, RegraspConfig(),
                       np.random.default_rng(0))
    on.prepare(lambda: False)
    off = RegraspSearch(PivotChecker(scene), scene.start, scene.goal,
                        RegraspConfig(search=SearchConfig(turns=False)),
                        np.random.default_rng(0))
    off.prepare(lambda: False)
    assert on.roadmap.of_kind("turn") and on.graph.turn_edges > 0
    assert not off.roadmap.of_kind("turn") and off.graph.turn_edges == 0


def test_lattice_routes_end_exactly_and_enclosed_goals_cost_nothing():
    ck = PivotChecker(make_scene(**OPEN))
    lattice = TransferLattice(ck, COSTS)
    route, seconds = lattice.route(ck.scene.start, ck.scene.goal, 0)
    assert route[0] == ck.scene.start and route[-1] == ck.scene.goal
    assert math.isfinite(seconds) and all(ck.state_valid(q, 0) for q in route)
    box = dict(type="box", size=[0.2, 3.0], height=1.0)
    walls = [dict(box, center=[7.0, 3.0]), dict(box, center=[10.0 - 0.1, 3.0]),
             dict(box, center=[8.5, 1.6], size=[3.0, 0.2]),
             dict(box, center=[8.5, 4.4], size=[3.0, 0.2])]
    shut = PivotChecker(make_scene(**{**OPEN, "obstacles": walls}))
    lat = TransferLattice(shut, COSTS)
    assert lat.route(shut.scene.start, (8.5, 3.0, 0.0), 0) == ([], math.inf)
    assert lat.expansions == 0


def _wasteful(ck, grasps):
    """A valid path over an open floor with regrasps that serve nothing."""
    a, b = (3.0, 3.0, 0.0), (6.0, 3.2, 0.2)
    path = [(ck.scene.start, grasps[0]), (a, grasps[0])]
    for g in grasps[1:]:
        path += [(a, g)]
        a, b = b, a
        path += [(a, g)]
    path += [(ck.scene.goal, grasps[-1])]
    assert math.isfinite(Evaluator(ck, COSTS).path(path).cost), path
    return path


def test_regrasps_that_serve_nothing_become_turns_or_go():
    for grasps in ([0, 2], [0, 2, 0], [0, 1, 2]):
        scene = make_scene(**OPEN)
        ck = PivotChecker(scene)
        path = _wasteful(ck, grasps)
        stats = RefineStats()
        out = refine(ck, TransferLattice(ck, COSTS), path, costs=COSTS,
                     should_stop=lambda: False, stats=stats, run_spacing=SPACING)
        regrasps = sum(1 for x, y in zip(out, out[1:], strict=False) if x[1] != y[1])
        assert Evaluator(ck, COSTS).path(out).cost < Evaluator(ck, COSTS).path(path).cost
        assert out[0][0] == scene.start and out[-1][0] == scene.goal  # the goal as given
        # the grasps at the start and at the goal are free: a quarter turn goes too
        assert regrasps == 0, grasps
        assert stats.applied >= 1
        rep = check_plan(path_to_plan(scene, ck, out), scene)
        assert rep.ok, rep.problems


def test_refinement_is_never_costlier_and_stops_at_once():
    scene = shipped("slot")
    ck = PivotChecker(scene)
    search = RegraspSearch(ck, scene.start, scene.goal,
                           RegraspConfig().with_values({"optimiser.enabled": "false"}),
                           np.random.default_rng(1))
    path = search.run(lambda: False)
    lattice = TransferLattice(ck, COSTS)
    same = refine(ck, lattice, path, costs=COSTS, should_stop=lambda: True, run_spacing=SPACING)
    assert same == path
    out = refine(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                 run_spacing=SPACING)
    assert Evaluator(ck, COSTS).path(out).cost <= Evaluator(ck, COSTS).path(path).cost
    assert check_plan(path_to_plan(scene, ck, out), scene).ok


def test_a_face_change_after_the_start_goes_where_a_turn_serves():
    """Two box-only slots: the plan meets the proven bound (no regrasp to change the face)."""
    from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
    from pivot_ompl.api import plan
    from pivot_ompl.generate import GeneratorParams, generate

    scene = generate("walls", 2, params=GeneratorParams(walls=2)).scene
    res = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert res.solved
    assert res.regrasps == regrasp_lower_bound(scene).regrasps == 2
    assert check_plan(res.plan, scene).ok


@settings(max_examples=20, deadline=None)
@given(distance=st.floats(0.05, 2.0), hole=st.floats(0.2, 1.5))
def test_within_distance_is_the_points_within_that_distance_of_the_region(distance, hole):
    import shapely

    from pivot_ompl.planners.routes.lattice import within_distance

    region = shapely.Polygon([(0, 0), (4, 0), (4, 3), (0, 3)],
                             holes=[[(1, 1), (1 + hole, 1), (1 + hole, 2), (1, 2)]]
                             ).union(shapely.box(6, 6, 7, 7.5))  # a hole, two parts
    xs, ys = np.linspace(-2.0, 9.0, 89), np.linspace(-2.0, 9.5, 77)
    got = within_distance(region, xs, ys, distance)
    gap = shapely.distance(region, shapely.points(np.broadcast_to(xs[:, None], got.shape),
                                                   np.broadcast_to(ys[None, :], got.shape)))
    sure = np.abs(gap - distance) > 1e-9  # a point at the distance itself may go either way
    assert np.array_equal(got[sure], (gap <= distance)[sure])


@settings(max_examples=30, deadline=None)
@given(cx=st.floats(-3.0, 10.0), cy=st.floats(-3.0, 10.0), r=st.floats(0.05, 1.5),
       distance=st.floats(0.05, 2.0))
def test_within_distance_of_a_small_region_anywhere_over_the_grid(cx, cy, r, distance):
    """A region far smaller than the grid (a band's), in it, at its edge or beyond it."""
    import shapely

    from pivot_ompl.planners.routes.lattice import within_distance

    region = shapely.Point(cx, cy).buffer(r, quad_segs=3)
    xs, ys = np.linspace(-2.0, 9.0, 89), np.linspace(-2.0, 9.5, 77)
    got = within_distance(region, xs, ys, distance)
    gap = shapely.distance(region, shapely.points(np.broadcast_to(xs[:, None], got.shape),
                                                   np.broadcast_to(ys[None, :], got.shape)))
    sure = np.abs(gap - distance) > 1e-9
    assert got.shape == (len(xs), len(ys))
    assert np.array_equal(got[sure], (gap <= distance)[sure])


def test_within_distance_takes_the_points_at_the_distance_itself():
    """Points exactly ``distance`` from the region are within it (``dwithin``: ``<=``)."""
    import shapely

    from pivot_ompl.planners.routes.lattice import within_distance

    xs = ys = np.arange(-1.0, 2.01, 0.25)  # exact in binary: the gaps are exactly 0.5
    got = within_distance(shapely.box(0.0, 0.0, 1.0, 1.0), xs, ys, 0.5)
    on_edge = {(float(x), float(y)) for x in xs for y in ys
               if (x in (-0.5, 1.5) and 0.0 <= y <= 1.0) or (y in (-0.5, 1.5) and 0.0 <= x <= 1.0)}
    assert len(on_edge) == 20
    for x, y in on_edge:
        assert got[list(xs).index(x), list(ys).index(y)]
    assert not got[0, 0] and not got[list(xs).index(1.5), list(ys).index(1.5)]  # corners: 0.71


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**16), pairs=st.integers(1, 500))
def test_within_distance_is_the_same_measured_in_any_batches(seed, pairs):
    import shapely

    import pivot_ompl.planners.routes.lattice_region as lattice_region

    rng = np.random.default_rng(seed)
    region = shapely.union_all([shapely.Point(*rng.uniform(0.0, 6.0, 2)).buffer(
        rng.uniform(0.2, 1.0), quad_segs=4) for _ in range(5)])
    xs, ys = np.linspace(-1.0, 7.0, 41), np.linspace(-1.0, 7.0, 37)
    whole = lattice_region.within_distance(region, xs, ys, 0.4)
    saved = lattice_region.PAIRS
    lattice_region.PAIRS = pairs
    try:
        assert np.array_equal(lattice_region.within_distance(region, xs, ys, 0.4), whole)
    finally:
        lattice_region.PAIRS = saved

"""The regrasp-free tries before the multiplexed search: RRT-Connect, then the lattice route."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from factories import shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl import plan, scene_from_map
from pivot_ompl.analysis.bound_cache import clear_memory, lower_bound
from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig, RegraspConfig, SingleGraspConfig
from pivot_ompl.planners.direct import DirectStats, direct_path, lattice_path
from pivot_ompl.planners.evaluation import Status
from pivot_ompl.planners.routes.guide import grid_distances
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.validity.plan_check import check_plan

SPACING = OptimiserConfig().run_spacing

HOUSE = Path(__file__).resolve().parents[2] / "scenes" / "maps" / "aws_small_house" / "map.yaml"


@pytest.fixture(scope="module")
def house():
    """The AWS small house, across it with a quarter turn (the buildings benchmark's task)."""
    return scene_from_map(HOUSE, start=(-6.0, -3.0, 0.0), goal=(7.0, -1.0, 0.5 * math.pi))


def _valid_grasps(checker, scene):
    return [g for g in range(4) if checker.state_valid(scene.start, g)
            and checker.state_valid(scene.goal, g)]


def test_the_lattice_crosses_a_house_with_one_grasp_where_no_tree_is_grown(house):
    checker = PivotChecker(house)
    stats = DirectStats()
    lattice = TransferLattice(checker, CostModel())
    states = direct_path(checker, house.start, house.goal,
                         grasps=_valid_grasps(checker, house),
                         config=SingleGraspConfig(checks=0), costs=CostModel(),
                         rng=np.random.default_rng(0), lattice=lambda: lattice, run_spacing=SPACING,
                         should_stop=lambda: False, stats=stats)
    assert stats.solved_by == "lattice" and stats.checks == 0
    assert states[0][0] == house.start and states[-1][0] == house.goal
    assert len({g for _, g in states}) == 1  # one grasp all the way
    p = path_to_plan(house, checker, states)
    assert p.regrasps == 0 and check_plan(p, house).ok


def test_the_cheapest_grasp_route_is_taken_and_the_others_pruned_by_their_bounds(house):
    checker = PivotChecker(house)
    lattice = TransferLattice(checker, CostModel())
    grasps = _valid_grasps(checker, house)
    stats = DirectStats()
    found = lattice_path(checker, lattice, CostModel(), house.start, house.goal,
                         grasps=grasps, weight=1.0, run_spacing=SPACING,
                         should_stop=lambda: False, stats=stats)
    assert found.status is Status.VALID and found.path is not None
    costs = {g: lattice.route(house.start, house.goal, g)[1] for g in grasps}
    assert costs[found.path[0][1]] == min(costs.values())
    # a grasp whose lower bound is above the cheapest route was never searched
    assert stats.routes < len(grasps)


def test_no_single_grasp_path_where_a_regrasp_is_needed_and_none_when_stopped():
    scene = shipped("fig10")  # its walls' passages force two regrasps
    checker = PivotChecker(scene)
    lattice = TransferLattice(checker, CostModel())
    grasps = _valid_grasps(checker, scene)
    stats = DirectStats()
    found = lattice_path(checker, lattice, CostModel(), scene.start, scene.goal,
                         grasps=grasps, weight=1.2, run_spacing=SPACING,
                         should_stop=lambda: False, stats=stats)
    assert found.status is Status.INVALID and found.path is None
    stopped = lattice_path(checker, TransferLattice(checker, CostModel()), CostModel(),
                           scene.start, scene.goal, grasps=grasps, weight=1.2, run_spacing=SPACING,
                           should_stop=lambda: True, stats=DirectStats())
    assert stopped.status is Status.STOPPED


def test_the_planner_ends_with_the_lattice_route_before_seeding_passages(house):
    cfg = RegraspConfig()
    cfg = replace(cfg, single_grasp=replace(cfg.single_grasp, checks=0))
    res = plan(house, time_limit=30.0, seed=0, config=cfg, bound=False)
    assert res.solved and res.plan.regrasps == 0
    assert res.roadmap["single_grasp_by"] == "lattice"
    assert res.roadmap["slots"] == 0 and res.roadmap["doors"] == 0  # nothing seeded
    off = replace(cfg, single_grasp=replace(cfg.single_grasp, lattice=False))
    res_off = plan(house, time_limit=30.0, seed=0, config=off, bound=False)
    assert res_off.roadmap["single_grasp_by"] == ""
    # the house's reachable floor is about 120 m^2: below lattice_area, no lattice try
    small = replace(cfg, single_grasp=replace(cfg.single_grasp, lattice_area=150.0))
    assert plan(house, time_limit=30.0, seed=0, config=small,
                bound=False).roadmap["single_grasp_by"] == ""


def test_the_guided_route_costs_the_same_and_expands_fewer_states(house):
    checker = PivotChecker(house)
    plain, guided = TransferLattice(checker, CostModel()), TransferLattice(checker, CostModel())
    a = plain.route(house.start, house.goal, 1, weight=0.0)  # no guide: Dijkstra
    b = guided.route(house.start, house.goal, 1)
    assert a[1] == pytest.approx(b[1], rel=1e-9)  # both cheapest: the guide is admissible
    assert guided.expansions < 0.6 * plain.expansions
    w = guided.route(house.start, house.goal, 1, weight=1.2)
    assert b[1] <= w[1] <= 1.2 * b[1] + 1e-9


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_grid_distances_are_the_shortest_ways_over_free_cells(seed):
    rng = np.random.default_rng(seed)
    nx, ny = 7, 6
    free = rng.uniform(size=nx * ny) < 0.7
    cell_ids = np.full(nx * ny, -1)
    cell_ids[free] = np.arange(int(free.sum()))
    if not free.any():
        return
    moves = [(1, 0), (0, 1), (1, 1), (2, 1)]
    src = int(rng.integers(int(free.sum())))
    got = grid_distances(cell_ids, nx, ny, moves, [src])
    # Bellman-Ford over the same moves, both ways
    pos = np.flatnonzero(free)
    dist = np.full(len(pos), math.inf)
    dist[src] = 0.0
    for _ in range(len(pos)):
        for k, p in enumerate(pos):
            ix, iy = divmod(int(p), ny)
            for vx, vy in moves:
                for s in (1, -1):
                    jx, jy = ix + s * vx, iy + s * vy
                    if 0 <= jx < nx and 0 <= jy < ny and cell_ids[jx * ny + jy] >= 0:
                        j = cell_ids[jx * ny + jy]
                        dist[k] = min(dist[k], dist[j] + math.hypot(vx, vy))
    assert np.allclose(got, dist)


def test_a_lattice_detour_is_left_to_the_search():
    # the AWS bookstore: the lattice turns only in place, so its routes go round the west
    # side, 2.2-2.4 times the floor's way; the search's curves take the middle aisle
    book = scene_from_map(HOUSE.parents[1] / "aws_bookstore" / "map.yaml",
                          start=(-2.3, 5.4, 0.0), goal=(2.6, -3.1, 0.5 * math.pi))
    checker = PivotChecker(book)
    lattice = TransferLattice(checker, CostModel())
    grasps = _valid_grasps(checker, book)

    def run(detour):
        return lattice_path(checker, lattice, CostModel(), book.start, book.goal,
                            grasps=grasps, weight=1.2, detour=detour, run_spacing=SPACING,
                            should_stop=lambda: False, stats=DirectStats())

    assert run(math.inf).status is Status.VALID
    assert run(1.5).status is Status.INVALID
    g = grasps[0]
    cost = lattice.route(book.start, book.goal, g, weight=1.2)[1]
    assert cost > 2.0 * lattice.way_bound(book.start, book.goal, g)


def test_no_regrasp_free_try_where_a_kept_bound_proves_every_plan_regrasps(tmp_path,
                                                                           monkeypatch):
    """fig10 needs 2 regrasps: once its bound is kept, the one-grasp tries are not made."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    clear_memory()  # nothing kept by earlier tests
    scene = shipped("fig10")
    before = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert before.roadmap["single_grasp_checks"] > 0  # tried while nothing is known
    assert lower_bound(scene).regrasps == 2
    after = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert after.roadmap["single_grasp_checks"] == 0 and after.roadmap["time_single_grasp"] == 0
    assert after.solved and after.plan.regrasps == 2
    # the tries draw from a stream of their own: the search's plan is the one made without
    # the bound kept
    assert after.plan.phases == before.plan.phases

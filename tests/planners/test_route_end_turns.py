"""A lattice route that starts with a turn in place, made real at a tight start.

On the staggered-barrier hall (``benchmarks/layouts/hall.yaml``) the cheaper grasps' lattice
routes start with a quarter turn in place; one transfer turning the whole way grazes the
floor's side, where the lattice's small turns pass. Before, the chain over the route's
corners failed there, so the one-grasp try failed and the plan's cost depended on the grasp
the random roadmap's path happened to use (1101-1318 s over five seeds).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl import plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig, SingleGraspConfig
from pivot_ompl.planners.direct import DirectStats, direct_path, route_weight
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.chain import corners, made_real, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.quality import plan_quality
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.plan_check import check_plan

HALL = Path(__file__).resolve().parents[2] / "benchmarks" / "layouts" / "hall.yaml"
SPACING = OptimiserConfig().run_spacing
#: a grasp whose lattice route starts with a quarter turn in place at the hall's start
GRASP = 1


@pytest.fixture(scope="module")
def hall():
    return load_scene(HALL)


def _route(turn_in: int, straight: int, turn_out: int) -> list[tuple[float, float, float]]:
    """A route turning ``turn_in`` steps in place, pushing ``straight``, turning ``turn_out``."""
    out = [(0.0, 0.0, 0.0)]
    for _ in range(turn_in):
        x, y, a = out[-1]
        out.append((x, y, a + 0.3))
    for _ in range(straight):
        x, y, a = out[-1]
        out.append((x + 0.1 * math.cos(a), y + 0.1 * math.sin(a), a))
    for _ in range(turn_out):
        x, y, a = out[-1]
        out.append((x, y, a + 0.2))
    return out  # every pose distinct


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 5), st.integers(0, 40), st.integers(0, 5), st.integers(1, 8))
def test_end_turns_add_only_the_poses_of_the_turns_at_either_end(turn_in, straight, turn_out,
                                                                  spacing):
    route = _route(turn_in, straight, turn_out)
    coarse = corners(route, spacing=spacing)
    fine = corners(route, spacing=spacing, end_turns=True)
    assert set(coarse) <= set(fine)
    assert fine[0] == route[0] and fine[-1] == route[-1]
    assert fine == sorted(fine, key=route.index)  # in the route's order
    if straight > 0:  # every pose of both end turns, nothing else added
        turns = set(route[:turn_in + 1]) | set(route[len(route) - 1 - turn_out:])
        assert set(fine) - set(coarse) <= turns
        assert turns <= set(fine)


def test_a_route_starting_with_a_turn_at_a_tight_start_is_made_real(hall):
    # grasp 1 (grasp 3's route, since its pushes beside walls are priced higher, turns
    # where the whole turn at once passes)
    checker = PivotChecker(hall)
    costs = CostModel()
    lattice = TransferLattice(checker, costs)
    route, _ = lattice.route(hall.start, hall.goal, GRASP)
    assert abs(route[1][2] - route[0][2]) > 1e-9  # it starts with a turn in place
    evaluate = Evaluator(checker, costs)
    coarse = shortened(evaluate, corners(route, spacing=SPACING), GRASP, lambda: False)
    assert coarse.status is Status.INVALID  # the whole quarter turn at once grazes
    found = made_real(evaluate, route, GRASP, lambda: False, spacing=SPACING)
    assert found.status is Status.VALID and found.path is not None
    chain, cost = found.path
    assert chain[0] == hall.start and chain[-1] == hall.goal
    assert cost == pytest.approx(evaluate.path([(q, GRASP) for q in chain]).cost)


def test_the_hall_is_crossed_by_the_one_grasp_lattice_try(hall):
    checker = PivotChecker(hall)
    stats = DirectStats()
    lattice = TransferLattice(checker, CostModel())
    states = direct_path(checker, hall.start, hall.goal, grasps=[0, 1, 2, 3],
                         config=SingleGraspConfig(checks=0), costs=CostModel(),
                         rng=np.random.default_rng(0), lattice=lambda: lattice,
                         run_spacing=SPACING, should_stop=lambda: False, stats=stats)
    assert stats.solved_by == "lattice"
    assert states[0][0] == hall.start and states[-1][0] == hall.goal
    assert len({g for _, g in states}) == 1


def test_the_hall_costs_the_same_whichever_seed(hall):
    costs = []
    for seed in (1, 4):  # 1318 s and 1101 s before
        res = plan(hall, time_limit=30.0, seed=seed)
        assert res.solved and check_plan(res.plan, hall).ok
        costs.append(plan_quality(res.plan)["cost"])
    assert max(costs) <= 1.02 * min(costs)


def _checks(checker) -> int:
    return checker.counters.valid + checker.counters.invalid


def test_a_route_made_real_once_is_answered_from_the_cache_as_a_fresh_search_would(hall):
    checker = PivotChecker(hall)
    costs = CostModel()
    lattice = TransferLattice(checker, costs)
    evaluate = Evaluator(checker, costs)
    cache: dict = {}
    for grasp in (1, 3):
        route, _ = lattice.route(hall.start, hall.goal, grasp)
        first = made_real(evaluate, route, grasp, lambda: False, spacing=SPACING, cache=cache)
        assert first.status is Status.VALID and first.path is not None
        cost = first.path[1]
        for ceiling in (math.inf, cost + 1.0, cost - 1.0, 0.5 * cost):
            before = _checks(checker)
            cached = made_real(evaluate, route, grasp, lambda: False, spacing=SPACING,
                               ceiling=ceiling, cache=cache)
            assert _checks(checker) == before  # nothing checked again
            fresh = made_real(Evaluator(PivotChecker(hall), costs), route, grasp,
                              lambda: False, spacing=SPACING, ceiling=ceiling)
            assert (cached.path is None) == (fresh.path is None) == (ceiling <= cost)
            if cached.path is not None:
                assert cached.path == fresh.path


def test_no_chain_at_all_is_remembered_too(hall):
    checker = PivotChecker(hall)
    costs = CostModel()
    evaluate = Evaluator(checker, costs)
    blocked = [hall.start, (hall.start[0] + 5.0, hall.start[1], hall.start[2])]  # into a wall
    cache: dict = {}
    assert made_real(evaluate, blocked, 0, lambda: False, spacing=SPACING,
                     cache=cache).status is Status.INVALID
    before = _checks(checker)
    assert made_real(evaluate, blocked, 0, lambda: False, spacing=SPACING,
                     cache=cache).status is Status.INVALID
    assert _checks(checker) == before and list(cache.values()) == [None]


def test_the_re_routing_shares_the_lattice_try_s_weight_only_where_that_try_is_made():
    cfg = SingleGraspConfig()
    assert route_weight(cfg, cfg.lattice_area) == cfg.lattice_weight
    assert route_weight(cfg, cfg.lattice_area - 1.0) == 1.0
    assert route_weight(replace(cfg, lattice=False), 10 * cfg.lattice_area) == 1.0

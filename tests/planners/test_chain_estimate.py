"""The cheapest chain along a route: a transfer's part rotations at its ends are estimated."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes import chain
from pivot_ompl.planners.routes.lattice import TransferLattice

COSTS = CostModel()
SPACING = OptimiserConfig().run_spacing


def _chain(scene_name: str, grasp: int):
    """The scene's lattice route at ``grasp`` made real: the chain and the checks computed."""
    scene = shipped(scene_name)
    ck = PivotChecker(scene)
    route, _ = TransferLattice(ck, COSTS).route(scene.start, scene.goal, grasp)
    assert len(route) > 2
    before = ck.counters.valid + ck.counters.invalid
    found = chain.shortened(Evaluator(ck, COSTS), chain.corners(route, spacing=SPACING), grasp,
                            lambda: False)
    assert found.status is Status.VALID
    return found.path, ck.counters.valid + ck.counters.invalid - before


@pytest.mark.parametrize(("scene", "grasp"), [("corridor", 0), ("corridor", 3),
                                              ("cluttered_room", 1)])
def test_the_part_rotations_estimated_find_the_same_chain_checking_fewer_transfers(
        monkeypatch, scene, grasp):
    found, checks = _chain(scene, grasp)
    # the search that estimates a transfer by its length at the push rate alone sees chains
    # of many short transfers as cheap as those of few long ones, and checks more of them
    monkeypatch.setattr(chain, "end_rotations", lambda costs: 0.0)
    plain, plain_checks = _chain(scene, grasp)
    assert found == plain
    assert checks < plain_checks


def test_the_part_rotations_cost_one_rotation():
    assert chain.end_rotations(COSTS) == COSTS.durations.per_pivot > 0.0

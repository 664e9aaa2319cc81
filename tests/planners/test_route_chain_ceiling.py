"""A lattice route made real under a ceiling: the same chain below it, no checks above it."""

from __future__ import annotations

import math

import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.chain import TOO_DEAR, corners, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice

COSTS = CostModel()
SPACING = OptimiserConfig().run_spacing


def _chain(scene: str, grasp: int, ceiling: float = math.inf):
    """``shortened`` on a fresh checker along the scene's lattice route, and the checks made."""
    ck = PivotChecker(shipped(scene))
    route, _ = TransferLattice(ck, COSTS).route(ck.scene.start, ck.scene.goal, grasp)
    assert len(route) >= 2
    before = ck.counters.valid + ck.counters.invalid
    found = shortened(Evaluator(ck, COSTS), corners(route, spacing=SPACING), grasp, lambda: False,
                      ceiling=ceiling)
    return found, ck.counters.valid + ck.counters.invalid - before


@pytest.mark.parametrize(("scene", "grasp"), [("cluttered_room", 0), ("cluttered_room", 3),
                                               ("open_fig7", 1)])
def test_a_ceiling_keeps_every_chain_below_it_and_spares_the_checks_of_one_above(scene, grasp):
    free, checks = _chain(scene, grasp)
    assert free.status is Status.VALID and free.path is not None
    chain, cost = free.path
    # above the chain's cost: the very same chain, the same checks
    same, same_checks = _chain(scene, grasp, ceiling=cost + 1e-3)
    assert same.path == (chain, cost) and same_checks == checks
    # below it: never a cheaper chain (there is none), never more checks
    below, below_checks = _chain(scene, grasp, ceiling=cost - 1e-3)
    assert below is TOO_DEAR or below.path == (chain, cost)
    assert below_checks <= checks
    # under the bound of any chain (the transfers' fewest seconds): nothing is checked
    none, none_checks = _chain(scene, grasp, ceiling=1.0)
    assert none is TOO_DEAR and none.path == ([], math.inf) and none_checks == 0

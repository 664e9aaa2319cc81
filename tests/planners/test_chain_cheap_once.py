"""A route made real tests each pair of poses cheaply once.

:func:`~pivot_ompl.planners.routes.chain.made_real` searches the route's corners, then the
corners with the poses of its end turns: both searches meet the same pairs of poses, whose
cheap test (:meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.path_free`) gives the same
answer; the second search takes the first one's answers.
"""

from __future__ import annotations

from collections import Counter

import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.generate import generate
from pivot_ompl.planners.config import OptimiserConfig
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.chain import corners, made_real, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice

COSTS = CostModel()
SPACING = OptimiserConfig().run_spacing
#: the regrasp place of ``gen:walls:1``'s plans (seed 0) and the grasp held from there: a
#: route ending with a turn in place, so both searches run
WALLS_REGRASP, WALLS_GRASP = (5.998351191878267, 2.5139395433130627, 0.6547078274734721), 0


def _cases():
    walls = generate("walls", 1).scene
    yield walls, WALLS_REGRASP, walls.goal, WALLS_GRASP, False
    corridor = shipped("corridor")
    for grasp in (1, 3):
        yield corridor, corridor.start, corridor.goal, grasp, True


@pytest.mark.parametrize("case", list(_cases()), ids=["walls", "corridor-1", "corridor-3"])
def test_each_pair_is_tested_cheaply_once_and_the_chain_is_the_same(monkeypatch, case):
    scene, start, goal, grasp, turned = case
    never = lambda: False  # noqa: E731
    checker = PivotChecker(scene)
    route, cost = TransferLattice(checker, COSTS, turned=turned).route(start, goal, grasp,
                                                                       leads=True)
    assert len(route) > 2 and cost < 1e9
    tests: Counter = Counter()
    cheap = checker.path_free

    def counted(a, b, g, **kwargs):
        tests[(a, b, g)] += 1
        return cheap(a, b, g, **kwargs)

    monkeypatch.setattr(checker, "path_free", counted)
    found = made_real(Evaluator(checker, COSTS), route, grasp, never, spacing=SPACING,
                      leads=True)
    assert tests and max(tests.values()) == 1
    # the same chain as the two searches each testing on their own, on a fresh checker
    monkeypatch.undo()
    alone = PivotChecker(scene)
    evaluate = Evaluator(alone, COSTS)
    coarse = shortened(evaluate, corners(route, spacing=SPACING), grasp, never)
    fine = corners(route, spacing=SPACING, end_turns=True, leads=True)
    tries = [coarse]
    if len(fine) > len(corners(route, spacing=SPACING)):
        below = coarse.path[1] if coarse.path is not None else float("inf")
        tries.append(shortened(evaluate, fine, grasp, never, ceiling=below))
    best = min((t.path for t in tries if t.path is not None), key=lambda p: p[1],
               default=None)
    assert (found.status is Status.VALID) == (best is not None)
    if best is not None:
        assert found.path[0] == best[0]
        assert found.path[1] == pytest.approx(best[1])

"""The cheapest chain along a route: every transfer of a candidate chain takes the cheap test
before any of them takes the full check."""

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


def _rounds(monkeypatch, scene_name: str, grasp: int):
    """The chain found along the scene's lattice route, and each search round's tests.

    A round is a list of ``("cheap", passed)`` and ``("full", valid)`` events.
    """
    scene = shipped(scene_name)
    ck = PivotChecker(scene)
    route, _ = TransferLattice(ck, COSTS).route(scene.start, scene.goal, grasp)
    evaluate = Evaluator(ck, COSTS)
    rounds: list[list[tuple[str, bool]]] = []
    cheap, full = ck.path_free, evaluate.transfer

    def spied_cheap(*args, **kwargs):
        passed = cheap(*args, **kwargs)
        rounds[-1].append(("cheap", passed))
        return passed

    def spied_full(*args, **kwargs):
        e = full(*args, **kwargs)
        rounds[-1].append(("full", e.valid))
        return e

    monkeypatch.setattr(ck, "path_free", spied_cheap)
    monkeypatch.setattr(evaluate, "transfer", spied_full)
    search = chain.lazy_search

    def spied_search(cheapest, check, should_stop):
        def checked(found):
            rounds.append([])
            return check(found)
        return search(cheapest, checked, should_stop)

    monkeypatch.setattr(chain, "lazy_search", spied_search)
    found = chain.shortened(evaluate, chain.corners(route, spacing=SPACING), grasp,
                            lambda: False)
    return found, rounds


@pytest.mark.parametrize(("scene", "grasp"), [("corridor", 1), ("corridor", 3)])
def test_a_round_whose_cheap_test_refuses_a_transfer_pays_for_no_full_check(
        monkeypatch, scene, grasp):
    found, rounds = _rounds(monkeypatch, scene, grasp)
    assert found.status is Status.VALID
    refused = [r for r in rounds if ("cheap", False) in r]
    assert refused  # the routes' chains do meet transfers the cheap test refuses
    for r in refused:
        assert not any(kind == "full" for kind, _ in r)
    for r in rounds:  # and in the others the cheap tests all come first
        kinds = [kind for kind, _ in r]
        assert kinds == sorted(kinds)  # "cheap" < "full"

"""The regrasp planner routes the regrasp lattice's legs at its lattice's weight first.

The re-routing after them (:mod:`pivot_ompl.planners.routes.refine`) asks the lattice's routes
at that weight: legs routed at another weight were searched and made real once for the path,
then again for the re-routing. A leg whose route at that weight fails its checks is routed
again at weight 1 (the lattice's cheapest route).
"""

from __future__ import annotations

from corner_factories import open_corner

from pivot_ompl.api import plan
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.routes.lattice import TransferLattice

SPEC = "regrasp[sampling.band_area=0;sampling.band_boxes=0;single_grasp.lattice_area=0]"


def test_a_leg_is_routed_at_the_lattices_weight_before_weight_one(monkeypatch):
    asked: list[tuple[tuple, float]] = []  # (start, goal, grasp), weight
    route = TransferLattice.route

    def spy(self, start, goal, grasp, **kwargs):
        weight = kwargs.get("weight")
        asked.append(((start, goal, grasp), self.weight if weight is None else weight))
        return route(self, start, goal, grasp, **kwargs)

    monkeypatch.setattr(TransferLattice, "route", spy)
    result = plan(open_corner(), planner=SPEC, time_limit=30.0, seed=0)
    assert result.status == "EXACT_SOLUTION"
    assert result.roadmap["regrasp_lattice_solved"] is True
    lattice_weight = RegraspConfig().single_grasp.lattice_weight
    assert lattice_weight != 1.0  # else the test tells nothing
    assert any(w == lattice_weight for _, w in asked)
    for k, (query, weight) in enumerate(asked):
        assert weight in (1.0, lattice_weight)
        if weight == 1.0:  # only after the same query at the lattice's weight
            assert (query, lattice_weight) in asked[:k]

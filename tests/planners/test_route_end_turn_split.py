"""A lattice route's end turns split whenever that makes its chain cheaper.

On the generated walls ``gen:walls:1`` the transfer after the regrasp ends with a 1.65 rad
turn in place onto the goal's yaw. Joined as one transfer, that turn is a Reeds-Shepp
manoeuvre of about 120 s; split at the lattice's turn poses it costs about 78 s. Before, the
split was tried only where the chain over the route's corners failed, so the route's chain
cost 252 s against the plan's own transfer (about 200 s) and the re-routing kept the plan's
transfer: the plan cost 772 s over a route 1.71 x the shortest.
"""

from __future__ import annotations

import pytest

from pivot_ompl import plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.generate import generate
from pivot_ompl.planners.config import OptimiserConfig
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.chain import TOO_DEAR, corners, made_real, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.validity.plan_check import check_plan

SPACING = OptimiserConfig().run_spacing
#: the regrasp place of ``gen:walls:1``'s plans (seed 0), box pose after the regrasp
REGRASP = (5.998351191878267, 2.5139395433130627, 0.6547078274734721)
#: the grasp held from there to the goal
GRASP = 0


@pytest.fixture(scope="module")
def walls():
    return generate("walls", 1).scene


@pytest.fixture(scope="module")
def route(walls):
    checker = PivotChecker(walls)
    costs = CostModel()
    # the lattice in world headings: its route ends with the long turn in place (the walls'
    # frame lines the route up with the walls and leaves a smaller turn)
    lattice = TransferLattice(checker, costs, turned=False)
    poses, cost = lattice.route(REGRASP, walls.goal, GRASP, leads=True)
    assert len(poses) > 2 and cost < 1e9
    return Evaluator(checker, costs), poses


def test_the_chain_is_no_dearer_than_either_set_of_corners(route):
    evaluate, poses = route
    never = lambda: False  # noqa: E731
    found = made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True)
    assert found.status is Status.VALID
    coarse = corners(poses, spacing=SPACING)
    fine = corners(poses, spacing=SPACING, end_turns=True, leads=True)
    assert len(fine) > len(coarse)  # the route ends with a turn in place
    tries = [shortened(evaluate, c, GRASP, never) for c in (coarse, fine)]
    costs = [t.path[1] for t in tries if t.path is not None]
    assert costs
    assert found.path[1] <= min(costs) + 1e-6
    # the split turn is the cheaper one here, by far (one transfer: a long manoeuvre)
    assert tries[1].path is not None and tries[1].path[1] < 0.85 * tries[0].path[1]


def test_a_ceiling_below_both_chains_is_too_dear(route):
    evaluate, poses = route
    never = lambda: False  # noqa: E731
    best = made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True).path[1]
    found = made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True,
                      ceiling=0.99 * best)
    assert found is TOO_DEAR
    cache: dict = {}
    found = made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True,
                      ceiling=1.01 * best, cache=cache)
    assert found.path is not None and abs(found.path[1] - best) < 1e-6
    # answered from the cache: the same chain under a ceiling above it, too dear below
    again = made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True,
                      cache=cache)
    assert again.path is not None and again.path[1] == found.path[1]
    assert made_real(evaluate, poses, GRASP, never, spacing=SPACING, leads=True,
                     ceiling=0.5 * best, cache=cache) is TOO_DEAR


@pytest.mark.slow
@pytest.mark.timed
def test_the_walls_plan_keeps_its_route_within_one_and_a_half_of_the_shortest(walls):
    res = plan(walls, planner="regrasp", time_limit=30.0, seed=0)
    assert res.solved
    q = res.plan.extra["quality"]
    assert q["regrasps"] == q["regrasps_lower_bound"] == 1
    assert q["route_ratio"] is not None and q["route_ratio"] <= 1.5, q["route_ratio"]
    assert check_plan(res.plan, walls).ok

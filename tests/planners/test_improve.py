"""The one improve step of fresh plans and repairs: budgets, and the held grasp kept."""

from __future__ import annotations

import math

from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.improve import ROUNDS, Budget, ImproveStats, improve
from pivot_ompl.planners.repair import polish
from pivot_ompl.planners.routes.lattice import TransferLattice

A, B = (1.5, 3.0, 0.0), (6.0, 3.0, 0.0)
#: the goal turned, with a wall where the robot would stand at grasp 0: the box ends there at
#: grasp 1 (or 2, 3)
TURNED = (6.0, 3.0, -math.pi / 2)
BEHIND = [dict(type="box", height=1.0, center=[6.0, 4.3], size=[1.2, 0.6])]
#: held with grasp 0, the robot walks to grasp 1 and pushes from there: the regrasp at the
#: start is what holding grasp 0 costs, not a detour to remove
HELD_0 = [(A, 0), (A, 1), (TURNED, 1)]


def test_a_repair_polished_from_a_held_grasp_starts_with_it():
    """Regression: the polish did not pass the held grasp to the lattice re-routing, which
    re-planned the run from the start at another grasp (the regrasp at the start removed)."""
    ck = PivotChecker(make_scene(goal=list(TURNED), obstacles=BEHIND))
    assert not ck.state_valid(TURNED, 0)
    out = polish(ck, list(HELD_0), RegraspConfig(), should_stop=lambda: False, lattice=True,
                 start_grasp=0)
    assert out[0] == (A, 0) and out[-1][0] == TURNED
    ev = Evaluator(ck, RegraspConfig().cost)
    assert math.isfinite(ev.path(out).cost)
    assert ev.path(out).cost <= ev.path(HELD_0).cost


def test_without_a_held_grasp_the_regrasp_at_the_start_goes():
    ck = PivotChecker(make_scene(goal=list(TURNED), obstacles=BEHIND))
    out = polish(ck, list(HELD_0), RegraspConfig(), should_stop=lambda: False, lattice=True)
    assert out[0][0] == A and out[-1][0] == TURNED
    assert len({g for _, g in out}) == 1  # one grasp: the regrasp served nothing


def test_each_step_keeps_to_its_budget_of_motion_checks():
    ck = PivotChecker(make_scene(obstacles=[dict(type="box", height=1.0, center=[4.0, 2.0],
                                                 size=[0.3, 2.0])]))
    config = RegraspConfig()
    path = [(A, 0), ((3.0, 4.5, 0.5), 0), ((5.0, 4.5, -0.5), 0), (B, 0)]
    c = ck.counters
    stats = ImproveStats()
    none = Budget()  # no check beyond the path's own (cache hits)
    Evaluator(ck, config.cost).path(path)
    before = c.valid + c.invalid
    out = improve(ck, path, config, should_stop=lambda: False, routes=none, optimiser=none,
                  start_grasp=None, lattice=TransferLattice(ck, config.cost), stats=stats)
    # a step stops once it computed more than its budget: the re-routing one check at most,
    # then per round the optimiser, the followed route (first round) and the straightening,
    # each within the optimiser's budget, one check or one candidate at most (the
    # straightening's turn, push and turn: two checks here, its turns in place pass), and
    # the rounds repeat while one changes the path
    assert c.valid + c.invalid - before <= 1 + ROUNDS * 4
    assert out[0][0] == A and out[-1][0] == B
    assert stats.seconds >= stats.routes_seconds >= 0.0

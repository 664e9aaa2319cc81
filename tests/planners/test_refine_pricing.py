"""The re-routing's pricing of runs: the lattice's bound and the branch and bound over runs."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.run_pricing import best_run

COSTS = CostModel()
BOX = dict(type="box", height=1.0)
CLUTTERED = dict(bounds=[0.0, 0.0, 10.0, 6.0], start=[1.5, 3.0, 0.0], goal=[8.5, 3.0, 0.0],
                 obstacles=[dict(BOX, center=[5.0, 2.0], size=[0.3, 2.6]),
                            dict(BOX, center=[3.2, 4.8], size=[1.2, 0.4], yaw=0.4)])


def test_the_lattice_bound_is_below_every_route():
    ck = PivotChecker(make_scene(**CLUTTERED))
    lattice = TransferLattice(ck, COSTS)
    rng = np.random.default_rng(3)
    routed = 0
    for _ in range(40):
        a, b = _free(ck, rng), _free(ck, rng)
        g = int(rng.integers(4))
        _route, seconds = lattice.route(a, b, g)
        low = lattice.lower_bound(a, b, g)
        assert low >= 0.0
        if math.isfinite(seconds):
            routed += 1
            assert seconds >= low - 1e-9, (a, b, g)
    assert routed >= 10


def _free(ck: PivotChecker, rng: np.random.Generator) -> tuple[float, float, float]:
    while True:
        q = (float(rng.uniform(0.5, 9.5)), float(rng.uniform(0.5, 5.5)),
             float(rng.uniform(-math.pi, math.pi)))
        if all(ck.state_valid(q, g) for g in range(4)):
            return q


def _zigzag(ck: PivotChecker, grasps: list[int]) -> list[tuple[tuple[float, float, float], int]]:
    """A valid path over the floor with regrasps that serve little, one phase per grasp."""
    stops = [(1.5 + 7.0 * k / len(grasps), 3.0 + 0.4 * (-1) ** k, 0.1 * k)
             for k in range(1, len(grasps))]
    path = [(ck.scene.start, grasps[0])]
    for q, g, h in zip(stops, grasps, grasps[1:], strict=False):
        path += [(q, g), (q, h)]
    path.append((ck.scene.goal, grasps[-1]))
    return path


def test_routing_only_the_runs_that_may_win_picks_what_pricing_every_run_picks():
    scene = make_scene(**{**CLUTTERED, "obstacles": CLUTTERED["obstacles"][1:]})
    compared = pruned = every = 0
    rng = np.random.default_rng(11)
    sequences = [[0, 2, 0, 2], [0, 1, 2, 3, 0], [3, 1, 0, 2, 0], [2, 0, 1, 3, 1, 0]]
    while len(sequences) < 12:  # and random ones: a new grasp at each regrasp
        seq = [int(rng.integers(4))]
        for _ in range(int(rng.integers(2, 6))):
            seq.append((seq[-1] + int(rng.integers(1, 4))) % 4)
        sequences.append(seq)
    for grasps in sequences:
        ck = PivotChecker(scene)
        path = _zigzag(ck, grasps)
        if not math.isfinite(Evaluator(ck, COSTS).path(path).cost):
            assert grasps not in sequences[:4]  # the fixed ones are valid
            continue
        lattice = TransferLattice(ck, COSTS)
        for start_grasp in (None, path[0][1]):
            refused: frozenset[tuple[int, int, int]] = frozenset()
            for _ in range(60):  # as refine does: the best refused, then the next, to the last
                got, want = (best_run(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                                      start_grasp=start_grasp, exclude=refused,
                                      exhaustive=exhaustive) for exhaustive in (False, True))
                assert (got.run, got.saving) == (want.run, want.saving), (grasps, start_grasp)
                assert got.routed <= want.routed
                pruned, every = pruned + got.routed, every + want.routed
                compared += 1
                if got.run is None:
                    break
                assert got.saving > 0.0
                refused |= {got.run}
    assert compared >= 16
    assert pruned < every  # the bound spares routes


def test_no_run_is_chosen_on_an_empty_path_or_one_that_fails_its_checks():
    ck = PivotChecker(make_scene(**CLUTTERED))
    lattice = TransferLattice(ck, COSTS)
    through_wall = [(ck.scene.start, 0), ((5.0, 2.0, 0.0), 0), (ck.scene.goal, 0)]
    assert not math.isfinite(Evaluator(ck, COSTS).path(through_wall).cost)
    for path in ([], through_wall):
        got = best_run(ck, lattice, path, costs=COSTS, should_stop=lambda: False)
        assert (got.run, got.saving, got.routed) == (None, 0.0, 0)

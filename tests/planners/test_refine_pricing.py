"""The re-routing's pricing of runs: the lattice's bound and the branch and bound over runs."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.refine import (
    RefineStats,
    _best_candidate,
    _candidates,
    _phases,
    _priced,
    _Pricer,
)

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


def _brute_force(lattice, pricer, phases, current, refused, start_grasp):
    """The run pricing every run chooses: the largest saving, ties to the earlier run."""
    cost = [pricer.phase(p) for p in phases]
    regrasp = [0.0] + [pricer.regrasp(a, b) for a, b in zip(phases, phases[1:], strict=False)]
    best = None
    for i, j, g in _candidates(phases, start_grasp):
        if (i, j, g, phases[i].poses) in refused:
            continue
        priced = _priced(lattice, phases, cost, regrasp, current, (i, j, g), lambda: False)
        if priced is not None and priced[0] > 1e-9 and (best is None or priced[0] > best[0]):
            best = (priced[0], i, j, g, priced[1])
    return None if best is None else best[1:]


def test_routing_only_the_runs_that_may_win_picks_what_pricing_every_run_picks():
    scene = make_scene(**{**CLUTTERED, "obstacles": CLUTTERED["obstacles"][1:]})
    compared = 0
    for grasps in ([0, 2, 0, 2], [0, 1, 2, 3, 0], [3, 1, 0, 2, 0], [2, 0, 1, 3, 1, 0]):
        ck = PivotChecker(scene)
        path = _zigzag(ck, grasps)
        assert math.isfinite(Evaluator(ck, COSTS).path(path).cost), grasps
        lattice, pricer = TransferLattice(ck, COSTS), _Pricer(ck, COSTS)
        phases = _phases(path)
        current = pricer.path(phases)
        refused: set = set()
        for start_grasp in (None, path[0][1]):
            for _ in range(4):  # as refine does: the best refused, then the next
                st = RefineStats()
                got = _best_candidate(lattice, pricer, phases, current, refused, lambda: False,
                                      st, start_grasp)
                want = _brute_force(lattice, pricer, phases, current, refused, start_grasp)
                assert got == want, (grasps, start_grasp)
                compared += 1
                if got is None:
                    break
                refused.add((got[0], got[1], got[2], phases[got[0]].poses))
            assert st.candidates <= len(_candidates(phases, start_grasp))
    assert compared >= 16

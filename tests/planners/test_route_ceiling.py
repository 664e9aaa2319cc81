"""Work the re-routing need not do: a chain too dear, a small saving, a distance asked twice."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import InputError
from pivot_ompl.planners.config import OptimiserConfig, RegraspConfig, parameters
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.routes import lattice as lattice_module
from pivot_ompl.planners.routes.chain import TOO_DEAR, corners, shortened
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.refine import RefineStats, refine
from pivot_ompl.planners.routes.run_pricing import best_run

COSTS = CostModel()
SPACING = OptimiserConfig().run_spacing
GRASP = 1


def _chain(ceiling: float):
    """The cluttered room's lattice route at ``GRASP`` made real; the checks it computed."""
    scene = shipped("cluttered_room")
    ck = PivotChecker(scene)
    route, _ = TransferLattice(ck, COSTS).route(scene.start, scene.goal, GRASP)
    assert len(route) > 2
    before = ck.counters.valid + ck.counters.invalid
    found = shortened(Evaluator(ck, COSTS), corners(route, spacing=SPACING), GRASP,
                      lambda: False, ceiling=ceiling)
    return found, ck.counters.valid + ck.counters.invalid - before


@pytest.fixture(scope="module")
def unbounded():
    found, checks = _chain(math.inf)
    assert found.status is Status.VALID
    return found.path, checks


@pytest.mark.parametrize("above", [1e-3, 1.0, 50.0])
def test_a_ceiling_above_the_chains_cost_changes_nothing(unbounded, above):
    (chain, cost), checks = unbounded
    found, n = _chain(cost + above)
    assert found.status is Status.VALID and found.path == (chain, cost)
    assert n <= checks


@pytest.mark.parametrize("share", [0.999, 0.9, 0.6, 0.3])
def test_a_chain_that_cannot_beat_the_ceiling_is_refused_before_its_checks_end(unbounded,
                                                                                share):
    (_chain_poses, cost), checks = unbounded
    found, n = _chain(share * cost)
    assert found is TOO_DEAR and found.status is Status.INVALID and found.path is None
    assert n <= checks
    if share < 0.8:  # stopped before every transfer of the chain was checked
        assert n < checks


def test_a_route_and_its_way_bound_compute_the_floor_distances_once(monkeypatch):
    # a start no other test plans from (moved by 0.1 um): the floor distances the scenes'
    # shared memo keeps for cluttered_room in this process are not this scene's
    room = shipped("cluttered_room")
    scene = dataclasses.replace(room, start=(room.start[0] + 1e-7, *room.start[1:]))
    calls = []
    real = lattice_module.graph_distances

    def counted(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    lat = TransferLattice(PivotChecker(scene), COSTS)
    fresh = TransferLattice(PivotChecker(scene), COSTS)
    way = fresh.way_bound(scene.start, scene.goal, GRASP)
    monkeypatch.setattr(lattice_module, "graph_distances", counted)
    route = lat.route(scene.start, scene.goal, GRASP)
    assert lat.way_bound(scene.start, scene.goal, GRASP) == way
    assert len(calls) == 1
    assert len(route[0]) > 2
    lat.route(scene.start, scene.goal, GRASP + 2)  # the other side's car: other goal cells
    assert len(calls) == 2


def _found_path(ck):
    """The cluttered room's path as found (a direct single-grasp path), not improved."""
    scene = ck.scene
    search = RegraspSearch(ck, scene.start, scene.goal,
                           RegraspConfig().with_values({"optimiser.enabled": "false"}),
                           np.random.default_rng(0))
    path = search.run(lambda: False)
    assert math.isfinite(Evaluator(ck, COSTS).path(path).cost)
    return path


def test_a_run_estimated_to_save_no_more_than_the_least_share_is_not_replanned():
    scene = shipped("cluttered_room")
    ck = PivotChecker(scene)
    lattice = TransferLattice(ck, COSTS)
    path = _found_path(ck)
    current = Evaluator(ck, COSTS).path(path).cost
    first = best_run(ck, lattice, path, costs=COSTS, should_stop=lambda: False, grasps=(0, 1, 2, 3))
    assert first.run is not None and first.saving > 0
    share = first.saving / current

    def refined(min_saving):
        stats = RefineStats()
        out = refine(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                     run_spacing=SPACING, stats=stats, grasps=(0, 1, 2, 3),
                     min_saving=min_saving)
        return out, stats

    out, stats = refined(share * 1.001)  # the best estimate is under it: nothing is tried
    assert out == path and stats.tried == 0 and stats.applied == 0
    out, stats = refined(share * 0.999)
    assert stats.tried >= 1
    assert Evaluator(ck, COSTS).path(out).cost <= current
    assert refined(0.0)[0] == refine(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                                     run_spacing=SPACING, grasps=(0, 1, 2, 3))


def test_the_least_saving_is_a_listed_knob():
    listed = {p.name: p for p in parameters()}
    knob = listed["optimiser.route_min_saving"]
    assert knob.default == 0.05 and knob.doc
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({"optimiser.route_min_saving": "-0.1"})
    assert e.value.field == "optimiser.route_min_saving"


def _refined(ck, lattice, path, **kwargs):
    stats = RefineStats()
    out = refine(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                 run_spacing=SPACING, stats=stats, grasps=(0, 1, 2, 3), **kwargs)
    return out, stats


def test_whole_path_runs_estimated_under_their_least_share_are_not_made_real():
    # the corridor's found path is one phase: every run re-plans the whole path (the
    # cluttered room's before the lattice priced pushes beside walls higher: its estimates
    # are now all above the share or far under it)
    ck = PivotChecker(shipped("corridor"))
    lattice = TransferLattice(ck, COSTS)
    path = _found_path(ck)
    evaluate = Evaluator(ck, COSTS)
    every, every_stats = _refined(ck, lattice, path, min_saving=0.05)
    share = OptimiserConfig().whole_min_saving
    fewer, fewer_stats = _refined(ck, lattice, path, min_saving=0.05, whole_min_saving=share)
    # the run it leaves (estimated to save under 10 %) costs more than the path once checked:
    # the same path, fewer routes made real
    assert fewer == every and evaluate.path(fewer).cost < evaluate.path(path).cost
    assert fewer_stats.tried < every_stats.tried
    assert fewer_stats.applied == every_stats.applied >= 1
    # above the best run's estimated share nothing is tried at all
    first = best_run(ck, lattice, path, costs=COSTS, should_stop=lambda: False,
                     grasps=(0, 1, 2, 3))
    top = first.saving / evaluate.path(path).cost
    out, stats = _refined(ck, lattice, path, whole_min_saving=top * 1.001)
    assert out == path and stats.tried == 0


def test_the_whole_paths_least_share_leaves_the_runs_of_fewer_phases():
    ck = PivotChecker(shipped("fig10"))
    lattice = TransferLattice(ck, COSTS)
    path = _found_path(ck)
    evaluate = Evaluator(ck, COSTS)
    assert len({g for _, g in path}) > 1  # regrasps: runs of one phase exist
    out, stats = _refined(ck, lattice, path, whole_min_saving=1.0)
    assert stats.applied >= 1 and evaluate.path(out).cost < evaluate.path(path).cost


def test_the_whole_paths_least_share_is_a_listed_knob():
    listed = {p.name: p for p in parameters()}
    knob = listed["optimiser.whole_min_saving"]
    assert knob.default == 0.1 and knob.doc
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({"optimiser.whole_min_saving": "1.5"})
    assert e.value.field == "optimiser.whole_min_saving"

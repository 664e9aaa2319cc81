"""The search tells what it expects of its plan once, as soon as it knows it."""

from __future__ import annotations

import math

import pytest
from corner_factories import open_corner
from factories import shipped

from pivot_ompl.base.problem import make_setup
from pivot_ompl.base.state import read_state
from pivot_ompl.planners import make_planner
from pivot_ompl.planners.expectation import Expectation

#: The regrasp lattice's coarse plan taken on the small corner (no band, no area floor).
LATTICE = "regrasp[sampling.band_area=0;sampling.band_boxes=0;single_grasp.lattice_area=0]"


def _told(scene, spec: str, seed: int = 0) -> tuple[list, object, object]:  # noqa: ANN001
    problem = make_setup(scene, seed=seed)
    planner = make_planner(spec, problem, seed=seed)
    told: list = []
    planner.expect = lambda regrasps, places: told.append((regrasps, places))
    problem.setup.setPlanner(planner)
    assert str(problem.setup.solve(30.0)) == "Exact solution"
    return told, planner, problem


def test_the_lattice_s_coarse_plan_is_told_with_where_it_regrasps():
    told, planner, problem = _told(open_corner(), LATTICE)
    assert len(told) == 1
    regrasps, places = told[0]
    search = planner.last_search
    assert regrasps == search.stats.regrasp_lattice_changes == 1
    assert places and all(len(p) == 2 for p in places)
    # the plan regrasps where it was told it would (a place refined first is worth it)
    solution = problem.setup.getSolutionPath()
    path = [read_state(solution.getState(i)) for i in range(solution.getStateCount())]
    at = [a[0] for a, b in zip(path, path[1:], strict=False) if a[1] != b[1]]
    assert len(at) == 1
    assert min(math.dist(at[0][:2], p) for p in places) <= 1.0


def test_a_plan_without_regrasps_is_told_as_such_and_no_coarse_plan_as_unknown():
    told, _, _ = _told(shipped("open_fig7"), "regrasp")
    assert told == [(0, ())]
    off = LATTICE.replace("]", ";sampling.regrasp_lattice=false]")
    told, planner, _ = _told(open_corner(), off)
    assert told == [(None, ())]
    assert planner.last_search.stats.regrasp_lattice_changes == -1


def test_a_resumed_search_tells_at_once_that_it_knows_nothing_new():
    told, planner, problem = _told(shipped("open_fig7"), "regrasp")
    again: list = []
    planner.expect = lambda regrasps, places: again.append((regrasps, places))
    problem.setup.solve(10.0)  # the same problem: the search is resumed
    assert planner.last_search is not None and told == [(0, ())]
    assert again == [(None, ())]


@pytest.mark.parametrize("first", [0, 2, None])
def test_only_the_first_expectation_is_told(first):
    told: list = []
    e = Expectation(lambda r, p: told.append((r, p)))
    e.tell(first, ((1.0, 2.0),) if first else ())
    e.tell(5, ((3.0, 4.0),))
    assert told == [(first, ((1.0, 2.0),) if first else ())] and e.told
    Expectation().tell(1)  # nobody listens: nothing happens

"""Long unpolled steps found by profiling ``plan --time T`` (issue 43, class 5).

A 10 000-point polygon on a 100 m floor at ``--time 2`` ended at 2.26-2.77 s: the single-grasp
connection's cheap filter (:meth:`PivotChecker.path_free`) tested the whole start-to-goal
path (hundreds of poses, each a few ms against the polygon) without looking at the clock.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import DeadlineWatch, make_scene

from pivot_ompl.api import plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.evaluation import Status
from pivot_ompl.planners.single_grasp import SingleGraspConnect

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


def _star(n: int, cx: float, cy: float) -> list[list[float]]:
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    r = np.where(np.arange(n) % 2 == 0, 3.0, 2.0)
    return [[float(cx + q * math.cos(t)), float(cy + q * math.sin(t))]
            for t, q in zip(a, r, strict=True)]


@pytest.fixture(scope="module")
def star_hall():
    """A 100 m floor holding one 10 000-point star at its middle (off the straight path)."""
    return make_scene(bounds=[0.0, 0.0, 100.0, 100.0], start=[5.0, 5.0, 0.0],
                      goal=[95.0, 95.0, 0.0],
                      obstacles=[{"type": "polygon", "height": 1.0,
                                  "points": _star(10_000, 50.0, 50.0)}])


def _stop_after(n: int):
    calls: list[int] = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) > n

    return stop, calls


def test_the_cheap_path_filter_polls_along_a_long_path(star_hall):
    checker = PivotChecker(star_hall)
    stop, calls = _stop_after(2)
    with pytest.raises(Interrupted):
        checker.path_free(star_hall.start, star_hall.goal, 0, should_stop=stop)
    assert len(calls) == 3
    # unstopped, the same answer as without a stop condition
    assert checker.path_free(star_hall.start, star_hall.goal, 0, should_stop=lambda: False) \
        == checker.path_free(star_hall.start, star_hall.goal, 0)


def test_the_single_grasp_connection_stops_inside_its_first_edge(star_hall):
    checker = PivotChecker(star_hall)
    grasp = next(g for g in range(4) if checker.state_valid(star_hall.start, g)
                 and checker.state_valid(star_hall.goal, g))
    connect = SingleGraspConnect(checker, star_hall.start, star_hall.goal, grasp,
                                 np.random.default_rng(0))
    tested = []
    state_valid = checker.state_valid
    checker.state_valid = lambda obj, g: tested.append(obj) or state_valid(obj, g)  # type: ignore[method-assign]
    found = connect.run(100, lambda: True)
    assert found.status is Status.STOPPED
    # stopped within the direct edge's cheap filter, a few poses in (the path is 500 poses
    # long and meets the star half way)
    assert len(tested) <= 10, len(tested)


def test_a_large_polygon_plan_ends_within_its_limit(star_hall):
    limit = 1.5
    with DeadlineWatch(limit) as watch:
        res = plan(star_hall, time_limit=limit, bound=False)
    assert res.status in ("TIMEOUT", "EXACT_SOLUTION")
    # the work after the deadline, in this process's CPU seconds (a loaded machine stretches
    # the wall clock, not these)
    assert watch.cpu_past_deadline < 0.05 * limit + 0.05, watch.cpu_past_deadline
    assert watch.wall < 3 * limit, watch.wall

"""The evaluation layer: every check answers valid (with its cost), invalid (with its reason)
or stopped, and a stopped check is never taken for a failed one."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator, Found, Status, lazy_search
from pivot_ompl.planners.objects.critical import CriticalConfigurations
from pivot_ompl.planners.objects.roadmap import Roadmap
from pivot_ompl.planners.objects.visibility import VisibilityRoadmap

COSTS = CostModel()
WALL = dict(type="box", height=1.0, center=[4.0, 3.0], size=[0.3, 6.0])
A, B = (1.5, 3.0, 0.0), (6.0, 3.0, 0.0)


def _after(n: int):
    """A stop condition that says stop from its ``n + 1``-th call on."""
    calls = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) > n

    return stop


def test_a_valid_transfer_carries_its_cost_from_the_cost_model():
    ev = Evaluator(PivotChecker(make_scene()), COSTS)
    e = ev.transfer(A, B, 0)
    assert e.status is Status.VALID and e.valid and e.edge is not None and e.reason == ""
    assert e.cost == COSTS.rotations(r.angle for r in e.edge.sequence.rotations) > 0.0


def test_an_invalid_transfer_carries_its_reason_and_no_cost():
    ev = Evaluator(PivotChecker(make_scene(obstacles=[WALL])), COSTS)
    e = ev.transfer(A, B, 0)
    assert e.status is Status.INVALID and not e.valid
    assert e.cost == math.inf and e.reason


def test_a_stopped_check_is_stopped_not_invalid_and_is_checked_again_later():
    ck = PivotChecker(make_scene(), share=False)  # not answered by another checker's checks
    ev = Evaluator(ck, COSTS)
    assert ev.transfer(A, B, 0, should_stop=lambda: True).status is Status.STOPPED
    assert ev.walk(A, 0, 2, should_stop=lambda: True).status is Status.STOPPED
    assert ck.counters.valid + ck.counters.invalid == 0  # nothing recorded
    assert ev.transfer(A, B, 0).status is Status.VALID
    assert ev.walk(A, 0, 2).status is Status.VALID


def test_a_path_costs_the_sum_of_its_edges_and_answers_its_first_failure():
    scene = make_scene()
    path = [(A, 0), ((3.5, 3.2, 0.3), 0), ((3.5, 3.2, 0.3), 2), (B, 2)]
    stopped = Evaluator(PivotChecker(scene), COSTS).path(path, should_stop=lambda: True)
    assert stopped.status is Status.STOPPED and stopped.cost == math.inf
    ev = Evaluator(PivotChecker(scene), COSTS)
    steps = [ev.step(a, b) for a, b in zip(path, path[1:], strict=False)]
    assert all(s.valid for s in steps)
    assert ev.path(path).cost == sum(s.cost for s in steps)
    assert steps[1].cost == COSTS.regrasp_seconds(steps[1].walk.length)
    # a check known already answers from the cache whatever the stop condition says
    assert ev.path(path, should_stop=lambda: True).cost == ev.path(path).cost
    moved = [(A, 0), (B, 2)]  # a grasp change between two poses is no edge
    assert ev.path(moved).status is Status.INVALID


def test_random_transfers_answer_as_the_checker_does():
    scene = make_scene(obstacles=[dict(WALL, size=[0.3, 2.0]),
                                  dict(WALL, center=[2.0, 1.0], size=[1.0, 0.4])])
    ck = PivotChecker(scene)
    ev = Evaluator(ck, COSTS)
    rng = np.random.default_rng(7)
    seen = set()
    for _ in range(30):
        a = (float(rng.uniform(1, 7)), float(rng.uniform(1, 5)), float(rng.uniform(-3, 3)))
        b = (float(rng.uniform(1, 7)), float(rng.uniform(1, 5)), float(rng.uniform(-3, 3)))
        g = int(rng.integers(4))
        e, edge = ev.transfer(a, b, g), ck.transfer(a, b, g)
        assert e.valid == edge.valid
        assert (e.cost == COSTS.sequence(edge.sequence)) if edge.valid else e.cost == math.inf
        seen.add(e.status)
    assert seen == {Status.VALID, Status.INVALID}


def test_the_box_visibility_says_stopped_when_stopped_not_wall():
    """Regression: a stopped check was taken for a wall (the box not visible)."""
    ck = PivotChecker(make_scene())
    critical = CriticalConfigurations(ck, Roadmap(), grasps=(0, 1, 2, 3), spacing=0.4)
    assert critical.box_visible(A, B, lambda: True) is Status.STOPPED
    assert critical.box_visible(A, B, lambda: False) is Status.VALID


def test_a_sample_whose_visibility_check_is_stopped_becomes_no_guard():
    """Regression: with the stopped check taken for a wall, the sample became a guard."""
    ck = PivotChecker(make_scene(), share=False)  # its checks computed here, so stoppable
    roadmap = Roadmap()
    critical = CriticalConfigurations(ck, roadmap, grasps=(0, 1, 2, 3), spacing=0.4)
    vis = VisibilityRoadmap(roadmap, sample=lambda stop: B, visible=critical.box_visible,
                            candidates=lambda q, guards: list(guards), max_failures=5)
    vis.add_guard(A)
    # the step's own poll passes; the steering's first poll of the check stops it
    assert vis.step(_after(1)) == ("stopped", -1)
    assert len(vis.guards) == 1 and len(roadmap) == 1
    assert vis.step(lambda: False)[0] == "discarded"  # A sees B: B is not a guard


def test_the_lazy_loop_searches_again_until_a_path_stands_and_stops_when_told():
    edges = {"ab": True, "ac": False, "ad": True}
    removed: set[str] = set()
    order = ["ac", "ab", "ad"]  # the cheapest first

    def cheapest() -> Found[str]:
        left = [e for e in order if e not in removed]
        return Found(Status.VALID, left[0]) if left else Found(Status.INVALID)

    def check(e: str) -> Status:
        if not edges[e]:
            removed.add(e)
            return Status.INVALID
        return Status.VALID

    assert lazy_search(cheapest, check, lambda: False) == Found(Status.VALID, "ab")
    assert lazy_search(cheapest, lambda e: Status.STOPPED, lambda: False) == \
        Found(Status.STOPPED)
    assert lazy_search(cheapest, check, lambda: True) == Found(Status.STOPPED)
    removed.update(order)
    assert lazy_search(cheapest, check, lambda: False) == Found(Status.INVALID)

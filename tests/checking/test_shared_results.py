"""Plans of one scene share what depends only on it: values computed once, and the motion
checks (the same answers, counted as computed)."""

from __future__ import annotations

import dataclasses

import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import StoredMotions
from pivot_ompl.scene import BoxObstacle


def _queries(scene):
    """Transfers from the start (some valid, some not) and a walk, at grasp 0."""
    x, y, h = scene.start
    ends = [(x + dx, y + dy, h + dh) for dx, dy, dh in
            [(0.5, 0.0, 0.0), (1.0, 0.3, 0.4), (-0.8, 0.2, -0.3), (3.0, 2.0, 1.0)]]
    return [(scene.start, b, 0) for b in ends]


def _ask(checker, scene):
    edges = [checker.transfer(a, b, g) for a, b, g in _queries(scene)]
    walk = checker.transit(scene.start, 0, 2)
    return edges, walk


def _computed(monkeypatch, checker):
    """The transfers ``checker`` computes itself, from now on."""
    calls = []
    real = checker.transfers.check

    def spy(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(checker.transfers, "check", spy)
    return calls


def _counts(checker):
    c = checker.counters
    return c.valid, c.invalid, c.cache_hits


_made = iter(range(1, 1000))


@pytest.fixture()
def scene():
    """The slot scene, its bounds grown a little: a scene of its own, whatever ran before."""
    s = shipped("slot")
    x0, y0, x1, y1 = s.bounds
    return dataclasses.replace(s, bounds=(x0, y0, x1 + 1e-3 * next(_made), y1))


def test_a_second_checker_of_a_scene_takes_the_first_ones_results(monkeypatch, scene):
    first = PivotChecker(scene)
    edges, walk = _ask(first, scene)
    assert any(e.valid for e in edges) and not all(e.valid for e in edges)
    second = PivotChecker(scene)
    calls = _computed(monkeypatch, second)
    assert _ask(second, scene) == (edges, walk)
    assert calls == []
    # counted as computed: the budgets counting checks, and so the plans, do not change
    assert _counts(second) == _counts(first)
    _ask(second, scene)
    assert _counts(second)[:2] == _counts(first)[:2]
    assert _counts(second)[2] == _counts(first)[2] + len(_queries(scene)) + 1


def test_a_checker_not_sharing_computes_the_same(monkeypatch, scene):
    first = PivotChecker(scene)
    expected = _ask(first, scene)
    alone = PivotChecker(scene, share=False)
    calls = _computed(monkeypatch, alone)
    assert _ask(alone, scene) == expected
    assert len(calls) == len(_queries(scene))
    assert _counts(alone) == _counts(first)


def test_an_offered_checker_keeps_its_results(monkeypatch, scene):
    PivotChecker(scene).transfer(*_queries(scene)[0])
    offered = PivotChecker(scene)
    offered.offer(StoredMotions())
    calls = _computed(monkeypatch, offered)
    offered.transfer(*_queries(scene)[0])
    offered.transfer(*_queries(scene)[1])
    assert len(calls) == 2
    later = PivotChecker(scene)
    calls = _computed(monkeypatch, later)
    later.transfer(*_queries(scene)[1])  # the offered checker's result was not given
    assert len(calls) == 1


def test_another_scene_does_not_take_them(monkeypatch, scene):
    PivotChecker(scene).transfer(*_queries(scene)[0])
    x, y, _ = scene.start
    moved = dataclasses.replace(scene, obstacles=(
        *scene.obstacles, BoxObstacle((x + 2.5, y - 3.0), (0.2, 0.2), 0.0, 1.0)))
    other = PivotChecker(moved)
    calls = _computed(monkeypatch, other)
    other.transfer(*_queries(scene)[0])
    assert len(calls) == 1


def test_a_value_is_computed_once_per_scene_and_a_stopped_one_not_kept(scene):
    from pivot_ompl.scene.shared import scene_shared

    made = []

    def compute(value):
        def f():
            made.append(value)
            return value
        return f

    assert scene_shared(scene, ("test", 1), compute(None)) is None  # stopped: not kept
    value = object()
    assert scene_shared(scene, ("test", 1), compute(value)) is value
    same = dataclasses.replace(scene, name="another name, the same geometry")
    assert scene_shared(same, ("test", 1), compute(object())) is value
    assert scene_shared(scene, ("test", 2), compute(2)) == 2  # another kind: its own
    assert made == [None, value, 2]


def test_a_result_another_checker_knows_answers_even_when_stopped(scene):
    a, b, g = _queries(scene)[0]
    known = PivotChecker(scene).transfer(a, b, g)
    later = PivotChecker(scene)
    assert later.transfer(a, b, g, should_stop=lambda: True) == known  # nothing to compute
    assert later.counters.valid + later.counters.invalid == 1


def test_a_scene_keeps_at_most_results_kept(monkeypatch, scene):
    from pivot_ompl.checking import shared_results as sr

    monkeypatch.setattr(sr, "RESULTS_KEPT", 2)
    checker = PivotChecker(scene)
    for a, b, g in _queries(scene):
        checker.transfer(a, b, g)
        kept = sr.shared_results(scene, tolerance=checker.tolerance,
                                 clearance=checker.world.clearance)
        assert 1 <= len(kept.edges) <= 2
    assert checker.counters.valid + checker.counters.invalid == len(_queries(scene))

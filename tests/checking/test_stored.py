"""A plan file's motions offered to the checker: used only after they pass its checks."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from factories import shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import stored_motions, stored_rotations
from pivot_ompl.planfile import TransferPhase, TransitPhase, plan_from_dict
from pivot_ompl.planners.repair import route_of
from pivot_ompl.scene import BoxObstacle
from pivot_ompl.session import PlanningSession
from pivot_ompl.validity.plan_check import check_plan


@pytest.fixture(scope="module")
def slot_plan():
    scene = shipped("slot")
    res = PlanningSession(scene, seed=0).plan(time_limit=30.0)
    assert res.solved
    plan = plan_from_dict(json.loads(res.plan.to_text()))  # as a new process reads it
    return scene, plan, route_of(plan.extra["route"])


@pytest.fixture(scope="module")
def corridor_plan():
    """A plan whose phases' edges meet with rotations about one corner (merged there)."""
    scene = shipped("corridor")
    res = PlanningSession(scene, seed=0).plan(time_limit=30.0)
    assert res.solved
    plan = plan_from_dict(json.loads(res.plan.to_text()))
    return scene, plan, route_of(plan.extra["route"])


def _refuse(*_args, **_kwargs):
    raise AssertionError("computed again")


def _spy(monkeypatch, obj, name):
    calls = []
    real = getattr(obj, name)

    def spy(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(obj, name, spy)
    return calls


def test_every_route_edge_is_read_with_the_plans_own_motions(slot_plan):
    _, plan, route = slot_plan
    st = stored_motions(plan, route)
    assert len(st) == len(route) - 1 and st.walks
    steps = [(s.pivot, s.angle) for ph in plan.phases if isinstance(ph, TransferPhase)
             for s in ph.steps]
    assert [s for (a, b, g), rot in st.transfers.items() for s in rot] == steps
    walks = [ph.robot_path for ph in plan.phases if isinstance(ph, TransitPhase)]
    assert list(st.walks.values()) == walks


def test_offered_motions_pass_the_checks_and_are_used_without_planning_again(slot_plan,
                                                                             monkeypatch):
    scene, plan, route = slot_plan
    checker = PivotChecker(scene)
    checker.offer(stored_motions(plan, route))
    monkeypatch.setattr(checker.walker, "plan", _refuse)
    monkeypatch.setattr(checker.transfers, "check", _refuse)
    again = path_to_plan(scene, checker, route, extra={})
    assert [ph.type for ph in again.phases] == [ph.type for ph in plan.phases]
    for new, old in zip(again.phases, plan.phases, strict=True):
        if isinstance(new, TransitPhase):
            assert np.allclose(new.robot_path, old.robot_path, rtol=0.0, atol=1e-12)
        else:
            assert [s.angle for s in new.steps] == [s.angle for s in old.steps]
    assert check_plan(again, scene).ok
    assert checker.counters.valid == len(route) - 1


def test_an_obstacle_on_a_stored_walk_or_transfer_rejects_it(slot_plan, monkeypatch):
    scene, plan, route = slot_plan
    st = stored_motions(plan, route)
    (obj, g0, g1), path = next(iter(st.walks.items()))
    mid = path[len(path) // 2]
    (qa, qb, g), rots = next(iter(st.transfers.items()))
    step = next(s for ph in plan.phases if isinstance(ph, TransferPhase)
                for s in ph.steps[len(ph.steps) // 2:])
    blocks = (BoxObstacle((mid[0], mid[1]), (0.05, 0.05), 0.0, 1.0),
              BoxObstacle((step.robot[0], step.robot[1]), (0.05, 0.05), 0.0, 1.0))
    changed = dataclasses.replace(scene, obstacles=scene.obstacles + blocks)
    checker = PivotChecker(changed)
    checker.offer(st)
    planned = _spy(monkeypatch, checker.walker, "plan")
    walk = checker.transit(obj, g0, g1)
    assert len(planned) == 1  # the stored walk failed its check: planned again
    assert walk.robot_path != path
    converted = _spy(monkeypatch, checker.transfers, "check")
    m = changed.model
    refused = []
    for (a, b, gg), rots in st.transfers.items():
        ca, cb = m.car_pose(a, gg), m.car_pose(b, gg)
        given = stored_rotations(m, ca, cb, rots, gg, alpha_max=changed.alpha_max)
        assert given is not None  # the sequence is the edge's, only the scene changed
        if not checker.transfers.check_given(ca, cb, given, gg).valid:
            refused.append((a, b, gg))
        checker.transfer(a, b, gg)
    assert refused  # the block is on a stored transfer: its sweep fails the check
    assert [c[2] for c in converted] == [k[2] for k in refused]  # converted again, those only

def test_stored_rotations_that_are_not_the_edges_pivots_are_refused(slot_plan):
    scene, plan, route = slot_plan
    st = stored_motions(plan, route)
    (qa, qb, g), rots = next(iter(st.transfers.items()))
    m = scene.model
    ca, cb = m.car_pose(qa, g), m.car_pose(qb, g)

    def rebuilt(r):
        return stored_rotations(m, ca, cb, r, g, alpha_max=scene.alpha_max)

    assert rebuilt(rots) is not None
    (px, py), angle = rots[0]
    assert rebuilt((((px + 0.01, py), angle), *rots[1:])) is None  # not a corner
    assert rebuilt((((px, py), angle + 1e-3), *rots[1:])) is None  # ends elsewhere
    assert rebuilt(rots[:-1]) is None  # stops short
    assert stored_rotations(m, ca, cb, rots, g, alpha_max=0.5 * max(
        abs(a) for _, a in rots)) is None  # over the rotation bound


def test_a_rotation_merged_where_two_edges_meet_is_cut_there_when_read(corridor_plan):
    scene, plan, route = corridor_plan
    m, checker = scene.model, PivotChecker(scene)
    edges = [checker.transfer(a, b, g).sequence for (a, g), (b, h) in
             zip(route, route[1:], strict=False) if g == h]
    assert plan.pivots < sum(len(e.rotations) for e in edges)  # merged where edges meet
    assert check_plan(plan, scene).ok
    st = stored_motions(plan, route)
    assert len(st) == len(route) - 1  # every edge read, the merged ones cut in two
    joined: list = []
    for (a, b, g), rots in st.transfers.items():
        given = stored_rotations(m, m.car_pose(a, g), m.car_pose(b, g), rots, g,
                                 alpha_max=scene.alpha_max)
        assert given is not None  # each edge's part chains from its start to its end
        for r in given:
            checker.steering.append_merged(joined, r)
    steps = [s for ph in plan.phases if isinstance(ph, TransferPhase) for s in ph.steps]
    assert len(joined) == len(steps)
    assert np.allclose([r.angle for r in joined], [s.angle for s in steps], rtol=0.0,
                       atol=1e-9)

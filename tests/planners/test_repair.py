"""Local repair of a plan's route from an observed state (seeded slot plan)."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest
from factories import shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planfile import TransferPhase, plan_from_dict
from pivot_ompl.planners.evaluation import Found, Status
from pivot_ompl.planners.repair import join_points, repair_route, route_of
from pivot_ompl.scene import BoxObstacle
from pivot_ompl.session import PlanningSession
from pivot_ompl.validity.plan_check import check_plan


@pytest.fixture(scope="module")
def slot_plan():
    res = PlanningSession(shipped("slot"), seed=0).plan(time_limit=30.0)
    assert res.solved
    return plan_from_dict(json.loads(res.plan.to_text()))  # as a new process reads it


def _drifted(plan, share, metres, degrees):
    steps = [(st.object, ph.grasp) for ph in plan.phases if isinstance(ph, TransferPhase)
             for st in ph.steps]
    q, g = steps[int(share * (len(steps) - 1))]
    c, s = math.cos(q[2]), math.sin(q[2])
    return (q[0] + metres * c, q[1] + metres * s, q[2] + math.radians(degrees)), g


def test_the_route_field_is_the_path_the_plan_was_made_of(slot_plan):
    route = route_of(slot_plan.extra["route"])
    assert route[0][0] == pytest.approx(slot_plan.start)
    assert route[-1][0] == pytest.approx(shipped("slot").goal)
    ck = PivotChecker(shipped("slot"))
    again = path_to_plan(shipped("slot"), ck, route)
    assert again.pivots == slot_plan.pivots and again.regrasps == slot_plan.regrasps
    pts = join_points(ck, route)
    assert [p.along for p in pts] == sorted(p.along for p in pts)


@pytest.mark.parametrize(("share", "metres", "degrees"), [(0.25, 0.05, 5.0), (0.8, 0.15, 15.0),
                                                         (0.3, -0.04, -3.0)])
def test_a_drift_is_repaired_into_a_plan_that_checks_and_arrives_exactly(
        slot_plan, share, metres, degrees):
    box, grasp = _drifted(slot_plan, share, metres, degrees)
    scene = dataclasses.replace(shipped("slot"), start=box)
    ck = PivotChecker(scene)
    assert ck.world.box_distance(box) > 0  # the drift leaves the box free (else no repair)
    rep = repair_route(ck, route_of(slot_plan.extra["route"]), box, grasp).path
    assert rep is not None
    assert rep.states[0] == (box, rep.states[0][1])
    assert rep.states[-1][0] == scene.goal  # the route's own end: exact arrival
    new = path_to_plan(scene, ck, rep.states)
    report = check_plan(new, scene)  # the independent checker, on the observed scene
    assert report.ok, report.problems
    assert new.start == box


def test_a_new_process_replans_by_repair_without_a_search(slot_plan):
    box, grasp = _drifted(slot_plan, 0.5, 0.05, 5.0)
    s = PlanningSession(shipped("slot"), seed=0, executing=slot_plan)
    res = s.replan(box=box, grasp=grasp, time_limit=30.0)
    assert res.solved and res.roadmap["repaired"] and res.search is None
    assert check_plan(res.plan, s.scene).ok
    assert res.plan.start == box and s.scene.start == box
    box, grasp = _drifted(res.plan, 0.5, 0.03, 2.0)
    again = s.replan(box=box, grasp=grasp)  # from its own route
    assert again.roadmap["repaired"] and check_plan(again.plan, s.scene).ok


def test_an_obstacle_on_the_route_ahead_is_never_kept(slot_plan):
    route = route_of(slot_plan.extra["route"])
    (qa, g), (qb, _) = route[-2], route[-1]  # the last transfer edge
    mid = ((qa[0] + qb[0]) / 2, (qa[1] + qb[1]) / 2)
    block = BoxObstacle(mid, (0.3, 0.3), 0.0, 1.0)
    box, grasp = _drifted(slot_plan, 0.2, 0.05, 5.0)
    base = shipped("slot")
    scene = dataclasses.replace(base, start=box, obstacles=base.obstacles + (block,))
    ck = PivotChecker(scene)
    assert not ck.transfer(qa, qb, g).valid  # the change does cut the old route
    rep = repair_route(ck, route, box, grasp, seed=0).path
    if rep is not None:  # a detour round the block, or nothing
        assert check_plan(path_to_plan(scene, ck, rep.states), scene).ok
    s = PlanningSession(base, seed=0, executing=slot_plan)
    res = s.replan(box=box, grasp=grasp, add_obstacles=[block], time_limit=30.0)
    if res.solved:
        assert check_plan(res.plan, s.scene).ok


def test_only_the_edges_a_new_obstacle_touches_are_checked_again(slot_plan):
    """A warm session keeps the route's untouched edges: the repair finds them cached."""
    s = PlanningSession(shipped("slot"), seed=0)
    first = s.plan(time_limit=30.0)
    route = route_of(first.plan.extra["route"])
    far = BoxObstacle((7.7, 4.7), (0.2, 0.2), 0.0, 1.0)  # a corner away from every edge
    box, grasp = _drifted(first.plan, 0.5, 0.05, 5.0)
    old = s.checker
    res = s.replan(box=box, grasp=grasp, add_obstacles=[far], time_limit=30.0)
    assert res.roadmap.get("repaired") and check_plan(res.plan, s.scene).ok
    assert s.checker is not old
    kept = [k for k in old.edges if k in s.checker.edges and old.edges[k].valid]
    edges = [(a[0], b[0], a[1], True) for a, b in zip(route, route[1:], strict=False)
             if a[1] == b[1]]
    assert all(e in kept for e in edges)  # the far obstacle touches none of them
    near = BoxObstacle((5.3, 1.5), (0.2, 0.2), 0.0, 1.0)
    fresh = PivotChecker(s.scene)
    fresh.adopt(s.checker, added=[near])
    assert (route[-2][0], route[-1][0], route[-1][1], True) not in fresh.edges


def test_the_optimiser_keeps_a_held_first_grasp_and_the_last_grasp_of_a_part(slot_plan):
    from pivot_ompl.planners.optimiser import optimise

    route = route_of(slot_plan.extra["route"])
    k = next(i for i in range(len(route) - 1) if route[i][1] != route[i + 1][1])
    ck = PivotChecker(shipped("slot"))
    head = route[:k + 2]  # ends with a walk: useless alone, needed by what follows it
    assert optimise(ck, head, should_stop=lambda: False)[-1] != head[-1]  # dropped alone
    kept = optimise(ck, head, should_stop=lambda: False, end_grasp=head[-1][1])
    assert kept[-1] == head[-1] and kept[0][0] == head[0][0]
    tail = route[k:]  # starts with a walk: the robot holds the box with the grasp before it
    assert optimise(ck, tail, should_stop=lambda: False)[0] != tail[0]  # skipped, unpriced
    held = optimise(ck, tail, should_stop=lambda: False, start_grasp=tail[0][1])
    assert held[0] == tail[0] and held[-1][0] == tail[-1][0]


def test_the_polish_of_a_repair_reworks_its_own_states_and_keeps_the_old_route(slot_plan,
                                                                               monkeypatch):
    from pivot_ompl.planners import improve, repair
    from pivot_ompl.planners.config import RegraspConfig

    box, grasp = _drifted(slot_plan, 0.1, 0.05, 5.0)
    scene = dataclasses.replace(shipped("slot"), start=box)
    ck = PivotChecker(scene)
    assert ck.world.box_distance(box) > 0  # the drift leaves the box free (else no repair)
    rep = repair_route(ck, route_of(slot_plan.extra["route"]), box, grasp).path
    assert rep is not None
    new = len(rep.states) - rep.kept_edges
    seen = []
    real = improve.optimise

    def spy(checker, states, **kw):
        seen.append((list(states), kw["end_grasp"]))
        return real(checker, states, **kw)

    monkeypatch.setattr(improve, "optimise", spy)
    out = repair.polish(ck, rep.states, RegraspConfig(), should_stop=lambda: False, new=new,
                        kept=0)
    # the old route's rest was polished before: the first round reworks the head alone, a
    # later round (improve.ROUNDS) the first's result, ending with the same grasp
    assert seen[0] == (rep.states[:new], rep.states[new - 1][1])
    assert all(end == rep.states[new - 1][1] for _, end in seen)
    tail = rep.states[new - 1:]  # from the head's last state (grasp included) on
    assert out[0] == rep.states[0] and out[-len(tail):] == tail
    assert check_plan(path_to_plan(scene, ck, out), scene).ok


def test_a_stopped_repair_says_so_and_a_box_off_the_floor_finds_no_join(slot_plan):
    box, grasp = _drifted(slot_plan, 0.1, 0.05, 5.0)
    ck = PivotChecker(dataclasses.replace(shipped("slot"), start=box))
    route = route_of(slot_plan.extra["route"])
    assert repair_route(ck, route, box, grasp, should_stop=lambda: True) == \
        Found(Status.STOPPED)
    assert repair_route(ck, route, (4.05, 0.595, 0.0), None) == Found(Status.INVALID)  # wall
    assert repair_route(ck, route, box, grasp).status is Status.VALID

"""Replanning while the robot holds the box: every plan starts with the held grasp."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from factories import shipped

from pivot_ompl.api import plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import InputError, PlanningError
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import load_scene
from pivot_ompl.session import PlanningSession
from pivot_ompl.validity.plan_check import check_plan

#: A generated walls scene with a block dropped on the route ahead (a benchmark point), where
#: the robot holds the box with grasp 2: the block meets the robot there, while the box and
#: another grasp are free (a route from scratch starts with grasp 0).
DROPPED = Path(__file__).parent.parent / "data" / "replan" / "walls_held_grasp_2.yaml"


def _first_grasp(p: Plan) -> int:
    first = p.phases[0]
    return first.from_grasp if isinstance(first, TransitPhase) else first.grasp


#: A box pose in the slot (on a plan's route) where a route from scratch starts with grasp 0,
#: and the robot holding the box with grasp 1, 2 or 3 cannot walk round it to grasp 0.
IN_SLOT = (5.423318141951605, 1.418120927274195, 0.19634954084936096)


def test_in_the_slot_a_route_from_scratch_starts_with_grasp_0_the_others_cannot_walk_to():
    scene = dataclasses.replace(shipped("slot"), start=IN_SLOT)
    scratch = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert scratch.solved and _first_grasp(scratch.plan) == 0
    ck = PivotChecker(scene)
    for held in (1, 2, 3):
        assert ck.state_valid(IN_SLOT, held)
        assert not ck.transit(IN_SLOT, held, 0).valid


@pytest.mark.parametrize("held", [1, 2, 3])
def test_a_replan_holding_grasp_k_starts_with_k_where_a_route_from_scratch_does_not(held):
    scene = dataclasses.replace(shipped("slot"), start=IN_SLOT)
    res = PlanningSession(scene, seed=0, repair=False).replan(box=IN_SLOT, grasp=held,
                                                              time_limit=30.0)
    assert res.solved
    assert _first_grasp(res.plan) == held
    assert check_plan(res.plan, scene).ok


def test_a_held_grasp_the_dropped_block_meets_is_reported_as_such():
    scene = load_scene(DROPPED)
    ck = PivotChecker(scene)
    assert ck.box_valid(scene.start) and ck.state_valid(scene.start, 0)
    assert not ck.state_valid(scene.start, 2)
    s = PlanningSession(scene, seed=0, repair=False)
    with pytest.raises(PlanningError, match="held grasp 2 is not valid at start"):
        s.replan(box=scene.start, grasp=2, time_limit=30.0)


def test_start_grasp_must_be_a_grasp_index():
    with pytest.raises(InputError, match="start_grasp"):
        plan(shipped("slot"), time_limit=5.0, start_grasp=7, bound=False)


@pytest.mark.parametrize("name", ["slot", "fig10"])
def test_every_plan_from_a_held_grasp_starts_with_it(name):
    scene = shipped(name)
    ck = PivotChecker(scene)
    for g in (g for g in range(4) if ck.state_valid(scene.start, g)):
        res = plan(scene, time_limit=30.0, seed=0, start_grasp=g, bound=False)
        assert res.solved, g
        assert _first_grasp(res.plan) == g
        assert check_plan(res.plan, scene).ok


def test_every_replan_holding_the_box_starts_with_the_held_grasp():
    s = PlanningSession(shipped("slot"), seed=0)
    first = s.plan(time_limit=30.0)
    assert first.solved
    steps = [(st.object, ph.grasp) for ph in first.plan.phases
             if isinstance(ph, TransferPhase) for st in ph.steps]
    for q, g in steps[len(steps) // 4::len(steps) // 3]:
        for held in (g, (g + 1) % 4):  # the route's grasp, and one the route does not use
            box = (q[0] + 0.04, q[1] - 0.03, q[2] + 0.06)
            if not PivotChecker(s.scene).state_valid(box, held):
                continue
            res = s.replan(box=box, grasp=held, time_limit=30.0)
            assert res.solved
            assert _first_grasp(res.plan) == held
            assert check_plan(res.plan, s.scene).ok

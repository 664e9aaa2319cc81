"""``check`` against an independent shapely model on random and mutated plans (issue 43, class 1).

The model (``plan_model.py``) carries its own pose chain from the scene's start and sweeps
every rotation and walk densely with shapely. Where it is sure (outside the check's stated
tolerances) the check must agree: random plans, slides (zero-angle steps whose written
poses drift below the pose tolerance each), teleports (a written pose moved, the chain going
on from it), swings (a walk turning in place between two walls) and grazes (an obstacle just
off or just into the bodies' outline).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from plan_model import KINDS, model_verdict, random_case

from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.validity.plan_check import check_plan


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(seed=st.integers(0, 2**32 - 1))
def test_check_agrees_with_the_shapely_model(kind, seed):
    case = random_case(seed, kind)
    if case is None:
        return
    plan, scene = case
    verdict = model_verdict(plan, scene)
    rep = check_plan(plan, scene)
    if verdict == "valid":
        assert rep.ok, rep.problems[:3]
    elif verdict == "invalid":
        assert not rep.ok


def _slide_plan(n: int, drift: float):
    from factories import make_scene

    scene = make_scene(start=[2.0, 3.0, 0.0], goal=[2.0 + n * drift, 3.0, 0.0])
    m = scene.model
    steps, q = [], scene.start
    for _ in range(n):
        q = (q[0] + drift, q[1], q[2])
        steps.append(TransferStep(m.pivots(m.car_pose(q, 0), 0)[0], 0.0, q, m.robot_pose(q, 0)))
    phase = TransferPhase(0, m.robot_pose(scene.start, 0), tuple(steps), scene.start, ())
    return Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, scene.start, [phase], {}), scene


def test_a_slide_of_tiny_steps_is_refused():
    """5600 zero-angle steps, each 0.9 um: the written box slides 5 mm, the rotations not."""
    plan, scene = _slide_plan(5600, 0.9e-6)
    rep = check_plan(plan, scene)
    assert not rep.ok
    assert any("not at the scene's goal" in p or "rotation's result" in p for p in rep.problems)


def test_a_turn_in_place_between_two_walls_is_refused():
    """Both ends of the turn fit on the floor; the body swings out of it mid-turn."""
    from factories import make_scene

    probe = make_scene()
    m = probe.model
    obj = (4.0, 3.0, 0.0)
    r = m.robot_pose(obj, 0)
    back = (r[0] - 0.6, r[1], r[2])
    turned = (back[0], back[1], back[2] + math.pi / 2)
    corners = [*m.robot_corners(back), *m.robot_corners(turned)]
    x0, y0 = min(x for x, _ in corners) + 1e-3, min(y for _, y in corners) + 1e-3
    scene = make_scene(bounds=[x0 - 2e-3, y0 - 2e-3, x0 + 8.0, y0 + 6.0], start=list(obj),
                       goal=list(obj))
    walk = TransitPhase(0, 0, (r, back, turned, back, r), obj)
    plan = Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, obj, [walk], {})
    assert model_verdict(plan, scene) == "invalid"
    rep = check_plan(plan, scene)
    assert any("leaves the bounds" in p for p in rep.problems), rep.problems

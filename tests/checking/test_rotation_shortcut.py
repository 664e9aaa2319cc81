"""A phase's rotations shortened: fewer, within the bound, chained, checked, same end."""

from __future__ import annotations

import json
import math

import pytest
from factories import make_scene, shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.rotation_shortcut import shorten
from pivot_ompl.checking.stored import stored_motions, stored_rotations
from pivot_ompl.pivoting.kinematics import ANGLE_TOL
from pivot_ompl.pivoting.transfer import phase_rotations
from pivot_ompl.planfile import TransferPhase, plan_from_dict
from pivot_ompl.planners.repair import route_of
from pivot_ompl.se2 import rotate_about, wrap_angle
from pivot_ompl.session import PlanningSession
from pivot_ompl.validity.plan_check import check_plan


def _chained(start, rotations, model, grasp, alpha_max):
    """Whether each rotation turns about a corner of the car before it, within the bound."""
    car = start
    for r in rotations:
        ends = model.pivots(car, grasp)
        if min(math.dist(ends[e], r.pivot) for e in (0, 1)) > 1e-9 or \
                abs(r.angle) > alpha_max + ANGLE_TOL:
            return False
        nxt = rotate_about(car, r.pivot, r.angle)
        if math.dist(nxt[:2], r.car[:2]) > 1e-9 or abs(wrap_angle(nxt[2] - r.car[2])) > 1e-9:
            return False
        car = r.car
    return True


def test_a_push_then_a_turn_in_place_takes_fewer_rotations_and_ends_where_it_did():
    scene = make_scene(bounds=[0.0, 0.0, 12.0, 12.0], start=[3.0, 6.0, 0.0],
                       goal=[9.0, 6.0, 0.0])
    checker = PivotChecker(scene, share=False)
    m, g = scene.model, 0
    a, b = (3.0, 6.0, 0.0), (4.0, 6.0, 0.0)
    turned = m.object_from_car(_spun(m.car_pose(b, g)), g)
    seqs = [checker.transfer(a, b, g).sequence, checker.transfer(b, turned, g).sequence]
    rots = phase_rotations(checker.steering, seqs)
    start = m.car_pose(a, g)
    short = shorten(checker.transfers.sweeps, start, rots, g,
                    half_length=m.edge_half_length(g), alpha_max=scene.alpha_max)
    assert len(short) < len(rots)
    assert short[-1].car == rots[-1].car  # exactly where the phase ended
    assert _chained(start, short, m, g, scene.alpha_max)


def test_no_run_is_replaced_where_the_checks_refuse_its_replacement(monkeypatch):
    scene = make_scene(bounds=[0.0, 0.0, 12.0, 12.0], start=[3.0, 6.0, 0.0],
                       goal=[9.0, 6.0, 0.0])
    checker = PivotChecker(scene, share=False)
    m, g = scene.model, 0
    a, b = (3.0, 6.0, 0.0), (4.0, 6.0, 0.0)
    turned = m.object_from_car(_spun(m.car_pose(b, g)), g)
    seqs = [checker.transfer(a, b, g).sequence, checker.transfer(b, turned, g).sequence]
    rots = phase_rotations(checker.steering, seqs)
    sweeps = checker.transfers.sweeps
    calls = []

    def refuse(prev, rotations, *args):
        calls.append(rotations)
        return "box collides", (args[2], args[3])

    monkeypatch.setattr(sweeps, "rotations", refuse)
    short = shorten(sweeps, m.car_pose(a, g), rots, g, half_length=m.edge_half_length(g),
                    alpha_max=scene.alpha_max)
    assert calls and short == rots


def test_an_arcs_three_rotation_pieces_are_joined_two_by_two():
    """A quarter turn on an arc: pieces of three (L, R, L) become runs alternating corners.

    The arc's rotations alternate in sign, so a replacement's leading rotations must take
    either sign (a grid turning only the way the window turns saves one rotation here).
    """
    scene = make_scene(bounds=[0.0, 0.0, 14.0, 14.0], start=[3.0, 6.0, 0.0],
                       goal=[9.0, 6.0, 0.0])
    checker = PivotChecker(scene, share=False)
    m, g = scene.model, 0
    a, b = (3.0, 6.0, 0.0), (5.0, 8.0, math.pi / 2)
    rots = phase_rotations(checker.steering, [checker.transfer(a, b, g).sequence])
    start = m.car_pose(a, g)
    short = shorten(checker.transfers.sweeps, start, rots, g,
                    half_length=m.edge_half_length(g), alpha_max=scene.alpha_max)
    assert len(short) <= 0.85 * len(rots)  # 39 -> 32
    assert short[-1].car == rots[-1].car
    assert _chained(start, short, m, g, scene.alpha_max)


def _spun(car):
    return (car[0], car[1], car[2] + math.pi)


@pytest.fixture(scope="module")
def t_junction_plan():
    scene = shipped("t_junction")
    res = PlanningSession(scene, seed=0).plan(time_limit=30.0)
    assert res.solved
    plan = plan_from_dict(json.loads(res.plan.to_text()))
    return scene, plan, route_of(plan.extra["route"])


def test_shortened_plans_pass_the_check_with_fewer_pivots_past_the_slot(t_junction_plan):
    scene, plan, route = t_junction_plan
    long = path_to_plan(scene, PivotChecker(scene, share=False), route, shortcut=False)
    assert check_plan(plan, scene).ok
    assert plan.pivots < long.pivots
    for short, full in zip(plan.phases, long.phases, strict=True):
        if isinstance(full, TransferPhase):
            assert len(short.steps) <= len(full.steps)
            assert short.object_end == full.object_end


def test_a_shortened_plans_motions_are_read_past_a_state_it_no_longer_passes(
        t_junction_plan):
    scene, plan, route = t_junction_plan
    st = stored_motions(plan, route)
    transfers = sum(1 for a, b in zip(route, route[1:], strict=False) if a[1] == b[1])
    assert len(st.transfers) < transfers  # some states are passed inside a replaced run
    assert len(st.walks) == plan.regrasps >= 1  # and reading went on past them
    m = scene.model
    for (a, b, g), steps in st.transfers.items():
        assert stored_rotations(m, m.car_pose(a, g), m.car_pose(b, g), steps, g,
                                alpha_max=scene.alpha_max) is not None


def test_a_shortened_phase_is_a_fixed_point(t_junction_plan):
    """Shortening the shortened rotations again replaces nothing (one pass is not enough)."""
    scene, _plan, route = t_junction_plan
    checker = PivotChecker(scene, share=False)
    m = scene.model
    phases, i = [], 0
    while i < len(route) - 1:
        g, j, seqs = route[i][1], i, []
        while j < len(route) - 1 and route[j + 1][1] == g:
            seqs.append(checker.transfer(route[j][0], route[j + 1][0], g).sequence)
            j += 1
        if seqs:
            phases.append((m.car_pose(route[i][0], g), phase_rotations(checker.steering, seqs), g))
        i = max(j, i + 1)
    assert len(phases) == 2
    for start, rots, g in phases:
        kw = {"half_length": m.edge_half_length(g), "alpha_max": scene.alpha_max}
        once = shorten(checker.transfers.sweeps, start, rots, g, **kw)
        assert len(once) < len(rots)
        assert shorten(checker.transfers.sweeps, start, once, g, **kw) == once

"""Physics in the loop: the short plan's motion simulated, open and closed loop."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

pytest.importorskip("mujoco")

from pivot_ompl.errors import InputError  # noqa: E402
from pivot_ompl.physics import LoopSettings, simulate  # noqa: E402
from pivot_ompl.physics.report import SLIP_LIMIT  # noqa: E402
from pivot_ompl.planfile import load_plan  # noqa: E402


@pytest.fixture(scope="module")
def nominal(short_run):
    scene, plan_file, motion_file = short_run
    return simulate(plan_file, motion_file, scene=scene)


def test_open_loop_tracks_the_plan(nominal, short_run):
    r = nominal
    assert r.status == "done" and r.reached_goal
    assert r.box_error_max_m <= 0.02
    assert r.box_yaw_error_max_rad <= math.radians(2.0)
    assert r.box_error_final_m <= 0.01
    assert r.goal_error_m <= 0.01
    assert r.replans == []
    assert len(r.pivots) == load_plan(short_run[1]).pivots
    assert r.obstacle_contacts == []


def test_errors_are_those_of_the_trace(nominal):
    a = nominal.trace
    err = np.linalg.norm(a["sim_pos"] - a["plan_pos"], axis=1)
    assert nominal.box_error_max_m == pytest.approx(err.max())
    assert nominal.box_error_final_m == pytest.approx(err[-1])
    assert np.all(np.diff(a["t"]) > 0)
    assert nominal.simulated_s == pytest.approx(a["t"][-1], abs=0.01)


def test_the_floor_carries_the_box_and_the_hands_move_it(nominal):
    weight = nominal.box_mass * 9.81
    for p in nominal.pivots:
        assert 0.3 * weight <= p.normal_max <= 3.0 * weight
        assert 0.0 < p.friction_median <= p.friction_peak
    assert 0.0 < max(nominal.hand_force_peak_n) < 3.0 * weight


@pytest.mark.parametrize("mu", [0.2, 0.8])
def test_the_corner_force_stays_in_the_friction_cone(short_run, mu):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, friction=mu)
    assert r.friction == mu
    for p in r.pivots:
        assert p.friction == mu
        assert p.friction_peak <= mu * 1.001


def test_a_friction_patch_sets_the_pivots_friction(short_run):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, friction=0.5,
                 perturb=["patch:0,0,10,0.3"])
    assert {p.friction for p in r.pivots} == {0.3}
    assert max(p.friction_peak for p in r.pivots) <= 0.3 * 1.001


def test_a_slip_makes_the_box_drift_and_the_open_loop_miss(short_run, nominal):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, perturb=["slip@1:0.06,0.0"])
    assert r.status == "goal_missed" and not r.reached_goal
    assert r.box_error_final_m > 0.03
    assert r.pivots[1].slip is not None and r.pivots[1].corner_slip > SLIP_LIMIT
    assert r.slipping_pivots >= 1 > nominal.slipping_pivots


def test_the_closed_loop_replans_to_the_goal(short_run):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, perturb=["slip@1:0.06,0.0"],
                 replan=True)
    assert r.status == "done" and r.reached_goal
    assert r.goal_error_m <= LoopSettings().goal_tolerance_m
    assert len(r.replans) >= 1
    first = r.replans[0]
    assert first.error_m > LoopSettings().threshold_m
    assert 0.0 < first.time < r.simulated_s
    assert first.pivots >= 1


def test_random_slips_are_drawn_from_the_seed(short_run):
    scene, plan_file, motion_file = short_run
    a = simulate(plan_file, motion_file, scene=scene, perturb=["slip:2"], seed=7)
    b = simulate(plan_file, motion_file, scene=scene, perturb=["slip:2"], seed=7)
    assert [p.slip for p in a.pivots] == [p.slip for p in b.pivots]
    assert sum(p.slip is not None for p in a.pivots) == 2
    assert a.box_error_max_m == b.box_error_max_m


def test_an_obstacle_on_the_route_is_touched(short_run):
    import dataclasses

    from pivot_ompl.scene import BoxObstacle

    scene, plan_file, motion_file = short_run
    block = BoxObstacle((0.75, 0.0), (0.3, 1.0), 0.0, 0.5)
    blocked = dataclasses.replace(scene, obstacles=(*scene.obstacles, block))
    r = simulate(plan_file, motion_file, scene=blocked)
    assert r.obstacle_contacts
    assert {c["obstacle"] for c in r.obstacle_contacts} == {len(scene.obstacles)}
    for c in r.obstacle_contacts:
        assert c["start"] <= c["end"] and c["depth_m"] >= 0.0
    starts = [c["start"] for c in r.obstacle_contacts]
    assert starts == sorted(starts)


def test_report_json(nominal, tmp_path):
    path = nominal.to_json(tmp_path / "r.json")
    doc = json.loads(path.read_text())
    for key in ("box_error_max_m", "box_error_final_m", "box_yaw_error_max_rad",
                "reached_goal", "replans", "pivots", "hand_force_peak_n",
                "obstacle_contacts", "friction"):
        assert key in doc
    assert doc["format"] == "pivot-physics/1"
    assert "trace" not in doc
    assert doc["pivots"][0]["slipped"] in (True, False)


def test_time_limit_stops_the_run(short_run):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, time_limit=1e-3)
    assert r.status == "time_limit" and not r.reached_goal
    assert r.simulated_s < 21.0


@pytest.mark.parametrize(("kw", "field"), [
    ({"friction": 0.0}, "friction"), ({"friction": math.nan}, "friction"),
    ({"box_mass": -1.0}, "box_mass"), ({"box_mass": 1e6}, "box_mass"),
    ({"perturb": ["mass:0,0,5"]}, "com_offset[2]"), ({"perturb": ["wobble"]}, "--perturb"),
    ({"perturb": ["slip@x:1,2"]}, "--perturb"), ({"perturb": ["patch:0,0,-1,0.5"]}, "--perturb"),
    ({"seed": -1}, "seed"), ({"time_limit": 0.0}, "time_limit"),
])
def test_bad_inputs_name_their_field(short_run, kw, field):
    scene, plan_file, motion_file = short_run
    with pytest.raises(InputError) as e:
        simulate(plan_file, motion_file, scene=scene, **kw)
    assert e.value.field == field


def test_missing_mujoco_is_an_input_error(monkeypatch, short_run):
    import sys

    from pivot_ompl.physics.backend import mujoco

    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(InputError, match="physics"):
        mujoco()


def test_no_replan_budget_ends_the_run_exhausted(short_run):
    scene, plan_file, motion_file = short_run
    r = simulate(plan_file, motion_file, scene=scene, perturb=["slip@1:0.06,0.0"],
                 replan=True, settings=LoopSettings(max_replans=0))
    assert r.status == "replans_exhausted" and not r.reached_goal and r.replans == []

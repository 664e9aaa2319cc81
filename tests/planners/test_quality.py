"""The plan's ``quality`` block: figures computed from the plan, optional in the file."""

from __future__ import annotations

import json
import math

import pytest
from factories import make_scene

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.cost import DurationModel
from pivot_ompl.planfile import load_plan, plan_from_dict
from pivot_ompl.quality import plan_quality

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


@pytest.fixture(scope="module")
def push():
    """A 4 m straight push at grasp 0 (l = 0.3 m) and a regrasp, checked by the checker."""
    a, b = (1.5, 3.0, 0.0), (5.5, 3.0, 0.0)
    scene = make_scene(start=list(a), goal=list(b))
    ck = make_problem(scene).checker
    return scene, path_to_plan(scene, ck, [(a, 0), (b, 0), (b, 2)])


def test_quality_of_a_straight_push(push):
    scene, plan = push
    q = plan_quality(plan, regrasps_lower_bound=0)
    assert q["pivots"] == plan.pivots and q["regrasps"] == 1 == plan.regrasps
    assert q["transfer_length"] == pytest.approx(4.0, rel=0.02)
    ideal = 1.0 / (2 * 0.3 * math.sin(scene.alpha_max / 2))
    assert q["ideal_pivots_per_m"] == pytest.approx(ideal)
    # longest pieces: the push runs at the ideal rate (two half rotations at the ends)
    assert ideal <= q["pivots_per_m"] <= 1.05 * ideal + 2 / 4.0
    assert q["walking_length"] == pytest.approx(plan.phases[1].length)
    d = DurationModel()
    turned = sum(abs(s.angle) for s in plan.phases[0].steps)
    assert q["duration_estimate"] == pytest.approx(
        d.per_transfer + d.per_pivot * plan.pivots + d.per_radian * turned
        + d.per_transit + d.per_walk_m * q["walking_length"])
    assert q["regrasps_lower_bound"] == 0


def test_quality_is_an_optional_extra_field(push, tmp_path):
    _scene, plan = push
    plan.extra["quality"] = plan_quality(plan)
    path = plan.to_json(tmp_path / "p.json")
    back = load_plan(path)
    assert back.extra["quality"] == json.loads(path.read_text())["quality"]
    assert back.extra["quality"]["pivots"] == plan.pivots
    doc = json.loads(path.read_text())
    del doc["quality"]  # plans written before the block still load
    old = plan_from_dict(doc)
    assert "quality" not in old.extra and old.pivots == plan.pivots
    assert plan_quality(old) == plan_quality(plan)


def test_plan_writes_the_quality_block():
    from pivot_ompl.api import plan

    res = plan(make_scene(), planner="regrasp", time_limit=20.0, seed=0)
    assert res.solved
    q = res.plan.extra["quality"]
    computed = plan_quality(res.plan, regrasps_lower_bound=q["regrasps_lower_bound"],
                            shortest_route=q["shortest_route"])
    assert {k: q[k] for k in computed} == computed  # and the explanations (docs/quality.md)
    assert set(q) - set(computed) == {"pivot_rate_ratio", "regrasps_unforced",
                                      "regrasp_reasons"}
    assert q["pivots"] == res.pivots > 0 and q["pivots_per_m"] > 0
    # the lower bound on regrasps (open floor: none needed), within the plan's time
    assert q["regrasps_lower_bound"] == 0 <= res.regrasps
    assert 0 < res.timings["bound"] < 20.0

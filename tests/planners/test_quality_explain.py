"""The quality block's explanations: each regrasp's forcing passage or "not forced", the rate."""

from __future__ import annotations

import json

import pytest
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.api import plan
from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.planfile import load_plan
from pivot_ompl.planners.explain import (
    explain_lines,
    explain_plan,
    regrasp_reasons,
    unforced_regrasps,
)
from pivot_ompl.quality import plan_quality

START, MID, GOAL = (1.5, 3.0, 0.0), (3.5, 3.4, 0.2), (6.0, 3.0, 0.0)


@pytest.fixture(scope="module")
def needless():
    """An open-floor plan with a regrasp nothing forces."""
    scene = make_scene(start=list(START), goal=list(GOAL), bounds=[-1.0, 0.0, 8.0, 6.0])
    ck = make_problem(scene).checker
    return scene, ck, path_to_plan(scene, ck, [(START, 0), (MID, 0), (MID, 2), (GOAL, 2)])


def test_a_needless_regrasp_is_reported_not_forced(needless):
    scene, ck, p = needless
    reasons = regrasp_reasons(p, ck)
    assert len(reasons) == 1 == p.regrasps
    r = reasons[0]
    assert (r["from_grasp"], r["to_grasp"]) == (0, 2) and not r["forced"]
    assert r["passage"] is None and r["pose"] == pytest.approx(list(MID))
    q = plan_quality(p, regrasps_lower_bound=0)
    extra = explain_plan(p, scene, q, checker=ck)
    assert extra["regrasps_unforced"] == 1
    assert extra["pivot_rate_ratio"] == pytest.approx(q["pivots_per_m"]
                                                      / q["ideal_pivots_per_m"])
    assert any(line.endswith("not forced") for line in explain_lines({**q, **extra}))


def test_the_slot_regrasp_is_forced_by_the_wall_and_written_to_the_file(tmp_path):
    scene = shipped("slot")
    res = plan(scene, planner="regrasp", time_limit=60.0, seed=0)
    assert res.solved and res.regrasps == 1
    q = res.plan.extra["quality"]
    (r,) = q["regrasp_reasons"]
    assert r["forced"] and q["regrasps_unforced"] == 0
    assert set(r["passage"]["obstacles"]) & {0, 1}  # the slot's walls
    assert 1.0 <= q["pivot_rate_ratio"] < 3.0
    path = res.plan.to_json(tmp_path / "slot.json")
    back = load_plan(path).extra["quality"]
    assert back["regrasp_reasons"] == json.loads(json.dumps(q["regrasp_reasons"]))
    assert any("forced by the passage" in line for line in explain_lines(back))
    # a bound cut short (0, as a large map's coarse bound) refutes no passage: still forced
    coarse = explain_plan(res.plan, scene, {**q, "regrasps_lower_bound": 0})
    assert coarse["regrasps_unforced"] == 0


@settings(max_examples=200, deadline=None)
@given(forced=hs.lists(hs.booleans(), max_size=8), data=hs.data())
def test_a_regrasp_is_unforced_only_without_a_passage_and_beyond_the_bound(forced, data):
    reasons = [{"forced": f} for f in forced]
    n, without = len(forced), forced.count(False)
    bound = data.draw(hs.none() | hs.integers(0, n))
    got = unforced_regrasps(reasons, lower_bound=bound)
    assert 0 <= got <= without  # a regrasp its passage forces is never counted
    if bound is None:
        assert got == without
    else:
        assert got <= n - bound  # the bound forces that many at least
        # each regrasp the bound forces beyond the passages' count leaves the count by one
        assert got == without - max(0, bound - (n - without))


def test_a_plan_without_regrasps_explains_no_regrasp():
    scene = make_scene()
    res = plan(scene, planner="regrasp", time_limit=30.0, seed=0)
    q = res.plan.extra["quality"]
    assert res.regrasps == 0 and q["regrasp_reasons"] == [] and q["regrasps_unforced"] == 0


def test_a_passages_obstacles_are_every_obstacle_within_near_of_the_assembly():
    """Among hundreds of obstacles round the passage: exactly those within NEAR, ascending."""
    import dataclasses

    import numpy as np
    import shapely

    from pivot_ompl.checking.pivot_checker import PivotChecker
    from pivot_ompl.planners.explain import NEAR
    from pivot_ompl.scene.model import BoxObstacle, CylinderObstacle
    from pivot_ompl.se2 import rectangle_corners
    from pivot_ompl.validity.footprints import obstacle_footprint

    scene = shipped("slot")
    res = plan(scene, planner="regrasp", time_limit=60.0, seed=0)
    (r,) = res.plan.extra["quality"]["regrasp_reasons"]
    px, py, _ = r["passage"]["pose"]
    rng = np.random.default_rng(0)
    extra = [BoxObstacle(center=(px + dx, py + dy), size=(0.05, 0.05), yaw=float(a), height=1.0)
             for dx, dy, a in rng.uniform([-2.0, -2.0, 0.0], [2.0, 2.0, 3.0], (300, 3))]
    extra += [CylinderObstacle(center=(px + dx, py + dy), radius=0.03, height=1.0)
              for dx, dy in rng.uniform(-2.0, 2.0, (100, 2))]
    crowded = dataclasses.replace(scene, obstacles=[*scene.obstacles, *extra])
    ck = PivotChecker(crowded)
    reasons = regrasp_reasons(res.plan, ck)
    assert reasons[0]["forced"]
    q = reasons[0]["passage"]["pose"]
    g = reasons[0]["from_grasp"]
    m = crowded.model
    body = shapely.union_all([shapely.Polygon(rectangle_corners(tuple(q), *m.object_size[:2])),
                              shapely.Polygon(rectangle_corners(m.robot_pose(tuple(q), g),
                                                                *m.robot_footprint))])
    want = [i for i, o in enumerate(crowded.obstacles)
            if body.distance(obstacle_footprint(o)) <= NEAR]
    added = [i for i in want if i >= len(scene.obstacles)]
    assert len(added) >= 5 and len(want) < len(crowded.obstacles) // 4, (len(added), len(want))
    assert reasons[0]["passage"]["obstacles"] == want

"""``pivot_ompl.plan`` arguments: wrong types and values are InputError; huge limits are real."""

from __future__ import annotations

import math
import re

import pytest
from factories import make_scene, shipped

import pivot_ompl
from pivot_ompl.api import MAX_SEED, MAX_TIME_LIMIT
from pivot_ompl.errors import InputError
from pivot_ompl.planners import PLANNERS


@pytest.mark.parametrize("scene, kwargs, field", [
    ("open", {"time_limit": "5"}, "time_limit"),
    ("open", {"time_limit": math.nan}, "time_limit"),
    ("open", {"time_limit": 0}, "time_limit"),
    ("open", {"time_limit": True}, "time_limit"),
    (None, {}, "scene"),
    ({}, {}, "scene"),
    (42, {}, "scene"),
    ("open", {"planner": None}, "planner"),
    ("open", {"planner": "nosuch"}, "planner"),
    ("open", {"seed": -1}, "seed"),
    ("open", {"seed": 2**64}, "seed"),
    ("open", {"seed": 1.0}, "seed"),
    ("open", {"simplify": "yes"}, "simplify"),
])
def test_bad_arguments_are_input_errors(scene, kwargs, field):
    with pytest.raises(InputError) as e:
        pivot_ompl.plan(scene, **kwargs)
    assert e.value.field == field


def test_largest_seed_works_with_ompl_planners():
    res = pivot_ompl.plan("open", planner="rrtconnect", seed=MAX_SEED, time_limit=5.0)
    assert res.solved


@pytest.mark.parametrize("limit", [math.inf, 1e10])
def test_huge_time_limit_is_a_real_limit(limit):
    res = pivot_ompl.plan(shipped("open"), planner="rrtconnect", time_limit=limit)
    assert res.status == "EXACT_SOLUTION" and res.time_limit == MAX_TIME_LIMIT


def test_goal_yaw_of_two_pi_is_the_same_pose():
    scene = make_scene(start=[1.5, 3.0, 0.0], goal=[5.0, 3.0, 2 * math.pi])
    res = pivot_ompl.plan(scene, planner="rrtconnect", time_limit=10.0)
    assert res.solved
    assert res.plan.object_end == pytest.approx((5.0, 3.0, 0.0), abs=1e-6)


def test_docstring_names_only_known_planners():
    doc = pivot_ompl.plan.__doc__ or ""
    named = set(re.findall(r'``"(\w+)"``', doc.split("planner:")[1].split("time_limit:")[0]))
    assert named and named <= set(PLANNERS)

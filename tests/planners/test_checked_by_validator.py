"""Plans the independent validator (``check_plan``) accepts, where one once failed it."""

from __future__ import annotations

import pytest

from pivot_ompl.api import plan
from pivot_ompl.generate import generate, mirror_scene
from pivot_ompl.validity.plan_check import check_plan


@pytest.mark.slow
def test_the_mirrored_walls_plan_passes_the_validator():
    # regression: ``gen:walls:1`` reflected in the line at 0.3 rad: two rotations about one
    # corner, each passed by the sweep check's tolerance while its box dipped 50 micrometres
    # into the kept 1 cm of a wall between two samples, were written as one pivot, and the
    # validator's sampling of it fell on the dip ("phases[0].steps[39]: box collides")
    inner = generate("walls", 1).scene
    scene = mirror_scene(inner, 0.3, name=f"{inner.name}_mirror")
    res = plan(scene, planner="regrasp", time_limit=30.0, seed=0)
    assert res.solved
    rep = check_plan(res.plan, scene)
    assert rep.ok, rep.problems[:3]
    assert rep.steps > 40

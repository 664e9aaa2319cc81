"""The demo's plan (fig10, seed 0) animates with every link and the box clear of obstacles."""

from __future__ import annotations

import pytest

from pivot_ompl.api import plan
from pivot_ompl.scene import load_scene
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.motion_checks import check_motion


@pytest.mark.slow
def test_fig10_demo_motion_keeps_every_link_clear():
    scene = load_scene("fig10")
    res = plan(scene, planner="regrasp", time_limit=60.0, seed=0)
    assert res.solved
    motion, _ = generate_motion(res.plan)
    report = check_motion(motion, res.plan, scene=scene)
    assert report.passed, report.table()
    cl = report.clearance
    assert cl is not None and cl.worst is not None and cl.worst.clearance >= 0.01
    assert len(cl.per_link()) == 32  # 31 links with collision geometry and the box

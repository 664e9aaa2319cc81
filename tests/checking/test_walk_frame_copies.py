"""The walk planner's frame is turned to the walls facing the free floor, as the lattice's is.

A turned or mirrored copy keeps its old floor as long walls round it; counted with the inner
walls, their edges set the direction of all the walls. The only walk round the resting box
in ``walls_2_narrow_walk.yaml`` passes a wall with 0.83 mm beyond the kept centimetre: a walk
lattice turned 0.015 rad off that wall finds no such walk, and the copies had no plan.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from pivot_ompl import plan
from pivot_ompl.analysis.wall_frame import facing_yaw
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import mirror_scene, rotate_scene
from pivot_ompl.scene import load_scene
from pivot_ompl.scene.walls import wall_yaw
from pivot_ompl.validity.plan_check import check_plan

LAYOUT = Path(__file__).parents[1] / "data" / "scenes" / "walls_2_narrow_walk.yaml"


def _quarter(a: float) -> float:
    return (a + 0.25 * math.pi) % (0.5 * math.pi) - 0.25 * math.pi


def _copies():  # noqa: ANN202
    scene = load_scene(LAYOUT)
    return scene, {"turned": rotate_scene(scene, 2.0), "mirrored": mirror_scene(scene, 0.3)}


@pytest.mark.parametrize("kind", ["turned", "mirrored"])
def test_the_walk_frame_of_a_copy_follows_its_inner_walls(kind):
    scene, copies = _copies()
    copy = copies[kind]
    own = wall_yaw(scene.obstacles)  # a reflection in the line at 0.3 rad: a -> 0.6 - a
    inner = _quarter(own + 2.0 if kind == "turned" else 0.6 - own)
    assert abs(_quarter(facing_yaw(copy) - inner)) < 1e-6
    assert abs(_quarter(wall_yaw(copy.obstacles) - inner)) > 0.01  # the old floor's walls
    frame = PivotChecker(copy).walker.frame
    assert abs(_quarter(frame.yaw - inner)) < 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["turned", "mirrored"])
def test_a_copy_of_the_narrow_walk_layout_keeps_its_plan(kind):
    _, copies = _copies()
    copy = copies[kind]
    res = plan(copy, time_limit=30.0, seed=0)
    assert res.solved and res.plan.regrasps == 1
    assert check_plan(res.plan, copy).ok

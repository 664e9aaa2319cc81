"""The lower bound on regrasps: sound (never above a valid plan's regrasps) and not empty."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from factories import make_scene, shipped

from pivot_ompl.analysis.regrasp_bound import free_cover, regrasp_lower_bound
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import generate, mirror_scene, rotate_scene
from pivot_ompl.scene import BoxObstacle, Scene

GOLDEN = Path(__file__).parents[1] / "data" / "golden" / "seeded_plans.json"

# fig10's robot doors (wall A: y 5.6..6.55, wall B: y 0.45..1.4), closed by a block each
DOOR_A = BoxObstacle(center=(4.05, 6.075), size=(0.5, 0.95), yaw=0.0, height=2.0)
DOOR_B = BoxObstacle(center=(7.95, 0.925), size=(0.5, 0.95), yaw=0.0, height=2.0)


def with_obstacles(scene: Scene, *extra: BoxObstacle) -> Scene:
    return dataclasses.replace(scene, obstacles=scene.obstacles + extra)


@pytest.fixture(scope="module")
def fig10() -> Scene:
    return shipped("fig10")


@pytest.mark.parametrize("turn", [None, "mirror", pytest.param(0.7, marks=pytest.mark.slow)])
def test_the_cover_holds_every_valid_state(fig10, turn):
    """Sampled valid states, many within 3 cm of contact, all lie in the over-approximation."""
    scene = fig10 if turn is None else (mirror_scene(fig10, 0.3) if turn == "mirror"
                                        else rotate_scene(fig10, turn))
    cover = free_cover(scene)
    assert cover is not None
    ck = PivotChecker(scene, seed=0)
    rng = np.random.default_rng(1)
    x0, y0, x1, y1 = scene.bounds
    near = 0
    for _ in range(3000):
        q = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
             float(rng.uniform(-math.pi, math.pi)))
        for g in range(4):
            c = ck.clearance(q, g)
            if c > 0:
                near += c < 0.03
                assert cover.covers(q, g), (q, g, c)
    assert near > 25  # the test reaches the states where a too small erosion would show


def test_most_colliding_states_are_excluded(fig10):
    """Not a vacuous cover: states in collision by more than the erosion are outside it."""
    cover = free_cover(fig10)
    assert cover is not None
    ck = PivotChecker(fig10, seed=0)
    rng = np.random.default_rng(2)
    hit = out = 0
    for _ in range(1500):
        q = (float(rng.uniform(0, 12)), float(rng.uniform(0, 7)), float(rng.uniform(-3, 3)))
        if not ck.world.box_in_bounds(q) or ck.world.box_distance(q) > 0:
            continue
        hit += 1
        out += not any(cover.covers(q, g) for g in range(4))
    assert hit > 100 and out > 0.8 * hit


def test_a_slot_forces_a_regrasp_per_wall(fig10):
    """With fig10's doors closed only the slots are left, which the robot cannot pass."""
    scene = with_obstacles(fig10, DOOR_A, DOOR_B)
    assert regrasp_lower_bound(scene).regrasps == 2
    # general: the same on a turned and a mirrored copy
    assert regrasp_lower_bound(rotate_scene(scene, 0.7)).regrasps == 2
    assert regrasp_lower_bound(mirror_scene(scene, 1.1)).regrasps == 2
    assert regrasp_lower_bound(with_obstacles(fig10, DOOR_B)).regrasps == 1


def test_bound_is_at_most_the_regrasps_of_the_seeded_plans():
    golden = json.loads(GOLDEN.read_text())
    bounds = {name: regrasp_lower_bound(shipped(name)) for name in ("fig10", "slot", "corridor")}
    for key, phases in golden.items():
        b = bounds[key.split("/")[0]]
        assert b.solvable is True and b.regrasps is not None
        assert b.regrasps <= sum("from_grasp" in p for p in phases), key


@pytest.mark.parametrize(("family", "seed"), [
    ("walls", 0), ("walls", 1), ("corridor", 0), ("clutter", 0),
    pytest.param("walls", 2, marks=pytest.mark.slow),
    pytest.param("corridor", 1, marks=pytest.mark.slow)])
def test_bound_is_at_most_the_witness_regrasps(family, seed):
    gen = generate(family, seed=seed)
    b = regrasp_lower_bound(gen.scene)
    assert b.regrasps is not None and b.regrasps <= gen.witness.regrasps


def test_a_walled_in_goal_has_no_relaxed_path():
    """The relaxation proves that no plan exists: a bound of ``None``, not solvable."""
    b = regrasp_lower_bound(shipped("enclosed"))
    assert b.solvable is False and b.regrasps is None


def test_open_floor_needs_no_regrasp_and_stopping_gives_unknown():
    scene = make_scene()
    assert regrasp_lower_bound(scene).regrasps == 0
    b = regrasp_lower_bound(scene, should_stop=lambda: True)
    assert b.regrasps is None and b.solvable is None

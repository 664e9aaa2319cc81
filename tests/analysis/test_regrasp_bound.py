"""The lower bound on regrasps: sound (never above a valid plan's regrasps) and not empty."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from cover_sampling import near_contact_states_covered
from factories import make_scene, shipped

from pivot_ompl.analysis.regrasp_bound import free_cover, held_bodies, regrasp_lower_bound
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import GeneratorParams, generate, mirror_scene, rotate_scene
from pivot_ompl.scene import Scene

GOLDEN = Path(__file__).parents[1] / "data" / "golden" / "seeded_plans.json"

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
    near = near_contact_states_covered(scene, cover, samples=3000, seed=1)
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


@pytest.mark.parametrize("copy", [None, "mirror", 0.7])
def test_fig10_needs_two_regrasps(fig10, copy):
    """The paper's count, proven on the scene and on turned and mirrored copies of it."""
    scene = fig10 if copy is None else (mirror_scene(fig10, 1.1) if copy == "mirror"
                                        else rotate_scene(fig10, copy))
    assert regrasp_lower_bound(scene).regrasps == 2


@pytest.mark.parametrize("walls", [1, 2, 3])
def test_k_box_only_slots_need_k_regrasps(walls):
    """Scenes built to force a count (each wall: a box-only slot and a robot-only door)."""
    gen = generate("walls", 1, params=GeneratorParams(walls=walls))
    b = regrasp_lower_bound(gen.scene)
    assert b.regrasps == walls <= gen.witness.regrasps


def test_a_wide_door_needs_no_regrasp():
    """The same walls with doors the held assembly passes: the bound drops to zero."""
    gen = generate("walls", 1, params=GeneratorParams(walls=2, door_width=(1.15, 1.35)))
    assert regrasp_lower_bound(gen.scene).regrasps == 0


def test_bound_is_at_most_the_regrasps_of_the_seeded_plans():
    golden = json.loads(GOLDEN.read_text())
    bounds = {name: regrasp_lower_bound(shipped(name)) for name in ("fig10", "slot", "corridor")}
    for key, phases in golden.items():
        b = bounds[key.split("/")[0]]
        assert b.solvable is True and b.regrasps is not None
        assert b.regrasps <= sum("from_grasp" in p for p in phases), key


@pytest.mark.parametrize(("family", "seed"), [
    ("walls", 0), ("walls", 1), ("corridor", 0), ("clutter", 0), ("building", 0),
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


def test_a_regrasp_needs_a_walk_round_the_box(fig10):
    """Door A closed: the robot cannot get round wall A, so no regrasp at slot A helps.

    The relaxation without the walk condition still counts two regrasps; with it, no plan
    exists (the box alone passes slot A, the robot never follows).
    """
    import dataclasses

    from pivot_ompl.scene import BoxObstacle

    door_a = BoxObstacle(center=(3.55, 6.075), size=(0.5, 0.95), yaw=0.0, height=2.0)
    closed = dataclasses.replace(fig10, obstacles=fig10.obstacles + (door_a,))
    assert regrasp_lower_bound(closed, walks=False).regrasps == 2
    b = regrasp_lower_bound(closed)
    assert b.regrasps is None and b.solvable is False


@pytest.mark.parametrize(("family", "seed"), [("walls", 1), ("corridor", 0), ("building", 0)])
def test_every_real_regrasp_is_allowed_by_the_walk_relaxation(family, seed):
    """Each regrasp of a witness (a real walk round the resting box) passes the relaxation."""
    import shapely

    from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
    from pivot_ompl.planfile import TransitPhase

    gen = generate(family, seed=seed)
    cover = free_cover(gen.scene)
    walk = WalkRelaxation(gen.scene, width=cover.width, tolerance=0.002, clearance=0.01)
    transits = [p for p in gen.witness.phases if isinstance(p, TransitPhase)]
    assert transits
    for p in transits:
        x, y, yaw = p.object_pose
        b = cover.bin_of(yaw)
        centre = -math.pi + (b + 0.5) * cover.width
        region = shapely.Point(x, y).buffer(1e-4)
        assert walk.may_regrasp(region, centre, p.from_grasp, p.to_grasp), p.object_pose


@pytest.mark.parametrize("grasp", [0, 1])
def test_a_body_offset_at_any_yaw_is_the_turned_body_offset(fig10, grasp):
    """Offsets built once at yaw 0 and turned are the offsets of the turned bodies."""
    rng = np.random.default_rng(3)
    for body in held_bodies(fig10, grasp):
        for _ in range(12):
            yaw, d = float(rng.uniform(-math.pi, math.pi)), float(rng.uniform(-0.05, 0.05))
            c, s = math.cos(yaw), math.sin(yaw)
            turned = shapely.Polygon(body.points @ np.array([[c, s], [-s, c]]))
            direct = turned.buffer(-d, join_style="mitre") if d > 0 else \
                turned.buffer(-d, quad_segs=4)
            got = body.offset_points(yaw, d)
            assert got is not None
            assert direct.symmetric_difference(shapely.Polygon(got)).area < 1e-12
        assert body.offset_points(0.3, 10.0) is None  # eroded to nothing

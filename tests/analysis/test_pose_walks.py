"""The regrasp count's walks and full clearance: never refusing what a checked plan does."""

from __future__ import annotations

import math

import pytest
import shapely
from factories import make_scene

from pivot_ompl.analysis.pose_jumps import JumpParts
from pivot_ompl.analysis.pose_regrasps import pose_regrasp_bound
from pivot_ompl.analysis.pose_walk import WHOLE, RegraspWalks
from pivot_ompl.planfile import TransferPhase, TransitPhase

CORRIDOR_BOX = {"object": {"size": [0.8, 0.4, 1.0]},
                "robot": {"model": "hrp2", "footprint": [0.4, 0.7], "standoff": 0.25}}


@pytest.fixture(scope="module")
def corridor_rows():
    """Two checked corridor rows (turned), with their witness plans."""
    from pivot_ompl.generate import GeneratorParams, generate

    return [generate("building", seed, params=GeneratorParams(
        rooms=3, layout="corridor", rotate=True, side_corridor=(0.87, 0.89),
        side_door=(1.0, 1.0))) for seed in (0, 1)]


def _bin(yaw: float, half: float = 0.01) -> tuple[float, float]:
    t = yaw % (2.0 * math.pi)
    return t - half, t + half


def test_every_regrasp_of_a_checked_plan_may_be_walked(corridor_rows):
    seen = 0
    for gen in corridor_rows:
        walks = RegraspWalks(gen.scene)
        for ph in gen.witness.phases:
            if isinstance(ph, TransitPhase) and ph.from_grasp != ph.to_grasp:
                x, y, yaw = ph.object_pose
                region = shapely.Point(x, y).buffer(1e-4)
                assert walks.may_regrasp(region, *_bin(yaw), ph.from_grasp, ph.to_grasp)
                seen += 1
    assert seen >= 4


def test_every_held_pose_of_a_checked_plan_is_in_a_part_of_its_grasp(corridor_rows):
    for gen in corridor_rows:
        parts = JumpParts(gen.scene, None)
        for ph in gen.witness.phases:
            if not isinstance(ph, TransferPhase):
                continue
            for pose in [ph.object_start] + [s.object for s in ph.steps][::7]:
                got = parts.of(*_bin(pose[2]))[ph.grasp]
                assert any(p.covers(shapely.Point(pose[0], pose[1])) for p in got)


def _dead_end(open_end: bool):
    # a 0.9 m corridor along y = 3 from x = 2 to 6.5; the box rests in it at x = 4, the
    # robot west of it; its east face is reachable only round the walls, by the east end
    walls = [{"type": "box", "center": [4.25, 2.4], "size": [4.5, 0.3], "yaw": 0.0,
              "height": 1.0},
             {"type": "box", "center": [4.25, 3.6], "size": [4.5, 0.3], "yaw": 0.0,
              "height": 1.0}]
    if not open_end:
        walls.append({"type": "box", "center": [6.35, 3.0], "size": [0.3, 0.9], "yaw": 0.0,
                      "height": 1.0})
    return make_scene(bounds=[0.0, 0.0, 8.0, 6.0], obstacles=walls, start=[1.0, 1.5, 0.0],
                      goal=[1.0, 4.5, 0.0], **CORRIDOR_BOX)


@pytest.mark.parametrize("whole", [WHOLE, 0])  # the floor one window; a raster outside it
@pytest.mark.parametrize("open_end", [False, True])
def test_a_regrasp_round_a_box_across_a_dead_end_is_refused(open_end, whole):
    scene = _dead_end(open_end)
    walks = RegraspWalks(scene, whole=whole)
    region = shapely.box(3.98, 2.98, 4.02, 3.02)  # box along x: robot at -x (0), at +x (2)
    assert walks.may_regrasp(region, -0.01, 0.01, 0, 2) is open_end


FINE = {"first_bins": 32, "most_rounds": 40, "most_bins": 1024}


def _two_rooms(width: float):
    # two rooms joined only by a corridor `width` wide, 3 m long: the held assembly is
    # 0.86 m across, so it keeps the checkers' 1 cm from the walls only from 0.88 m
    half = 0.5 * width
    walls = [{"type": "box", "center": [4.0, 3.0 + s * (half + 1.5)], "size": [3.0, 3.0],
              "yaw": 0.0, "height": 1.0} for s in (1.0, -1.0)]
    return make_scene(bounds=[0.0, 0.0, 8.0, 6.0], obstacles=walls, start=[1.2, 3.0, 0.0],
                      goal=[6.8, 3.0, 0.0], **CORRIDOR_BOX)


def test_a_corridor_open_at_8_mm_but_not_at_the_full_clearance_parts_start_and_goal():
    # at bins of 0.7 degrees the rotation cores keep a 0.870 m corridor open at 8 mm;
    # at 1 cm, grown by the sweep's 2 mm jumps, it is closed: no plan exists
    scene = _two_rooms(0.870)
    assert pose_regrasp_bound(scene, jumps=True, **FINE).apart
    assert not pose_regrasp_bound(scene, jumps=False, **FINE).apart
    assert not pose_regrasp_bound(_two_rooms(0.90), jumps=True, **FINE).apart


def test_a_count_cut_short_by_its_searches_stays_below_the_plans(corridor_rows):
    # with no search left the chain found is taken unasked: a count over more links than
    # the walks allow, so never above the full count, nor above a checked plan's regrasps
    for gen in corridor_rows:
        full = pose_regrasp_bound(gen.scene, target=None, most_rounds=2)
        short = pose_regrasp_bound(gen.scene, target=None, most_rounds=2, most_searches=0)
        assert short.complete and full.complete
        assert short.regrasps is not None and full.regrasps is not None
        assert short.regrasps <= full.regrasps <= gen.witness.regrasps


def test_the_levels_take_the_held_poses_count_after_the_exact_polygons():
    # a 4-room row whose exact polygons fit the levels' time: they prove the plans' 3 (their
    # walks refused where the walking body's own disk does not pass); the held poses' count
    # runs after them only while the bound is below the plan's count (here a plan of 4)
    from pivot_ompl.analysis.bound_levels import scaled_lower_bound
    from pivot_ompl.generate import GeneratorParams, generate

    scene = generate("building", 1, params=GeneratorParams(
        rooms=4, layout="corridor", rotate=True, side_corridor=(0.87, 0.89),
        side_door=(1.0, 1.0))).scene
    proven = scaled_lower_bound(scene, target=3, guided_seconds=60.0)
    assert proven.exhaustive and not proven.held and proven.regrasps == 3
    above = scaled_lower_bound(scene, target=4, guided_seconds=60.0)
    assert above.exhaustive and above.held and above.regrasps == 3

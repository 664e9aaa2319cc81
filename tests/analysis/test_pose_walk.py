"""The held poses' regrasp walks: sound against the exact walk, tight at a door."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import shapely
from factories import make_scene
from shapely import affinity

from pivot_ompl.analysis.late_proof import held_pose_proof
from pivot_ompl.analysis.pose_proof import prove_no_plan
from pivot_ompl.analysis.pose_walk import WHOLE, RegraspWalks
from pivot_ompl.cli.main import main
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.generate.sceneio import write_scene
from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.footprints import disk_clear
from pivot_ompl.validity.merge import merge_boxes

TOLERANCE, CLEARANCE = 0.002, 0.01
BOX = [0.8, 0.4, 1.0]


def _door(width: float, turn: float = 0.0):
    """Two rooms joined by a door ``width`` m wide through a 0.2 m wall at x = 4, the walls
    turned by ``turn`` about the door's centre (4, 3)."""
    c, s = math.cos(turn), math.sin(turn)
    walls = [{"type": "box", "center": [4.0 - s * d, 3.0 + c * d], "size": [0.2, 8.0],
              "yaw": turn, "height": 2.0}  # 8 m long: across the floor at any turn
             for d in (-0.5 * width - 4.0, 0.5 * width + 4.0)]
    return make_scene(obstacles=walls, object={"size": BOX})


def _in_the_door(half_span: float, turn: float = 0.0) -> shapely.Polygon:
    """Box centres lengthwise in the door, as far as ``half_span`` m either side of its axis."""
    box = shapely.box(3.95, 3.0 - half_span, 4.05, 3.0 + half_span)
    return affinity.rotate(box, turn, origin=(4.0, 3.0), use_radians=True)


BIN = (-math.pi / 512, math.pi / 512)  # about the door's axis


def _bin(turn: float) -> tuple[float, float]:
    return turn - math.pi / 512, turn + math.pi / 512  # about the door's axis


@pytest.mark.parametrize(("grasps", "turn"), [((0, 2), 0.0), ((2, 0), 0.0), ((0, 2), 0.7)])
def test_the_robot_cannot_walk_round_the_box_resting_lengthwise_in_a_narrow_door(grasps, turn):
    # 0.85 m: 0.45 m beside the box pushed to one jamb, the walking disk needs 0.54 m
    walks = RegraspWalks(_door(0.85, turn), tolerance=TOLERANCE, clearance=CLEARANCE)
    assert walks.may_regrasp(_in_the_door(0.2, turn), *_bin(turn), *grasps) is False


@pytest.mark.parametrize("turn", [0.0, 0.7])
def test_a_door_wide_enough_beside_the_box_lets_the_robot_walk_round_it(turn):
    # 1.1 m: 0.7 m beside the box pushed to one jamb
    walks = RegraspWalks(_door(1.1, turn), tolerance=TOLERANCE, clearance=CLEARANCE)
    assert walks.may_regrasp(_in_the_door(0.3, turn), *_bin(turn), 0, 2) is True
    # the box centred in it leaves 0.35 m either side: no walk
    assert walks.may_regrasp(_in_the_door(0.01, turn), *_bin(turn), 0, 2) is False


def _body_disk(scene) -> tuple[float, float]:
    """The walking body's largest inscribed disk: its radius, its centre ahead of the pose."""
    ahead, behind, side = scene.model.walking_extent()
    return min(side, 0.5 * (ahead + behind)), 0.5 * (ahead - behind)


def _centre(scene, q, grasp: int) -> shapely.Point:
    """The walking body's centre at grasp ``grasp`` of the box at ``q``."""
    x, y, heading = scene.model.robot_pose(q, grasp)
    ahead = _body_disk(scene)[1]
    return shapely.Point(x + ahead * math.cos(heading), y + ahead * math.sin(heading))


def _exact_walk(scene, free, q, g: int, h: int) -> bool:
    """The relaxation's walk for one pose, over the whole floor in exact polygons."""
    m = scene.model
    box = shapely.Polygon(rectangle_corners(q, m.object_size[0] - 2 * TOLERANCE,
                                            m.object_size[1] - 2 * TOLERANCE))
    left = free.difference(box.buffer(_body_disk(scene)[0] - TOLERANCE, quad_segs=16))
    a, b = (_centre(scene, q, k) for k in (g, h))
    return any(p.intersects(a) and p.intersects(b) for p in getattr(left, "geoms", [left]))


def _corridor_row():
    """A row of rooms on a turned corridor 0.87-0.89 m wide (the regrasp count's class)."""
    return generate("building", 0, params=GeneratorParams(
        rooms=3, layout="corridor", rotate=True, side_corridor=(0.87, 0.89),
        side_door=(1.0, 1.0))).scene


@pytest.mark.parametrize("whole", [WHOLE, 0])
@pytest.mark.parametrize("name", ["building", "corridor", "corridor_row"])
def test_a_walk_the_exact_polygons_allow_is_never_denied(name, whole):
    """Random poses of small regions and grasp pairs: where the whole floor's exact polygons
    join the stances round the box at the region's centre, the answer is "may"; and some
    answers are "no" (the test asks something: poses are drawn until one is refused, 600 at
    most). Both with the floor as one window and with a window and the raster outside it."""
    scene = _corridor_row() if name == "corridor_row" else generate(name, seed=0).scene
    free = disk_clear(scene.bounds, merge_boxes(scene.obstacles), radius=_body_disk(scene)[0],
                      clearance=CLEARANCE - TOLERANCE)
    walks = RegraspWalks(scene, tolerance=TOLERANCE, clearance=CLEARANCE, whole=whole)
    rng = np.random.default_rng(3)
    x0, y0, x1, y1 = scene.bounds
    seen = []
    while len(seen) < 120 or (all(got for _, got in seen) and len(seen) < 600):
        q = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
             float(rng.uniform(-math.pi, math.pi)))
        g, h = sorted(rng.choice(4, size=2, replace=False).tolist())
        stances = [_centre(scene, q, k) for k in (g, h)]
        if not all(free.covers(s) for s in stances):
            continue
        exact = _exact_walk(scene, free, q, g, h)
        width = float(rng.uniform(1e-4, 0.05))
        region = shapely.Point(q[:2]).buffer(float(rng.uniform(0.0, 0.05)))
        got = walks.may_regrasp(region, q[2] - width, q[2] + width, g, h)
        assert got or not exact, (q, g, h)
        seen.append((exact, got))
    assert any(not got for _, got in seen) and any(got for _, got in seen)


def test_the_held_poses_proof_separates_rooms_whose_door_holds_the_box_but_not_the_walk(
        monkeypatch):
    # the box fits the 0.85 m door lengthwise, held from either room; the held assembly
    # (0.88 m across) does not, and the robot cannot walk round the box resting in it
    scene = dataclasses.replace(_door(0.85), start=(2.0, 3.0, 0.0), goal=(6.0, 3.0, 0.0))
    assert prove_no_plan(scene).apart is True
    no_plan = held_pose_proof(scene)  # the door named: where, how wide, what needs what
    assert no_plan is not None and no_plan.passage is not None
    assert "the gap at (4.00, 3.00), 0.85 m wide" in no_plan.reason
    assert "0.88 m" in no_plan.reason and "walk round" in no_plan.reason
    assert no_plan.passage.width == pytest.approx(0.85)
    monkeypatch.setattr(RegraspWalks, "may_regrasp", lambda *args: True)
    assert prove_no_plan(scene).apart is not True  # the regrasp in the door joins them


def test_the_bound_verb_with_held_poses_proves_the_door_and_names_it(tmp_path, capsys):
    scene = dataclasses.replace(_door(0.85), start=(2.0, 3.0, 0.0), goal=(6.0, 3.0, 0.0))
    path = write_scene(scene, tmp_path / "door.yaml")
    assert main(["bound", str(path), "--no-cache"]) == 0  # the bound alone proves nothing
    capsys.readouterr()
    assert main(["bound", str(path), "--no-cache", "--held-poses"]) == 1
    out = capsys.readouterr().out
    assert "no plan" in out and "the gap at (4.00, 3.00), 0.85 m wide" in out

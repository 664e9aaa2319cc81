"""The held-pose test of floor cells: a cell holding a valid held pose is never closed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, turned_generated

from pivot_ompl.analysis.held_cells import HeldCells
from pivot_ompl.checking.pivot_checker import PivotChecker


def _slot(width: float):
    """A 1.5 m thick barrier across the floor at x 4-5.5 with one slot ``width`` m wide."""
    low, high = 3.0 - 0.5 * width, 3.0 + 0.5 * width
    return make_scene(bounds=[0.0, 0.0, 10.0, 6.0], obstacles=[
        {"type": "box", "center": [4.75, 0.5 * low], "size": [1.5, low], "yaw": 0.0,
         "height": 2.0},
        {"type": "box", "center": [4.75, 0.5 * (high + 6.0)], "size": [1.5, 6.0 - high],
         "yaw": 0.0, "height": 2.0}], start=[1.5, 3.0, 0.0], goal=[8.5, 3.0, 0.0])


def _edge_poses(scene, rng: np.random.Generator, count: int) -> np.ndarray:
    """Valid held poses ``(x, y, yaw)`` at the edge of the valid ones: a pose 3 cm or 2
    degrees away is invalid (where a test that erodes too little would close cells)."""
    checker = PivotChecker(scene)
    x0, y0, x1, y1 = scene.bounds
    out: list[tuple[float, float, float]] = []
    for _ in range(200 * count):
        p = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
             float(rng.uniform(-math.pi, math.pi)))
        k = int(rng.integers(4))
        if not checker.state_valid(p, k):
            continue
        moved = [(p[0] + 0.03 * math.cos(a), p[1] + 0.03 * math.sin(a), p[2])
                 for a in np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False)]
        moved += [(p[0], p[1], p[2] + d) for d in (-0.035, 0.035)]
        if any(not checker.state_valid(q, k) for q in moved):
            out.append(p)
            if len(out) == count:
                break
    return np.array(out)


@pytest.mark.parametrize("seed", range(3))
def test_no_cell_holding_a_valid_held_pose_is_closed(seed):
    scene = turned_generated(seed)
    rng = np.random.default_rng(seed)
    poses = _edge_poses(scene, rng, 60)
    assert len(poses) >= 20
    cells = HeldCells(scene)
    for half in (0.05, 0.025, 0.01):
        # cells of random placement, each holding one of the poses
        x = poses[:, 0] + rng.uniform(-half, half, len(poses))
        y = poses[:, 1] + rng.uniform(-half, half, len(poses))
        assert not cells.closed(x, y, half).any()


def test_in_a_slot_the_held_assembly_barely_fits_no_cell_holding_a_valid_pose_is_closed():
    # the robot (0.86 m wide, kept 1 cm off) fits a 0.89 m slot only centred to +-5 mm and
    # nearly aligned: the valid poses are a thin set, where a test eroding too little closes
    scene = _slot(0.89)
    checker = PivotChecker(scene)
    rng = np.random.default_rng(7)
    poses = []
    for _ in range(4000):
        p = (float(rng.uniform(4.1, 5.4)), 3.0 + float(rng.uniform(-0.008, 0.008)),
             float(rng.choice([0.0, 0.5 * math.pi, math.pi, -0.5 * math.pi])
                   + rng.uniform(-0.02, 0.02)))
        if any(checker.state_valid(p, k) for k in range(4)):
            poses.append(p)
    poses = np.array(poses)
    assert len(poses) >= 50
    cells = HeldCells(scene)
    for half in (0.02, 0.01, 0.004):
        x = poses[:, 0] + rng.uniform(-half, half, len(poses))
        y = poses[:, 1] + rng.uniform(-half, half, len(poses))
        assert not cells.closed(x, y, half).any()
    # and the slot is not closed everywhere: the robot is tight, not stuck
    narrower = HeldCells(_slot(0.86))
    assert narrower.closed(np.array([4.75]), np.array([3.0]), 0.01).all()


def test_a_slot_the_box_fits_and_the_robot_does_not_is_closed_inside():
    # the paper box is 0.6 m wide, the robot holding it at least 0.86 m: in a 0.7 m slot
    # the box's centre can be half way in only with the robot in the slot too
    scene = _slot(0.7)
    cells = HeldCells(scene)
    xs = np.arange(4.6, 4.95, 0.05)
    shut = cells.closed(xs, np.full(len(xs), 3.0), 0.025)
    assert shut.all()
    # in the open, and inside a slot the robot fits, nothing is closed
    assert not cells.closed(np.array([1.5, 8.5]), np.array([3.0, 3.0]), 0.025).any()
    wide = HeldCells(_slot(1.2))
    assert not wide.closed(xs, np.full(len(xs), 3.0), 0.025).any()


def test_a_cell_beyond_the_bounds_reach_is_closed():
    # the box's centre 0.2 m from the floor's edge: its 0.6 m side cannot be inside
    scene = make_scene()
    cells = HeldCells(scene)
    assert cells.closed(np.array([0.2]), np.array([3.0]), 0.02).all()
    assert not cells.closed(np.array([1.5]), np.array([3.0]), 0.02).any()

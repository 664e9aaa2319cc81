"""The lattice's frame of a turned or mirrored copy is the original's, up to a quarter turn.

The direction is that of the walls that look onto the free floor. A copy made by
``rotate_scene`` / ``mirror_scene`` keeps its old floor as four long walls; counted whole
(both faces), they outweighed the inner walls of ``gen:walls:1`` (walls at 40 degrees) and the
copy's lattice ran along the old floor, not along the walls that shape its route.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.wall_frame import wall_frame
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import generate, mirror_scene, rotate_scene
from pivot_ompl.planners.routes.lattice_frame import LatticeFrame, lattice_frame
from pivot_ompl.scene.walls import wall_yaw

QUARTER = 0.5 * math.pi
GRID = 0.1


@pytest.fixture(scope="module")
def walls_1():
    return generate("walls", 1).scene


def _off_quarter(a: float) -> float:
    """``a`` (rad) from the nearest multiple of a quarter turn."""
    return abs((a + 0.5 * QUARTER) % QUARTER - 0.5 * QUARTER)


def _frame(scene) -> LatticeFrame:  # noqa: ANN001
    return lattice_frame(PivotChecker(scene), resolution=GRID)


def _sides(frame: LatticeFrame) -> list[float]:
    assert frame.world is not None
    x0, y0, x1, y1 = frame.world.bounds
    return sorted((x1 - x0, y1 - y0))


@settings(max_examples=12, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), mirror=st.booleans())
def test_a_copy_of_a_floor_with_walls_at_two_angles_gets_the_original_s_frame(walls_1, angle,
                                                                              mirror):
    assume(_off_quarter(angle) > 1e-3)
    original = _frame(walls_1)
    if mirror:  # a direction d is reflected to 2 angle - d
        copy, expected = mirror_scene(walls_1, angle), 2.0 * angle - original.yaw
    else:
        copy, expected = rotate_scene(walls_1, angle), original.yaw + angle
    assume(_off_quarter(expected) > 1e-3)
    frame = _frame(copy)
    assert _off_quarter(frame.yaw - expected) < 1e-6  # the inner walls', not the old floor's
    assert _sides(frame) == pytest.approx(_sides(original), abs=GRID + 1e-6)


def test_the_old_floor_s_faces_outside_it_do_not_count(walls_1):
    copy = rotate_scene(walls_1, 0.6)
    # the old floor's walls run at 0.6 rad; the inner walls at 0.70 + 0.6 (less a quarter)
    assert _off_quarter(_frame(copy).yaw - 0.6) > 0.1
    # the relaxations keep every edge's direction (the old floor's, on this copy)
    relaxed = wall_frame(copy, worth=math.inf)
    assert relaxed is not None and relaxed.yaw == wall_yaw(copy.obstacles)
    assert _off_quarter(relaxed.yaw - 0.6) < 1e-9

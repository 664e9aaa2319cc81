"""Doors read from the geometry: gaps the held assembly passes straight but cannot turn in."""

from __future__ import annotations

import math

import pytest
from factories import two_rooms
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import RigidMap, rotate_scene
from pivot_ompl.planners.config import SamplingConfig
from pivot_ompl.planners.objects.slots import assembly_extent, door_poses, doors

#: Two 4 x 4.5 m rooms and the 0.3 m wall between them (its west face at x = 4.3).
WALL_X, WALL, DEPTH = 4.3, 0.3, 4.5
PLAY = SamplingConfig().door_play


def _door_centre() -> tuple[float, float]:
    return (WALL_X + 0.5 * WALL, 0.3 + 0.5 * DEPTH)


def test_a_door_is_wider_than_the_assembly_and_narrower_than_its_turning_disk():
    ck = PivotChecker(two_rooms(1.7), seed=0)
    ext = assembly_extent(ck)
    clear = ck.world.clearance
    assert ext.width > 0.8 and ext.radius > 0.5 * ext.width and ext.reach > ext.width
    found = [p for p in doors(ck, play=PLAY) if math.dist(p.center, _door_centre()) < 1e-6]
    assert len(found) == 1
    assert found[0].width == pytest.approx(1.7)
    assert found[0].length == pytest.approx(WALL)
    assert abs(math.remainder(found[0].axis, math.pi)) < 1e-9  # the wall's normal
    for width in (ext.width + 2 * clear - 0.02, 2 * (ext.radius + clear) + PLAY + 0.02):
        ck = PivotChecker(two_rooms(width), seed=0)
        assert not [p for p in doors(ck, play=PLAY)
                    if math.dist(p.center, _door_centre()) < 1e-6], width


@settings(max_examples=10, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), width=st.floats(1.0, 1.9))
def test_the_assembly_passes_a_door_straight_between_its_seeded_poses(angle, width):
    # at any rotation: the outer poses hold the whole assembly on either side of the wall and
    # at some grasp both straight pushes through the centre pose pass the exact checks
    scene = two_rooms(width)
    centre = (0.5 * (scene.bounds[0] + scene.bounds[2]), 0.5 * (scene.bounds[1] + scene.bounds[3]))
    copy = rotate_scene(scene, angle)
    f = RigidMap(angle, centre, False)
    ck = PivotChecker(copy, seed=0)
    door = [p for p in doors(ck, play=PLAY) if math.dist(p.center, f.point(_door_centre())) < 1e-6]
    assert len(door) == 1
    poses = door_poses(ck, door)
    assert len(poses) == 6  # three along the axis at each of two yaws, all free here
    ext = assembly_extent(ck)
    through = 0
    for k in range(0, len(poses), 3):
        a, mid, b = poses[k:k + 3]
        assert math.dist(a[:2], b[:2]) == pytest.approx(2 * ext.reach + WALL)
        for g in range(4):
            if all(ck.state_valid(q, g) for q in (a, mid, b)) and \
                    ck.transfer(a, mid, g).valid and ck.transfer(mid, b, g).valid:
                through += 1
    assert through >= 2  # pushed and pulled

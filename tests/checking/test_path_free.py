"""The cheap test run before a transfer check: box (and robot) free along the car's path."""

from __future__ import annotations

from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker

WALL = {"type": "box", "center": [4.0, 3.0], "size": [0.3, 2.0], "yaw": 0.0, "height": 2.0}


def test_a_wall_across_the_path_is_refused_without_a_transfer_check():
    ck = PivotChecker(make_scene(obstacles=[WALL]))
    a, b = (2.0, 3.0, 0.0), (6.0, 3.0, 0.0)
    assert ck.state_valid(a, 0) and ck.state_valid(b, 0)
    assert not ck.path_free(a, b, 0) and not ck.path_free(a, b, 0, with_robot=False)
    assert ck.counters.valid + ck.counters.invalid == 0  # no pivot sequence computed
    assert not ck.transfer(a, b, 0).valid  # and the full check agrees


def test_a_free_path_passes_and_its_transfer_holds():
    ck = PivotChecker(make_scene())
    a, b = (2.0, 3.0, 0.0), (6.0, 3.5, 0.3)
    assert ck.path_free(a, b, 1) and ck.transfer(a, b, 1).valid


def test_the_ends_are_not_tested_only_the_way_between():
    # a short edge (under two steps) has nothing between its ends to test
    ck = PivotChecker(make_scene(obstacles=[WALL]))
    assert ck.path_free((3.0, 3.0, 0.0), (3.1, 3.0, 0.0), 0)

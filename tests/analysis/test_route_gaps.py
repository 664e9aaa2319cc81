"""The route bound with the gaps no held pose fits closed: higher, and still a proof."""

from __future__ import annotations

import math
import re

import pytest
from factories import make_scene, turned_generated

from pivot_ompl.analysis.plan_bounds import disk_cells, disk_route, held_route, plan_bounds
from pivot_ompl.analysis.route_gaps import gap_closed_route
from pivot_ompl.api import plan
from pivot_ompl.cli.main import main
from pivot_ompl.errors import Interrupted
from pivot_ompl.generate.sceneio import write_scene


def _slot_and_door(width: float | None):
    """A 1.5 m thick barrier at x 4-5.5 up to y 4.4 (a door above it, 1.6 m), with a slot
    ``width`` m wide on the straight line from start to goal (``None``: no slot)."""
    wall = {"type": "box", "yaw": 0.0, "height": 2.0}
    if width is None:
        obstacles = [{**wall, "center": [4.75, 2.2], "size": [1.5, 4.4]}]
    else:
        low, high = 3.0 - 0.5 * width, 3.0 + 0.5 * width
        obstacles = [{**wall, "center": [4.75, 0.5 * low], "size": [1.5, low]},
                     {**wall, "center": [4.75, 0.5 * (high + 4.4)], "size": [1.5, 4.4 - high]}]
    return make_scene(bounds=[0.0, 0.0, 10.0, 6.0], obstacles=obstacles,
                      start=[1.5, 3.0, 0.0], goal=[8.5, 3.0, 0.0])


def test_a_slot_only_the_box_alone_fits_is_closed_and_the_bound_rises():
    # the paper box (0.6 m wide) passes a 0.7 m slot, the robot holding it (0.86 m) does not
    scene = _slot_and_door(0.7)
    found = held_route(scene)
    assert found is not None and found.complete and found.closed > 0
    assert found.plain == pytest.approx(7.0)  # the disk goes straight through the slot
    # closed, the way is round by the door: about as long as with no slot at all
    no_slot = disk_route(_slot_and_door(None), gaps=False)
    assert no_slot is not None and no_slot > 7.5
    assert found.route >= 0.99 * no_slot
    # a plan goes round by the door, and no shorter than the bound
    res = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert res.solved
    assert res.plan.extra["quality"]["route_length"] >= found.route


def test_the_bound_verb_prints_the_route_bound_a_plan_carries(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    scene = _slot_and_door(0.7)
    path = write_scene(scene, tmp_path / "slot_and_door.yaml")
    assert main(["bound", str(path), "--no-cache"]) == 0
    printed = re.search(r"a box route of at least ([0-9.]+) m", capsys.readouterr().out)
    found = held_route(scene)
    assert printed is not None and found is not None and found.closed > 0
    assert float(printed.group(1)) == pytest.approx(found.route, abs=0.005)
    assert float(printed.group(1)) > found.plain + 0.3  # not the disk's way through the slot


def test_a_slot_the_held_assembly_passes_stays_open():
    scene = _slot_and_door(1.2)
    found = held_route(scene)
    assert found is not None and found.complete
    assert found.route == pytest.approx(found.plain) == pytest.approx(7.0)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_no_plan_of_a_generated_scene_moves_its_box_less_than_the_gap_closed_route(seed):
    scene = turned_generated(seed)
    bound = disk_route(scene)
    assert bound is not None
    assert bound >= disk_route(scene, gaps=False) - 1e-9
    res = plan(scene, time_limit=30.0, seed=seed, bound=False)
    if res.solved:
        assert res.plan.extra["quality"]["route_length"] >= bound - 1e-9


def test_a_stop_after_the_first_path_keeps_the_rounds_done():
    scene = _slot_and_door(0.7)
    raster, mask = disk_cells(scene)
    calls = []

    def stop_later() -> bool:
        calls.append(1)
        return len(calls) > 12  # past the first graph search (11 polls), in the tests
    found = gap_closed_route(scene, raster, mask, should_stop=stop_later)
    assert found.stopped and not found.complete
    assert found.route is not None and found.plain is not None
    assert found.route >= found.plain > 6.5  # the first round: through the slot
    with pytest.raises(Interrupted):
        gap_closed_route(scene, raster, mask, should_stop=lambda: True)
    with pytest.raises(Interrupted):
        gap_closed_route(scene, raster, mask, time_left=lambda: 0.0)


def test_a_plan_without_regrasps_carries_the_gap_closed_route():
    scene = _slot_and_door(0.7)
    regrasps, route = plan_bounds(scene, 0)
    assert regrasps == 0 and route == pytest.approx(held_route(scene).route)
    assert route > 7.5 > math.dist(scene.start[:2], scene.goal[:2])


def test_a_route_bound_the_plan_refutes_is_dropped(caplog):
    # a plan shorter than the bound would prove the bound wrong: it is not given
    scene = _slot_and_door(0.7)
    assert plan_bounds(scene, 0, route_length=5.0) == (0, None)
    assert "route bound dropped" in caplog.text


def test_a_bound_stopped_partway_is_given_but_not_kept_for_later_plans(monkeypatch):
    import pivot_ompl.analysis.plan_bounds as bounds

    scene = _slot_and_door(0.72)  # a scene of its own (the memo is per scene geometry)
    calls: list[int] = []
    polls: list[int] = []

    def counted(*args, **kwargs):
        calls.append(1)
        return held_route(*args, **kwargs)

    def stop_in_the_tests() -> bool:
        polls.append(1)
        return len(polls) > 40  # past the disk cells and the first path

    monkeypatch.setattr(bounds, "held_route", counted)
    partial = plan_bounds(scene, 0, should_stop=stop_in_the_tests)[1]
    assert partial is not None and len(calls) == 1
    whole = plan_bounds(scene, 0)[1]
    assert len(calls) == 2 and whole is not None and whole >= partial
    assert plan_bounds(scene, 0)[1] == whole and len(calls) == 2

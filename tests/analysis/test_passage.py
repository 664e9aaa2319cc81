"""Proven infeasibility explained: the passage that blocks every plan, its place and width."""

from __future__ import annotations

import json
import time

import pytest
from factories import make_scene, scene_file, shipped, sliced
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.passage import assembly_width, blocking_passage, explain_no_plan
from pivot_ompl.api import PROOF_SHARE, plan
from pivot_ompl.cli.main import main
from pivot_ompl.generate import mirror_scene, rotate_scene
from pivot_ompl.scene import load_scene, obstacles_from_list

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


def _scene_with_slot(slot_y: float, slot: float, pieces: int = 1):
    """The 8 x 6 m floor walled across at x = 4 but for a slot of ``slot`` m centred at
    ``slot_y`` (each wall cut into ``pieces`` touching boxes)."""
    lo, hi = slot_y - 0.5 * slot, slot_y + 0.5 * slot
    walls = obstacles_from_list([
        {"type": "box", "center": [4.1, 0.5 * lo], "size": [0.2, lo], "yaw": 0.0, "height": 2.0},
        {"type": "box", "center": [4.1, 0.5 * (hi + 6.0)], "size": [0.2, 6.0 - hi],
         "yaw": 0.0, "height": 2.0}])
    doc = [{"type": "box", "center": list(o.center), "size": list(o.size), "yaw": o.yaw,
            "height": o.height} for o in sliced(walls, pieces)]
    return make_scene(obstacles=doc, object={"size": [0.8, 0.4, 1.0]})


@settings(max_examples=25, deadline=None)
@given(slot_y=st.floats(1.0, 5.0), slot=st.floats(0.05, 0.8), pieces=st.sampled_from([1, 3]))
def test_the_passage_is_the_slot_with_its_exact_width_and_place(slot_y, slot, pieces):
    scene = _scene_with_slot(slot_y, slot, pieces)
    assert slot < assembly_width(scene.model)
    p = blocking_passage(scene)
    assert p is not None and p.center is not None
    assert p.width == pytest.approx(slot, abs=1e-9)
    assert p.center[0] == pytest.approx(4.1, abs=1e-6)
    assert p.center[1] == pytest.approx(slot_y, abs=1e-6)
    x, y = p.center
    assert f"{p.width:.2f} m" in p.reason and f"({x:.2f}, {y:.2f})" in p.reason
    # what needs what: the box passes a slot wider than its short side (and clearance)
    assert ("the box passes" in p.reason) == (slot >= p.box_needs)


def test_a_wide_door_blocks_nothing():
    assert blocking_passage(_scene_with_slot(3.0, 1.2)) is None
    assert blocking_passage(shipped("fig10")) is None


def test_a_closed_room_has_no_opening():
    p = blocking_passage(shipped("enclosed"))
    assert p is not None and p.center is None and "no opening" in p.reason


@settings(max_examples=12, deadline=None)
@given(angle=st.floats(-3.1, 3.1), mirrored=st.booleans())
def test_a_closed_room_turned_or_mirrored_still_has_no_opening(angle, mirrored):
    # its walls touch edge to edge; turned, round-off moves the edges ~1e-16 m apart
    room = shipped("enclosed")
    scene = mirror_scene(room, angle) if mirrored else rotate_scene(room, angle)
    p = blocking_passage(scene)
    assert p is not None and p.center is None and "no opening" in p.reason, p


def test_a_mirrored_closed_room_is_answered_before_the_search():
    # the floor is cut between start and goal: proven without the relaxation
    scene = mirror_scene(shipped("enclosed"), 0.3)
    res = plan(scene, time_limit=2.0, seed=0)
    assert res.status == "INFEASIBLE" and "no opening" in (res.infeasible_reason or "")
    assert res.timings["solve"] == 0.0


def test_a_feasible_scene_is_not_explained_away():
    assert explain_no_plan(shipped("slot")) is None  # one regrasp: a plan exists


def test_plan_stops_at_once_with_the_reason_when_no_plan_exists():
    limit = 20.0
    t0 = time.monotonic()
    res = plan(load_scene(scene_file("box_only_room")), time_limit=limit, seed=0)
    took = time.monotonic() - t0
    assert res.status == "INFEASIBLE" and not res.solved
    assert took <= 0.1 * limit, took
    assert res.infeasible_reason is not None
    assert "(4.10, 2.00)" in res.infeasible_reason and "0.50 m" in res.infeasible_reason
    assert "0.88 m to follow the box" in res.infeasible_reason
    assert res.passage is not None and res.passage.width == pytest.approx(0.5)
    assert res.plan.extra["no_plan"] == res.infeasible_reason
    assert res.plan.extra["passage"]["width"] == pytest.approx(0.5)
    assert PROOF_SHARE < 0.1


def test_cli_plan_says_why_exits_1_and_plots_the_passage(tmp_path, capsys):
    out, fig = tmp_path / "plan.json", tmp_path / "why.png"
    out.write_text("{}")  # an existing file survives a failed run
    rc = main(["plan", str(scene_file("box_only_room")), "--time", "20", "--out", str(out),
               "--plot", str(fig)])
    text = capsys.readouterr()
    assert rc == 1
    line = [ln for ln in text.out.splitlines() if ln.startswith("INFEASIBLE")]
    assert len(line) == 1 and "slot at (4.10, 2.00) is 0.50 m" in line[0]
    assert json.loads(out.read_text()) == {}
    assert fig.stat().st_size > 10_000


def test_cli_plan_without_a_figure_says_no_plan_exists_not_none_found(tmp_path, capsys):
    out = tmp_path / "plan.json"
    rc = main(["plan", str(scene_file("box_only_room")), "--time", "20", "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 1 and not out.exists()
    assert "no plan exists: nothing written" in err and "no plan found" not in err


def test_of_two_slots_the_wider_is_the_passage_to_widen():
    walls = [{"type": "box", "center": [4.1, 0.75], "size": [0.2, 1.5], "yaw": 0.0, "height": 2},
             {"type": "box", "center": [4.1, 2.65], "size": [0.2, 1.7], "yaw": 0.0, "height": 2},
             {"type": "box", "center": [4.1, 4.9], "size": [0.2, 2.2], "yaw": 0.0, "height": 2}]
    p = blocking_passage(make_scene(obstacles=walls))  # slots 0.30 m at y 1.65, 0.30 m at 3.65
    assert p is not None and p.width == pytest.approx(0.3)
    walls[2] = {"type": "box", "center": [4.1, 5.0], "size": [0.2, 2.0], "yaw": 0.0, "height": 2}
    p = blocking_passage(make_scene(obstacles=walls))  # the upper slot now 0.50 m
    assert p is not None and p.width == pytest.approx(0.5) and p.center[1] == pytest.approx(3.75)


def test_no_proof_is_tried_where_every_way_is_wide_enough():
    # a large open floor: the relaxation would take seconds; the passage search milliseconds
    scene = make_scene(bounds=[0.0, 0.0, 60.0, 40.0], start=[3.0, 3.0, 0.0],
                       goal=[56.0, 36.0, 0.0])
    t0 = time.perf_counter()
    assert explain_no_plan(scene) is None
    assert time.perf_counter() - t0 < 0.5


def test_a_wall_of_pieces_with_cracks_still_shows_its_slot():
    # a SLAM map's wall: boxes 2 cm apart (cracks no body passes), one 0.5 m slot at y 2.0
    walls = []
    for lo, hi in ((0.0, 1.75), (2.25, 6.0)):
        n = round((hi - lo) / 0.25)
        for k in range(n):
            y0, y1 = lo + k * (hi - lo) / n, lo + (k + 1) * (hi - lo) / n - 0.02
            if k == n - 1:
                y1 = hi
            walls.append({"type": "box", "center": [4.1, 0.5 * (y0 + y1)],
                          "size": [0.2, y1 - y0], "yaw": 0.0, "height": 2.0})
    p = blocking_passage(make_scene(obstacles=walls))
    assert p is not None and p.width == pytest.approx(0.5)
    assert p.center == pytest.approx((4.1, 2.0))

"""Proven infeasibility for want of room to turn: no narrow passage, a corner too tight."""

from __future__ import annotations

import json
import math

import pytest
import yaml
from corner_factories import tight_corner
from cpu_share import with_cpu_limit
from factories import shipped, shipped_doc
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.late_proof import LateProof
from pivot_ompl.analysis.passage import assembly_width, blocking_passage
from pivot_ompl.analysis.turning import assembly_outline, turning_place
from pivot_ompl.analysis.turning_raster import raster_turning_place
from pivot_ompl.api import EXPLAIN_END, LATE_PROOF_BEGIN, plan
from pivot_ompl.cli.main import main
from pivot_ompl.generate import generate
from pivot_ompl.scene import Scene, scene_from_dict

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

LIMIT = 30.0


def _scene(seed: int) -> tuple[Scene, tuple[float, float]]:
    doc, corner = tight_corner(seed)
    return scene_from_dict(doc, source="<test>"), corner


def _proven_in_a_tenth(res, took: float, limit: float) -> bool:
    return res.status == "INFEASIBLE" and took <= 0.1 * limit


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_plan_says_where_the_box_cannot_turn_within_a_tenth_of_the_limit(seed):
    scene, corner = _scene(seed)
    assert blocking_passage(scene) is None  # no passage explains it: room to turn does
    # LIMIT, or more where a loaded machine gave the run less than a core (tests/cpu_share.py)
    res, took, limit = with_cpu_limit(lambda lim: plan(scene, time_limit=lim, seed=seed), LIMIT,
                                      _proven_in_a_tenth)
    assert res.status == "INFEASIBLE" and not res.solved, res.status
    assert took <= 0.1 * limit, took
    turn = res.turn
    assert turn is not None and res.passage is None
    assert math.dist(turn.center, corner) < 1.0  # at the corner
    x, y = turn.center
    reason = res.infeasible_reason
    assert reason is not None and reason.startswith("no plan: the box cannot turn at")
    assert f"({x:.2f}, {y:.2f})" in reason and f"{turn.width:.2f} m across" in reason
    w, length = assembly_outline(scene.model)
    assert turn.assembly_width == pytest.approx(assembly_width(scene.model))
    assert f"({w:.2f} x {length:.2f} m)" in reason
    # the room there is less than the held assembly's length, more than its width
    assert w < turn.width < length
    # the yaws it comes at from the start and those the goal needs do not meet
    a, b = turn.from_start
    c, d = turn.to_goal
    assert not any(a <= v <= b for v in (c, d, c + 360, d - 360))
    assert res.plan.extra["no_plan"] == reason and res.plan.extra["turn"]["reason"] == reason


def test_cli_plan_exits_1_with_the_reason_and_marks_the_place(tmp_path, capsys):
    doc, _ = tight_corner(3)
    path, out, fig = tmp_path / "corner.yaml", tmp_path / "plan.json", tmp_path / "why.png"
    path.write_text(yaml.safe_dump(doc))
    out.write_text("{}")  # an existing file survives a failed run

    def run(limit: float) -> tuple[int, str]:
        rc = main(["plan", str(path), "--time", str(limit), "--out", str(out), "--plot",
                   str(fig)])
        return rc, capsys.readouterr().out

    (rc, text), _, _ = with_cpu_limit(run, LIMIT, lambda r, took, limit: "INFEASIBLE" in r[1])
    assert rc == 1
    line = [ln for ln in text.splitlines() if ln.startswith("INFEASIBLE")]
    assert len(line) == 1 and "cannot turn at" in line[0] and "proven in" in line[0]
    assert json.loads(out.read_text()) == {}
    assert fig.stat().st_size > 10_000


def test_the_late_proof_is_not_tried_before_its_time_nor_twice():
    scene, _ = _scene(4)
    now = [0.0]
    late = LateProof(scene, begin=1.0, end=50.0, clock=lambda: now[0])
    assert late() is False and not late.tried  # an easy scene's search pays nothing
    now[0] = 1.0
    assert late() is True and late.tried and late.proof is not None
    assert late.proof.turn is not None and late.proof.fields()["turn"]["width"] > 0
    now[0] = 100.0
    assert late() is True  # asked once: the answer kept


def test_a_search_busy_less_than_its_share_of_cpu_is_not_slow_until_the_held_begin():
    # a loaded machine's clock runs ahead of the search's work: the proof waits for the work
    scene, _ = _scene(4)
    now, work = [1.0], [0.5]
    late = LateProof(scene, begin=1.0, end=50.0, held_begin=3.0, clock=lambda: now[0],
                     work_begin=1.0, work=lambda: work[0])
    assert late() is False and not late.tried
    work[0] = 1.0
    assert late() is True and late.tried and late.proof is not None
    idle = LateProof(scene, begin=1.0, end=50.0, held_begin=3.0, clock=lambda: now[0],
                     work_begin=1.0, work=lambda: 0.0)
    assert idle() is False and not idle.tried
    now[0] = 3.0  # from the held poses' begin on, whatever the work
    assert idle() is True and idle.tried and idle.proof is not None


def test_a_feasible_scene_is_never_stopped_by_the_late_proof():
    late = LateProof(shipped("slot"), begin=0.0, end=math.inf)
    assert late() is False and late.tried and late.proof is None
    assert late() is False
    assert turning_place(shipped("slot")) is None  # a plan exists: nothing to explain


def test_a_scene_whose_relaxation_joins_start_and_goal_is_not_asked_again(monkeypatch):
    import dataclasses

    import pivot_ompl.analysis.late_proof as late_proof

    s = shipped("slot")
    scene = dataclasses.replace(s, bounds=(*s.bounds[:3], s.bounds[3] + 0.0123))  # its own
    calls = []
    real = late_proof.turning_place

    def spy(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(late_proof, "turning_place", spy)
    ticks = iter([0.0, *[1e9] * 10_000])  # the relaxation chosen, then stopped at once
    stopped = LateProof(scene, begin=0.0, end=1e6, clock=lambda: next(ticks))
    assert stopped() is False and len(calls) == 1  # nothing learnt
    assert LateProof(scene, begin=0.0, end=math.inf)() is False and len(calls) == 2
    assert LateProof(scene, begin=0.0, end=math.inf)() is False and len(calls) == 2
    corner, _ = _scene(5)  # a proof found is found again
    for _ in range(2):
        late = LateProof(corner, begin=0.0, end=math.inf)
        assert late() is True and late.proof is not None


def test_the_shares_leave_the_answer_within_a_tenth_of_the_limit():
    assert 0.0 < LATE_PROOF_BEGIN < EXPLAIN_END < 0.1


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_every_generated_tight_corner_is_proven_and_placed(seed):
    scene, corner = _scene(seed)
    place = turning_place(scene)
    assert place is not None
    assert math.dist(place.center, corner) < 1.0


@pytest.mark.parametrize("seed", [0, 1])
def test_the_raster_relaxation_places_a_corner_too_tight_on_an_axis_aligned_floor(seed):
    # large floors: the coarse raster proves and places what the polygons would
    doc, corner = tight_corner(seed, widths=(0.9, 0.9), turned=False)
    scene = scene_from_dict(doc, source="<test>")
    place = raster_turning_place(scene)
    assert place is not None
    assert math.dist(place.center, corner) < 1.0
    assert place.reason.startswith("no plan: the box cannot turn at")
    a, b = place.from_start
    c, d = place.to_goal
    assert not any(a <= v <= b for v in (c, d, c + 360, d - 360))
    # the late proof takes the raster where the polygons do not fit its time
    late = LateProof(scene, begin=0.0, end=1e-3, clock=lambda: 0.0)
    assert late() is True and late.proof is not None and late.proof.turn == place


def test_the_raster_finds_no_place_where_a_plan_exists():
    assert raster_turning_place(shipped("slot")) is None
    assert raster_turning_place(shipped("fig10")) is None


@settings(max_examples=4, deadline=None)
@given(family=st.sampled_from(["walls", "corridor", "clutter"]), seed=st.integers(0, 40))
def test_no_place_is_given_where_a_witness_plan_exists(family, seed):
    # a place is a proof that no plan exists: never on a generated scene with its plan
    gen = generate(family, seed=seed)
    assert gen.witness.phases
    assert turning_place(gen.scene) is None
    assert raster_turning_place(gen.scene) is None


def test_a_proof_past_its_explanation_time_still_names_the_passage():
    # regression: on a loaded machine the proof ended after explain_end, and the passage
    # search, stopped at once, left a closed wall explained as a place too tight to turn
    doc = shipped_doc("slot")
    doc["obstacles"] = [*doc["obstacles"],  # the slot and the door closed: the wall spans
                        {"type": "box", "center": [4.05, 1.5], "size": [0.5, 0.62], "height": 2.0},
                        {"type": "box", "center": [4.05, 4.525], "size": [0.5, 0.95],
                         "height": 2.0}]
    scene = scene_from_dict(doc, source="<test>")
    polls = [0]

    def clock() -> float:  # a millisecond a poll: the proof polls far more than 50 times
        polls[0] += 1
        return 1e-3 * polls[0]

    late = LateProof(scene, begin=0.0, end=math.inf, explain_end=0.05, clock=clock)
    assert late() is True and late.proof is not None
    assert polls[0] > 50  # the proof did end past explain_end
    assert late.proof.passage is not None and late.proof.turn is None
    assert late.proof.reason.startswith("no plan: no opening joins")

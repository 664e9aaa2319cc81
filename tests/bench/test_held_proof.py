"""benchmarks/held_proof.py: one held poses' proof in a fresh process, its stages summed."""

from __future__ import annotations

import pytest
from corner_factories import corner_slot
from factories import benchmark_script

from pivot_ompl.generate.sceneio import write_scene


def test_a_proof_runs_in_its_own_process_and_reports_its_stages():
    hp = benchmark_script("held_proof")
    row = hp.run(hp.ROOT, "slot")
    # the slot's finest bins join start and goal: "joined", every bin's regions computed
    # once or read from its half-turn twin
    assert row["answer"] == "joined"
    assert row["rounds"] >= 1 and row["computed"] > 0
    # the stages' CPU seconds, summed inside the proof's own
    assert 0.0 < row["regions"] <= row["cpu"]
    assert 0.0 < row["unions"] <= row["cpu"]
    assert 0.0 <= row["chain"] <= row["cpu"] and 0.0 <= row["walks"] <= row["cpu"]


def test_a_corpus_map_is_imported_once_and_an_unknown_one_refused(tmp_path):
    hp = benchmark_script("held_proof")
    assert hp.scene_path("slot", tmp_path, "0") == str(tmp_path / "0.yaml")  # made here
    path = hp.scene_path("corpus:turtlebot3_world", tmp_path, "1")
    assert path.endswith("turtlebot3_world.yaml") and (tmp_path / "turtlebot3_world.yaml").exists()
    with pytest.raises(SystemExit, match="no such map"):
        hp.scene_path("corpus:nowhere", tmp_path, "2")


def test_the_gate_runs_in_its_own_process_with_its_answer_and_stages():
    hp = benchmark_script("held_proof")
    row = hp.run(hp.ROOT, "slot", gate=True)
    # poses valid at every yaw join the slot's start and goal: "joined" at the gate's 32 bins
    assert row["answer"] == "joined" and row["bins"] == 32 and "rounds" not in row
    assert row["computed"] > 0
    assert 0.0 < row["regions"] <= row["cpu"] and 0.0 < row["chain"] <= row["cpu"]


def test_the_held_try_runs_the_gate_then_the_proof_where_the_gate_does_not_join(tmp_path):
    hp = benchmark_script("held_proof")
    row = hp.run(hp.ROOT, "slot", both=True)
    # the slot's poses valid at every yaw join start and goal: the gate answers, no proof
    assert row["answer"] == "joined" and row["bins"] == 32 and row["rounds"] == 0
    assert 0.0 < row["regions"] <= row["cpu"] and 0.0 < row["chain"] <= row["cpu"]
    write_scene(corner_slot(0.90, 0.92), tmp_path / "corner_slot.yaml")
    row = hp.run(hp.ROOT, str(tmp_path / "corner_slot.yaml"), both=True)
    # no chain at every yaw; the proof runs on the gate's floor and proves
    assert row["answer"] == "apart" and row["rounds"] >= 1

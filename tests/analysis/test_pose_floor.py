"""One floor for the held poses' gate and proof: built once, the same answers as two."""

from __future__ import annotations

import math

import numpy as np
import pytest
from corner_factories import corner_slot, ragged_slot
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.late_proof import NOTHING_TO_PROVE, LateProof
from pivot_ompl.analysis.pose_bins import BinRegions
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_inner import EveryYawRegions, joined_at_every_yaw
from pivot_ompl.analysis.pose_proof import (
    MOTION_CLEARANCE,
    HeldParts,
    proof_estimate,
    prove_no_plan,
)
from pivot_ompl.analysis.pose_walk import RegraspWalks
from pivot_ompl.scene.shared import keep_shared
from pivot_ompl.validity.collision import KEEP_CLEARANCE


def _count_inits(monkeypatch: pytest.MonkeyPatch, cls: type,
                 args: list[tuple] | None = None) -> list[type]:
    """Every instance ``cls.__init__`` builds from now on, by its type (and its ``args``)."""
    built: list[type] = []
    init = cls.__init__

    def counted(self, *a, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003
        built.append(type(self))
        if args is not None:
            args.append(a)
        init(self, *a, **kwargs)

    monkeypatch.setattr(cls, "__init__", counted)
    return built


def test_the_gate_builds_only_the_regions_it_reads(monkeypatch):
    scene, args = corner_slot(0.90, 0.92), []
    built = _count_inits(monkeypatch, BinRegions, args)
    assert joined_at_every_yaw(scene) is False
    assert built == [EveryYawRegions]  # no proof's region index built and then replaced
    # its poses keep the checkers' centimetre, its room is the proof's
    want = HeldFloor(scene, MOTION_CLEARANCE, None).near_room(KEEP_CLEARANCE)
    grown = args[0][0]
    assert grown.keys() == want.keys()
    assert all(np.array_equal(grown[k], want[k]) for k in want)


def test_the_late_proofs_gate_and_proof_read_one_floor(monkeypatch):
    scene = corner_slot(0.90, 0.93)  # a geometry no other test keeps a held answer for
    walks = _count_inits(monkeypatch, RegraspWalks)
    floors = _count_inits(monkeypatch, HeldFloor)
    keep_shared(scene, NOTHING_TO_PROVE, True)  # as where the poses' relaxation joins
    late = LateProof(scene, begin=0.0, end=100.0, clock=lambda: 1.0,
                     held_end=1.0 + proof_estimate(scene))
    assert late() is True and "0.93 m" in late.proof.reason  # gate, then the proof: proven
    assert (len(floors), len(walks)) == (1, 1)  # the pieces, room and walks built once


@settings(max_examples=3, deadline=None)
@given(slot=st.floats(0.85, 1.0), seed=st.integers(0, 99))
@example(slot=0.92, seed=0)  # no plan: the proof proves it
def test_a_shared_floor_gives_the_answers_of_floors_of_their_own(slot, seed):
    scene = ragged_slot(seed, slot=slot, pieces=24)
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    assert joined_at_every_yaw(scene, floor=floor) is joined_at_every_yaw(scene)
    assert prove_no_plan(scene, floor=floor).apart is prove_no_plan(scene).apart


def test_the_gates_poses_keep_the_checkers_clearance_on_the_proofs_floor():
    scene = ragged_slot(1, pieces=40)
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    gate = HeldParts(scene, MOTION_CLEARANCE, None, parts_clearance=KEEP_CLEARANCE,
                     regions=EveryYawRegions, floor=floor)
    alone = HeldParts(scene, KEEP_CLEARANCE, None, regions=EveryYawRegions)
    assert gate.floor is floor and gate.walks is floor.walks
    a, b = 0.0, 2.0 * math.pi / 32
    for mine, own in zip(gate.bins.regions(a, b), alone.bins.regions(a, b), strict=True):
        assert mine.symmetric_difference(own).area < 1e-9
    # the proof's own parts on that floor are wider: its clearance is the motions' 8 mm
    proof = HeldParts(scene, MOTION_CLEARANCE, None, floor=floor)
    assert all(proof.bins.regions(a, b)[g].area > r.area + 1e-4
               for g, r in enumerate(gate.bins.regions(a, b)))


def test_a_floor_of_another_scene_or_clearance_is_not_read():
    scene, other = corner_slot(0.90, 0.92), corner_slot(3.0, 0.95)
    floor = HeldFloor(other, MOTION_CLEARANCE, None)
    assert HeldParts(scene, MOTION_CLEARANCE, None, floor=floor).floor is not floor
    assert HeldParts(other, KEEP_CLEARANCE, None, floor=floor).floor is not floor
    assert HeldParts(other, MOTION_CLEARANCE, None, floor=floor).floor is floor
    # the proof on the other scene's floor answers for its own scene: no plan there
    assert prove_no_plan(scene, floor=floor).apart is True

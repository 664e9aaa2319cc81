"""The held poses' proof's estimate from its passages' pieces, against the proof it estimates."""

from __future__ import annotations

import time

import pytest
from factories import shipped
from map_factories import lab_door

from pivot_ompl.analysis import pose_estimate
from pivot_ompl.analysis.pose_estimate import held_estimate
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, proof_estimate, prove_no_plan

pytestmark = pytest.mark.timed  # CPU seconds of proofs, compared with their estimates

#: How far (a factor either way) an estimate may be from the proof's CPU seconds: the bins a
#: proof computes vary about twofold between floors of one cost a bin.
FACTOR = 3.0


@pytest.mark.parametrize(("seed", "door"), [(0, 0.85), (2, 0.84)])
def test_the_estimate_follows_the_proof_where_the_passages_try_ends_it(tmp_path, seed, door):
    scene = lab_door(tmp_path, seed, door=door)
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    guess = held_estimate(floor)
    t0 = time.process_time()
    proof = prove_no_plan(scene, floor=floor)
    spent = time.process_time() - t0
    assert proof.apart is True  # the doorway is narrower than the held assembly
    assert guess / FACTOR <= spent <= guess * FACTOR, (guess, spent)
    assert proof_estimate(scene) > 3.0 * guess  # far fewer pieces than every piece


@pytest.mark.parametrize("name", ["fig10", "slot"])
def test_without_a_passages_try_the_estimate_is_every_pieces(name):
    scene = shipped(name)  # fewer pieces than a passages' try is worth
    assert held_estimate(HeldFloor(scene, MOTION_CLEARANCE, None)) == proof_estimate(scene)


def test_a_try_over_more_than_its_share_of_the_pieces_is_estimated_as_every_piece(
        tmp_path, monkeypatch):
    scene = lab_door(tmp_path, 0)  # its try holds under a tenth of the pieces near the room
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    assert held_estimate(floor) < proof_estimate(scene)
    monkeypatch.setattr(pose_estimate, "TRY_SHARE", 0.05)  # as the office's 41 % against 25 %
    assert held_estimate(floor) == proof_estimate(scene)

"""Which smaller rotations replace a failed piece: as large as pass, no short junction piece.

The refiner is driven by a stand-in check that passes exactly the rotations within an
angle (a narrow passage's limit, unknown to the refiner): its rotations must come close to
that angle (not only to the half-octave factor below it), end exactly on the path, and the
stretch's last sub-piece must run on past the piece's end where the path goes on.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.refinement import PieceRefiner
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.se2 import wrap_angle

AMAX = math.pi / 8
MODEL = BoxGraspModel((0.8, 0.4, 1.0), (0.4, 0.7), 0.25)
GRASP = 0
CA, CB = (0.0, 0.0, 0.0), (3.0, 0.0, 0.0)


def refiner(limit: float, *, stop_x: float = math.inf) -> tuple[PieceRefiner, PivotSteering]:
    """A refiner whose check passes rotations within ``limit`` that end before ``stop_x``."""
    steering = PivotSteering(turning_radius=1.0, alpha_max=AMAX)

    def rotations(pose, rots, grasp, with_robot, db, dr):
        ok = all(abs(r.angle) <= limit and r.car[0] <= stop_x for r in rots)
        return ("" if ok else "too large"), (db, dr)

    def clearance_bound(car, grasp, with_robot, db, dr):
        return 0.0, 1.0  # no bound from the clearance: the checks decide

    return PieceRefiner(MODEL, steering, 1e-4, rotations, clearance_bound), steering


def middle_piece(steering: PivotSteering):
    pieces = list(steering.iter_pieces(CA, CB, half_length=MODEL.edge_half_length(GRASP)))
    return pieces[len(pieces) // 2]


def close(a, b, tol=1e-9) -> bool:
    return abs(a[0] - b[0]) <= tol and abs(a[1] - b[1]) <= tol and \
        abs(wrap_angle(a[2] - b[2])) <= tol


@settings(max_examples=25, deadline=None)
@given(share=st.floats(0.2, 0.68))
def test_refined_rotations_are_nearly_as_large_as_the_check_allows(share):
    limit = share * AMAX
    ref, steering = refiner(limit)
    piece = middle_piece(steering)
    done = ref.refine(CA, CB, piece, GRASP, True, (1.0, 1.0), None, None)
    assert done.reason == ""
    assert all(abs(r.angle) <= limit + 1e-12 for r in done.rotations)
    # the half-octave factor below the limit gives up to 29 % less; bisected, a few %
    assert max(abs(r.angle) for r in done.rotations) >= 0.9 * limit
    # the rotations chain from the piece's start and end exactly on the path
    car = piece.start
    for r in done.rotations:
        car = r.car
    assert close(car, steering.paths.interpolate(CA, CB, done.reached))


def test_the_last_sub_piece_runs_past_the_piece_where_the_path_goes_on():
    ref, steering = refiner(0.3 * AMAX)
    piece = middle_piece(steering)
    done = ref.refine(CA, CB, piece, GRASP, True, (1.0, 1.0), None, None)
    assert done.reason == ""
    assert piece.t1 < done.reached < 1.0


def test_the_last_sub_piece_ends_on_the_piece_where_running_on_fails():
    steering = PivotSteering(turning_radius=1.0, alpha_max=AMAX)
    piece = middle_piece(steering)
    end = steering.paths.interpolate(CA, CB, piece.t1)
    ref, _ = refiner(0.3 * AMAX, stop_x=end[0] + 1e-9)
    done = ref.refine(CA, CB, piece, GRASP, True, (1.0, 1.0), None, None)
    assert done.reason == ""
    assert done.reached == pytest.approx(piece.t1, abs=1e-12)
    assert close(done.rotations[-1].car, end)
    # at the same bound as where running on passes (not a smaller one)
    assert max(abs(r.angle) for r in done.rotations) >= 0.9 * 0.3 * AMAX


def test_each_sub_piece_takes_the_largest_rotations_its_own_room_allows():
    """A passage that widens halfway: the wider part is not held to the narrow part's bound."""
    steering = PivotSteering(turning_radius=1.0, alpha_max=AMAX)
    piece = middle_piece(steering)
    wide_from = piece.start[0] + 0.4 * (steering.paths.interpolate(CA, CB, piece.t1)[0]
                                        - piece.start[0])
    narrow, wide = 0.25 * AMAX, 0.7 * AMAX

    def rotations(pose, rots, grasp, with_robot, db, dr):
        ok = all(abs(r.angle) <= (wide if min(pose[0], r.car[0]) >= wide_from else narrow)
                 for r in rots)
        return ("" if ok else "too large"), (db, dr)

    ref = PieceRefiner(MODEL, steering, 1e-4, rotations, lambda *args: (0.0, 1.0))
    done = ref.refine(CA, CB, piece, GRASP, True, (1.0, 1.0), None, None)
    assert done.reason == ""
    beyond = [r for r in done.rotations if r.car[0] > wide_from + 0.05]
    assert beyond and max(abs(r.angle) for r in beyond) >= 0.9 * wide
    car = piece.start
    for r in done.rotations:
        car = r.car
    assert close(car, steering.paths.interpolate(CA, CB, done.reached))

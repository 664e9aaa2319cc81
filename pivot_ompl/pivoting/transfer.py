"""Transfer phases: the box and the attached robot pivoted along a Reeds-Shepp path."""

from __future__ import annotations

from collections.abc import Iterable

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.steering import PivotSequence, PivotSteering
from pivot_ompl.planfile import TransferPhase, TransferStep
from pivot_ompl.se2 import Pose

#: Spacing of the Reeds-Shepp samples stored with a phase for plotting (m).
RS_PLOT_STEP = 0.05


def convert_object_path(model: BoxGraspModel, steering: PivotSteering, obj_a: Pose, obj_b: Pose,
                        grasp: int) -> PivotSequence:
    """Pivot rotations moving the box from object pose ``obj_a`` to ``obj_b`` at ``grasp``."""
    return steering.convert(model.car_pose(obj_a, grasp), model.car_pose(obj_b, grasp),
                            half_length=model.edge_half_length(grasp))


def steps_of(model: BoxGraspModel, seq: PivotSequence, grasp: int) -> tuple[TransferStep, ...]:
    """The plan steps (object and robot poses after each rotation) of a pivot sequence."""
    return tuple(TransferStep(r.pivot, r.angle, model.object_from_car(r.car, grasp),
                              model.robot_from_car(r.car, grasp)) for r in seq.rotations)


def phase_rotations(steering: PivotSteering,
                    sequences: Iterable[PivotSequence]) -> tuple[Rotation, ...]:
    """The rotations of a phase's consecutive pivot sequences, merged where they meet.

    Where a sequence's last rotation and the next one's first turn about the same corner and
    sum within the bound, they are one rotation
    (:meth:`~pivot_ompl.pivoting.steering.PivotSteering.append_merged`, as within a
    sequence): the merged rotation sweeps the union of the two checked sweeps, and the
    phase reaches the same poses with one pivot fewer.
    """
    rotations: list[Rotation] = []
    for seq in sequences:
        for r in seq.rotations:
            steering.append_merged(rotations, r)
    return tuple(rotations)


def rotation_steps(model: BoxGraspModel, rotations: Iterable[Rotation],
                   grasp: int) -> tuple[TransferStep, ...]:
    """The plan steps (object and robot poses after each rotation) of rotations at ``grasp``."""
    return tuple(TransferStep(r.pivot, r.angle, model.object_from_car(r.car, grasp),
                              model.robot_from_car(r.car, grasp)) for r in rotations)


def phase_steps(model: BoxGraspModel, steering: PivotSteering,
                sequences: Iterable[PivotSequence], grasp: int) -> tuple[TransferStep, ...]:
    """The plan steps of a phase's pivot sequences, merged where they meet.

    The rotations of :func:`phase_rotations`, as plan steps (:func:`rotation_steps`).
    """
    return rotation_steps(model, phase_rotations(steering, sequences), grasp)


def rs_samples(steering: PivotSteering, seq: PivotSequence) -> tuple[Pose, ...]:
    """Car poses along the sequence's Reeds-Shepp path, about every :data:`RS_PLOT_STEP` m."""
    n = max(2, int(seq.rs_length / RS_PLOT_STEP) + 1)
    return tuple(steering.paths.sample(seq.start, seq.goal, [i / (n - 1) for i in range(n)]))


def transfer_phase(model: BoxGraspModel, steering: PivotSteering, waypoints: list[Pose],
                   grasp: int, *, with_rs_path: bool = True) -> TransferPhase:
    """A transfer phase through object ``waypoints`` (first = phase start), one RS path per leg.

    Each leg starts from the object pose actually reached by the previous leg, so the chain of
    steps is continuous to round-off and ends exactly at the last waypoint.
    """
    seqs: list[PivotSequence] = []
    rs: list[Pose] = []
    current = waypoints[0]
    for target in waypoints[1:]:
        seq = convert_object_path(model, steering, current, target, grasp)
        seqs.append(seq)
        if with_rs_path:
            rs.extend(rs_samples(steering, seq))
        if seq.rotations:
            current = model.object_from_car(seq.rotations[-1].car, grasp)
    return TransferPhase(grasp, model.robot_pose(waypoints[0], grasp),
                         phase_steps(model, steering, seqs, grasp), waypoints[0], tuple(rs))

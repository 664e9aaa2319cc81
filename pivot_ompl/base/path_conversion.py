"""Turning a path of (object pose, grasp) states into a ``pivot-plan/1`` plan."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.rotation_shortcut import shorten
from pivot_ompl.checking.shared_results import shared_results
from pivot_ompl.errors import PlanningError
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.steering import PivotSequence
from pivot_ompl.pivoting.transfer import phase_rotations, rotation_steps, rs_samples
from pivot_ompl.planfile import Phase, Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose


def path_to_plan(scene: Scene, checker: PivotChecker, states: list[tuple[Pose, int]], *,
                 status: str = "exact", extra: dict[str, Any] | None = None,
                 shortcut: bool = True, should_stop: Callable[[], bool] | None = None) -> Plan:
    """Phases of a path: runs of one grasp become transfer phases, grasp changes transits.

    Every edge is taken from the checker's cache (so exactly the validated rotations and
    walks are written, two edges' rotations about one corner where they meet merged into
    one: :func:`~pivot_ompl.pivoting.transfer.phase_rotations`); an edge that is not valid
    raises :class:`PlanningError`. With ``shortcut``, runs of a transfer phase's rotations
    are then replaced by fewer where those pass the checker's checks
    (:func:`~pivot_ompl.checking.rotation_shortcut.shorten`: the phase ends where it did; a
    route state inside a replaced run is no longer passed exactly) until ``should_stop``.
    """
    m = scene.model
    phases: list[Phase] = []
    i = 0
    while i < len(states) - 1:
        pose, g = states[i]
        if states[i + 1][1] != g:
            walk = checker.transit(pose, g, states[i + 1][1])
            if not walk.valid:
                raise PlanningError("INVALID_PATH", f"no walk from grasp {g} at {pose}")
            phases.append(TransitPhase(g, states[i + 1][1], walk.robot_path, pose))
            i += 1
            continue
        seqs: list[PivotSequence] = []
        rs: list[Pose] = []
        j = i
        while j < len(states) - 1 and states[j + 1][1] == g:
            edge = checker.transfer(states[j][0], states[j + 1][0], g)
            if not edge.valid:
                raise PlanningError("INVALID_PATH", f"edge {j} invalid: {edge.reason}")
            seqs.append(edge.sequence)
            rs.extend(rs_samples(checker.steering, edge.sequence))
            j += 1
        rotations = phase_rotations(checker.steering, seqs)
        if shortcut and rotations:
            rotations = _shortened(scene, checker, m.car_pose(pose, g), rotations, g,
                                   should_stop)
        steps = rotation_steps(m, rotations, g)
        if steps:
            phases.append(TransferPhase(g, m.robot_pose(pose, g), steps, pose, tuple(rs)))
        i = j
    if not phases:  # start == goal: an empty transfer at the start grasp
        pose, g = states[0]
        phases.append(TransferPhase(g, m.robot_pose(pose, g), (), pose))
    return Plan(scene.name, status, m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, scene.start, phases, dict(extra or {}), scene.robot_model)


def _shortened(scene: Scene, checker: PivotChecker, start: Pose,
               rotations: tuple[Rotation, ...], grasp: int,
               should_stop: Callable[[], bool] | None) -> tuple[Rotation, ...]:
    """:func:`~pivot_ompl.checking.rotation_shortcut.shorten` of a phase, kept per scene.

    Kept with the checks the scene's checkers share
    (:mod:`~pivot_ompl.checking.shared_results`): they depend only on the scene's geometry
    and the rotations, so a later plan of the same route gets the same rotations unchecked.
    """
    shared = shared_results(scene, tolerance=checker.tolerance,
                            clearance=checker.world.clearance)
    key = (start, rotations, grasp)
    hit = shared.shortened.get(key)
    if not isinstance(hit, tuple):
        hit = shorten(checker.transfers.sweeps, start, rotations, grasp,
                      half_length=scene.model.edge_half_length(grasp),
                      alpha_max=checker.steering.alpha_max, should_stop=should_stop)
        if should_stop is not None and should_stop():
            return hit  # cut short: not kept
        shared.room()
        shared.shortened[key] = hit
    return hit

"""A witness: a plan built from a chain of ``(object pose, grasp)`` states and checked.

The chain is checked edge by edge with the project's own validity core (pivot sequences by
the steering, walks by the walk planner), turned into a ``pivot-plan/1`` plan, and the plan is
checked again by the independent validator (:func:`~pivot_ompl.validity.plan_check.check_plan`).
"""

from __future__ import annotations

from dataclasses import dataclass

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import require_type
from pivot_ompl.generate.checks import check_scene, check_states
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.plan_check import check_plan

State = tuple[Pose, int]


@dataclass(frozen=True)
class WitnessCheck:
    """Outcome of :func:`build_witness`: the plan if every check passed, else why not."""

    plan: Plan | None
    reason: str = ""

    @property
    def ok(self) -> bool:
        """Whether the chain is a valid plan of the scene."""
        return self.plan is not None


def build_witness(scene: Scene, states: list[State], *,
                  checker: PivotChecker | None = None) -> WitnessCheck:
    """Check the chain ``states`` in ``scene``; return its plan or the first failure.

    Raises:
        InputError: ``scene`` not a Scene, ``states`` not a sequence of ``(pose, grasp)``
            pairs (a pose three finite numbers, a grasp 0..3), ``checker`` not a
            :class:`PivotChecker` or ``None``.
    """
    check_scene(scene)
    check_states(states)
    if checker is not None:
        require_type(checker, PivotChecker, "checker", "a PivotChecker or None")
    states = [((float(p[0]), float(p[1]), float(p[2])), int(g)) for p, g in states]
    ck = checker or PivotChecker(scene)
    if not states or states[0][0] != scene.start or states[-1][0] != scene.goal:
        return WitnessCheck(None, "the chain must run from the scene's start to its goal")
    for pose, g in states:
        if not ck.state_valid(pose, g):
            return WitnessCheck(None, f"state {pose} grasp {g} invalid: {ck.explain(pose)}")
    for i, ((pa, ga), (pb, gb)) in enumerate(zip(states, states[1:], strict=False)):
        if ga == gb:
            edge = ck.transfer(pa, pb, ga)
            if not edge.valid:
                return WitnessCheck(None, f"transfer {i} invalid: {edge.reason}")
        elif pa != pb:
            return WitnessCheck(None, f"grasp change {i} between different poses")
        elif not ck.transit(pa, ga, gb).valid:
            return WitnessCheck(None, f"walk {i} (grasp {ga} -> {gb}) not found")
    plan = path_to_plan(scene, ck, states, extra={"planner": "witness"})
    rep = check_plan(plan, scene)
    if not rep.ok:
        return WitnessCheck(None, "plan check: " + "; ".join(rep.problems[:3]))
    return WitnessCheck(plan)

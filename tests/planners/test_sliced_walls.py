"""A floor plans the same however its walls are cut into boxes (the world merges them)."""

from __future__ import annotations

import dataclasses

from factories import sliced

from pivot_ompl.api import plan
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.planfile import Plan, TransferPhase
from pivot_ompl.validity.collision import CollisionWorld


def _summary(p: Plan) -> list[tuple]:
    """Per phase: a transfer's grasp, pivots and end pose (to 1e-6 m); a regrasp's grasps."""
    return [(ph.grasp, len(ph.steps), tuple(round(v, 6) for v in ph.steps[-1].object))
            if isinstance(ph, TransferPhase) and ph.steps
            else (ph.grasp, 0) if isinstance(ph, TransferPhase)
            else (ph.from_grasp, ph.to_grasp, len(ph.robot_path)) for ph in p.phases]


def test_a_building_with_sliced_walls_plans_as_the_whole_one():
    whole = generate("building", 0, params=GeneratorParams(rooms=2)).scene
    cut = dataclasses.replace(whole, obstacles=tuple(sliced(whole.obstacles, 3)))
    assert len(cut.obstacles) == 3 * len(whole.obstacles)
    assert len(CollisionWorld.from_scene(cut).obstacles) == len(whole.obstacles)
    a = plan(whole, time_limit=60.0, seed=0, bound=False)
    b = plan(cut, time_limit=60.0, seed=0, bound=False)
    assert a.solved and b.solved
    assert _summary(b.plan) == _summary(a.plan)

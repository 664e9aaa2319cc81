"""The duration model's defaults hold for real motions: each plan's estimate is within 5 % of
the duration of the whole-body motion made of it (the demo and two other scenes)."""

from __future__ import annotations

import pytest

from pivot_ompl.api import plan
from pivot_ompl.cost import DurationModel
from pivot_ompl.quality import plan_quality
from pivot_ompl.scene import load_scene
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.durations import duration_breakdown, fit_duration_model, pooled

#: the scenes ``benchmarks/duration_model.py`` fits the defaults to, seed 0
SCENES = ("fig10", "slot", "door")
FIELDS = ("per_transfer", "per_pivot", "per_radian", "per_transit", "per_walk_m")


@pytest.fixture(scope="module")
def motions():
    out = []
    for name in SCENES:
        scene = load_scene(name)
        res = plan(scene, planner="regrasp", time_limit=60.0, seed=0, bound=False)
        assert res.solved, name
        motion, _ = generate_motion(res.plan, walk=scene.walk)
        out.append((name, res.plan, motion))
    return out


@pytest.mark.slow
def test_each_estimate_is_within_five_percent_of_its_motion(motions):
    for name, p, motion in motions:
        estimate = plan_quality(p)["duration_estimate"]
        assert abs(estimate - motion.duration) <= 0.05 * motion.duration, \
            (name, estimate, motion.duration)


@pytest.mark.slow
def test_the_defaults_are_the_fit_to_the_motions(motions):
    """The script's fit, rounded to 0.1 s as the defaults are: regenerate them when the
    generator or the planner changes what the motions take."""
    fitted = fit_duration_model(pooled([duration_breakdown(m, p) for _, p, m in motions]))
    defaults = DurationModel()
    for k in FIELDS:
        assert getattr(fitted, k) == pytest.approx(getattr(defaults, k), abs=0.05 + 1e-9), k

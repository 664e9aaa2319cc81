"""The walk relaxation's answers do not depend on how far it widens its window first."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from factories import shipped

from pivot_ompl.analysis import regrasp_walk
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
from pivot_ompl.generate import generate


@pytest.mark.parametrize("name", ["fig10", "corridor", "building"])
def test_widened_windows_answer_as_the_whole_raster(name, monkeypatch):
    """Regions sampled over the floor, every pair of grasps: the answers with the widened
    windows (:data:`~pivot_ompl.analysis.regrasp_walk.MARGINS`) are those of labelling the
    whole raster at once."""
    scene = shipped(name) if name == "fig10" else generate(name, seed=0).scene
    rng = np.random.default_rng(7)
    x0, y0, x1, y1 = scene.bounds
    width = 2.0 * math.pi / 36
    questions = []
    for _ in range(150):
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        b = int(rng.integers(36))
        k, j = sorted(rng.choice(4, size=2, replace=False).tolist())
        questions.append((shapely.Point(x, y).buffer(float(rng.uniform(0.01, 0.2))),
                          -math.pi + (b + 0.5) * width, k, j))

    def answers() -> list[bool]:
        walk = WalkRelaxation(scene, width=width, tolerance=0.002, clearance=0.01)
        return [walk.may_regrasp(*q) for q in questions]

    widened = answers()
    monkeypatch.setattr(regrasp_walk, "MARGINS", (0,))
    assert widened == answers()
    monkeypatch.setattr(regrasp_walk, "MARGINS", ())
    assert widened == answers()
    assert any(widened) and not all(widened)

"""The walk relaxation's answers do not depend on how far it widens its window first."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from factories import shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import regrasp_walk
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation, centres_within
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


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), block=st.integers(1, 20),
       distance=st.floats(0.0, 0.6), boxes=st.integers(1, 12))
def test_the_centres_within_reach_are_those_asked_one_by_one(seed, block, distance, boxes):
    """Blocks decided at once (far from the region, or inside it) give the answers of every
    cell's centre asked alone."""
    rng = np.random.default_rng(seed)
    raster = FloorRaster((0.0, 0.0, 6.3, 4.1), min_cell=0.1, max_cells=10_000)
    lo = rng.uniform(0.0, 5.0, (boxes, 2))
    parts = shapely.box(lo[:, 0], lo[:, 1], lo[:, 0] + rng.uniform(0.05, 3.0, boxes),
                        lo[:, 1] + rng.uniform(0.05, 3.0, boxes))
    region = shapely.union_all(parts).difference(shapely.Point(3.0, 2.0).buffer(0.7))
    shapely.prepare(region)
    centres = shapely.points(raster.gx.ravel(), raster.gy.ravel())
    alone = shapely.dwithin(region, centres, distance).reshape(raster.shape)
    assert np.array_equal(centres_within(raster, region, distance, block=block), alone)


#: The answers of :func:`test_the_answers_are_those_recorded`'s questions, recorded before the
#: walk relaxation was made cheaper (ba82ba4): 1 "may", 0 "no".
RECORDED = {
    "fig10": "11111101011111111101111111011111111111101111111111111111110000101111111111101101"
             "01000011111101110111011111011011100111111101110111111101110001101111011111111111"
             "0101000100101111100101111011101110011111",
    "building": "10110011011111110101000101111111111101100001111110111011010110001101011111101100"
                "11000011001101010111111111011001101111111111110011101101101000101110111001111111"
                "1011000011111110010001101101010110011111",
}


@pytest.mark.parametrize("name", sorted(RECORDED))
def test_the_answers_are_those_recorded(name):
    """Rectangles of box positions over the floor, any bin and pair of grasps: every answer
    as recorded (the rounds of the guided bound depend on each)."""
    scene = shipped(name) if name == "fig10" else generate(name, seed=0).scene
    rng = np.random.default_rng(11)
    x0, y0, x1, y1 = scene.bounds
    width = 2.0 * math.pi / 36
    walk = WalkRelaxation(scene, width=width, tolerance=0.002, clearance=0.01)
    said = []
    for _ in range(200):
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        b = int(rng.integers(36))
        k, j = sorted(rng.choice(4, size=2, replace=False).tolist())
        region = shapely.box(x, y, x + float(rng.uniform(0.05, 0.8)),
                             y + float(rng.uniform(0.05, 0.8)))
        said.append("1" if walk.may_regrasp(region, -math.pi + (b + 0.5) * width, k, j) else "0")
    assert "".join(said) == RECORDED[name]

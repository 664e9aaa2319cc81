"""The walking floor field's rasterised footprints against the shapely route they replaced.

``reference_fits`` and ``reference_meets_box`` (``benchmarks/walk_field.py``) are the field's
code before the footprints were summed and rasterised in numpy (shapely convex hulls of
vertex differences, each rasterised by ``grid_inside``): the new route must give exactly the
same booleans.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.transit.field import OPEN_YAWS
from tests.factories import ROOT, make_scene, shipped

sys.path.insert(0, str(ROOT / "benchmarks"))
from walk_field import reference_fits, reference_meets_box  # noqa: E402
from walk_queries import scene_copy  # noqa: E402


def _assert_field_as_reference(scene, objs) -> None:
    f = PivotChecker(scene).walker.field.grid
    for k, yaw in enumerate(OPEN_YAWS):
        assert np.array_equal(f.fits_index(k), reference_fits(f, yaw)), (scene.name, k)
    for obj in objs:
        got, want = f.meets_box(obj), reference_meets_box(f, obj)
        assert all(np.array_equal(a, b) for a, b in zip(got, want, strict=True)), obj


@pytest.mark.parametrize("copy", ["", "rot37", "mir20"])
def test_static_field_and_box_footprints_as_before_on_fig10_and_copies(copy):
    scene = scene_copy("fig10", copy)
    _assert_field_as_reference(scene, [scene.start, scene.goal,
                                       (scene.start[0] + 0.37, scene.start[1] - 0.11, 0.3)])


@pytest.mark.parametrize("name", ["slot", "corridor"])
def test_static_field_as_before_on_other_shipped_scenes(name):
    scene = shipped(name)
    _assert_field_as_reference(scene, [scene.goal])


_obstacle = st.one_of(
    st.builds(lambda x, y, w, d, yaw: {"type": "box", "center": [x, y], "size": [w, d],
                                       "yaw": yaw, "height": 1.0},
              st.floats(0.5, 7.5), st.floats(0.5, 5.5), st.floats(0.05, 2.0),
              st.floats(0.05, 2.0),
              st.sampled_from([0.0, math.pi / 2, math.pi / 8, math.pi / 4]) | st.floats(-4, 4)),
    st.builds(lambda x, y, r: {"type": "cylinder", "center": [x, y], "radius": r,
                               "height": 1.0},
              st.floats(0.5, 7.5), st.floats(0.5, 5.5), st.floats(0.05, 0.8)),
    st.builds(lambda x, y, a, b: {"type": "polygon", "height": 1.0,
                                  "points": [[x, y], [x + a, y], [x + a * 0.5, y + b]]},
              st.floats(0.5, 6.5), st.floats(0.5, 4.5), st.floats(0.1, 1.0),
              st.floats(0.1, 1.0)))


@given(obstacles=st.lists(_obstacle, min_size=1, max_size=4),
       obj=st.tuples(st.floats(1.0, 7.0), st.floats(1.0, 5.0), st.floats(-4, 4)))
@settings(max_examples=15, deadline=None)
def test_static_field_and_box_footprints_as_before_on_generated_scenes(obstacles, obj):
    _assert_field_as_reference(make_scene(obstacles=obstacles, start=[0.8, 0.8, 0.0],
                                          goal=[7.2, 5.2, 0.0]), [obj])

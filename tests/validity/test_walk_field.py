"""The walking floor field's rasterised footprints against the shapely route they replaced.

:func:`_reference_fits` and :func:`_reference_meets_box` are the field's code before the
footprints were summed and rasterised in numpy (shapely convex hulls of vertex differences,
each rasterised by ``grid_inside``): the new route must give exactly the same booleans.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.se2 import rectangle_corners
from pivot_ompl.validity.footprints import grid_inside, meeting_hulls
from pivot_ompl.validity.pivot_checker import PivotChecker
from pivot_ompl.validity.walk_field import OPEN_YAWS, FloorField
from pivot_ompl.validity.walk_lattice import HEADING_YAWS
from tests.factories import ROOT, make_scene, shipped

sys.path.insert(0, str(ROOT / "benchmarks"))
from walk_queries import scene_copy  # noqa: E402


def _reference_fits(f: FloorField, yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    rot = np.array([[c, -s], [s, c]])
    corners = f._outline @ rot.T
    b = f.world.bounds
    xs, ys = f._x[:, 0], f._y[0, :]
    ok = ((xs + corners[:, 0].min() > b[0]) & (xs + corners[:, 0].max() < b[2]))[:, None] \
        & ((ys + corners[:, 1].min() > b[1]) & (ys + corners[:, 1].max() < b[3]))[None, :]
    for hull in meeting_hulls(f._pieces, f._grown @ rot.T):
        cols, rows, inside = grid_inside(hull, xs, ys)
        ok[cols, rows] &= ~inside
    return ok


def _reference_meets_box(f: FloorField, obj) -> list[np.ndarray]:
    box = shapely.Polygon(rectangle_corners(obj, f.model.object_size[0], f.model.object_size[1]))
    if f.box_margin > 0:
        box = box.buffer(f.box_margin, quad_segs=4)
    pts = np.asarray(box.exterior.coords)[:-1]
    out = []
    for yaw in HEADING_YAWS:
        c, s = math.cos(yaw), math.sin(yaw)
        body = f._outline @ np.array([[c, -s], [s, c]]).T
        hull = meeting_hulls([pts], body)[0]
        meets = np.zeros((f.nx, f.ny), dtype=bool)
        cols, rows, inside = grid_inside(hull, xs := f._x[:, 0], f._y[0, :])
        assert len(xs) == f.nx
        meets[cols, rows] = inside
        out.append(meets)
    return out


def _assert_field_as_reference(scene, objs) -> None:
    f = PivotChecker(scene).walker.field
    for k, yaw in enumerate(OPEN_YAWS):
        assert np.array_equal(f._fits_index(k), _reference_fits(f, yaw)), (scene.name, k)
    for obj in objs:
        got, want = f._meets_box(obj), _reference_meets_box(f, obj)
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

"""The raster relaxations in the walls' frame: sound, turned back, and sized by the building."""

from __future__ import annotations

import dataclasses
import math

import pytest
import shapely
from corner_factories import tight_corner
from factories import shipped, sliced
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import wall_frame as wall_frame_module
from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.late_proof import framed_turning_place
from pivot_ompl.analysis.regrasp_bound import held_bodies, regrasp_lower_bound
from pivot_ompl.analysis.turning import turning_place
from pivot_ompl.analysis.wall_frame import wall_frame
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.generate.transform import rotate_scene
from pivot_ompl.scene import scene_from_dict
from pivot_ompl.scene.walls import wall_yaw

_EXACT: dict[str, object] = {}


def _row(rooms: int, rotate: bool = False, seed: int = 0):
    return generate("building", seed, params=GeneratorParams(
        rooms=rooms, layout="corridor", rotate=rotate)).scene


def _exact(name: str):
    if name not in _EXACT:
        _EXACT[name] = regrasp_lower_bound(_row(10) if name == "row" else shipped(name))
    return _EXACT[name]


@settings(max_examples=6, deadline=None)
@example(name="row", angle=0.8)  # turned 46 deg: relaxed in the walls' frame
@given(name=st.sampled_from(["slot", "t_junction", "row"]),
       angle=st.floats(-math.pi, math.pi))
def test_a_turned_scene_is_bounded_as_the_scene_itself_never_above_the_exact_bound(name,
                                                                                    angle):
    scene = _row(10) if name == "row" else shipped(name)
    turned = rotate_scene(scene, angle)
    exact = _exact(name)
    got = lower_bound(turned, use_cache=False)
    assert got.solvable == exact.solvable  # every one of them has a plan
    assert got.regrasps is not None and got.regrasps <= exact.regrasps
    # the box moves at least the straight line; no route bound is above a witness plan's
    assert math.dist(scene.start[:2], scene.goal[:2]) <= got.shortest_route + 1e-9
    if wall_frame(turned) is not None:  # relaxed in the walls' frame: as the scene was
        plain = lower_bound(scene, use_cache=False)
        assert got.regrasps == plain.regrasps
        assert got.shortest_route == pytest.approx(plain.shortest_route, abs=0.3)


def test_a_turned_row_of_rooms_is_rastered_over_its_own_extent():
    scene = _row(16, rotate=True, seed=2)
    frame = wall_frame(scene)
    assert frame is not None
    assert frame.yaw == pytest.approx(wall_yaw(scene.obstacles))
    x0, y0, x1, y1 = scene.bounds
    u0, v0, u1, v1 = frame.scene.bounds
    assert (u1 - u0) * (v1 - v0) < 0.5 * (x1 - x0) * (y1 - y0)
    # start, goal and every wall of the row lie inside the turned bounds
    box = shapely.box(u0, v0, u1, v1)
    for pose in (frame.scene.start, frame.scene.goal):
        assert box.contains(shapely.Point(pose[:2]))
    reach = max(p.reach for g in (0, 1) for p in held_bodies(scene, g))
    assert min(u1 - u0, v1 - v0) > 2.0 * reach
    # turned back, the turned start is the scene's
    assert frame.point_out(frame.scene.start[:2]) == pytest.approx(scene.start[:2])
    assert frame.scene.start[2] == pytest.approx(scene.start[2] - frame.yaw)
    # and the bound is the same as the unturned row's (sound and no weaker)
    assert lower_bound(scene, use_cache=False).regrasps == \
        lower_bound(_row(16, seed=2), use_cache=False).regrasps


def test_floors_square_to_the_axes_are_relaxed_as_they_are():
    for name in ("fig10", "slot", "door", "corridor"):
        assert wall_frame(shipped(name)) is None


@pytest.mark.parametrize("seed", [6, 16])  # turned 45 and 35 deg off its walls
def test_the_place_found_in_the_walls_frame_is_turned_back(seed, monkeypatch):
    # walls on whole decimetres, turned: the raster places the corner only in their frame
    doc, corner = tight_corner(seed, widths=(0.9, 0.9), whole=True)
    scene = scene_from_dict(doc, source="<test>")
    monkeypatch.setattr(wall_frame_module, "WORTH", math.inf)  # a small L: turned all the same
    assert wall_frame(scene) is not None
    place = framed_turning_place(scene)
    exact = turning_place(scene)
    assert place is not None and exact is not None
    assert math.dist(place.center, corner) < 1.0
    assert place.reason.startswith("no plan: the box cannot turn at")
    for framed, polygons in ((place.from_start, exact.from_start),
                             (place.to_goal, exact.to_goal)):
        assert -180.0 <= framed[0] < 180.0 and framed[0] <= framed[1]
        # the same arc of yaws as the exact polygons', to a bin
        mid = 0.5 * (framed[0] + framed[1]) - 0.5 * (polygons[0] + polygons[1])
        assert abs((mid + 180.0) % 360.0 - 180.0) < 10.0


def _touching_hall(pieces: int):
    """A 30 x 3 m hall in 40 x 40 m bounds, its 0.2 m walls cut in ``pieces`` that touch end
    to end, the end walls touching the long walls' faces: closed only where they touch."""
    length, width, t, c = 30.0, 3.0, 0.2, 20.0
    walls = [{"type": "box", "center": [c, c + s * 0.5 * (width + t)], "size": [length + 2 * t, t],
              "yaw": 0.0, "height": 2.0} for s in (-1, 1)]
    walls += [{"type": "box", "center": [c + s * 0.5 * (length + t), c], "size": [t, width],
               "yaw": 0.0, "height": 2.0} for s in (-1, 1)]
    doc = {"name": "touching", "bounds": [0.0, 0.0, 40.0, 40.0],
           "object": {"size": [0.8, 0.6, 1.3]}, "start": [7.0, c, 0.0], "goal": [33.0, c, 0.0],
           "obstacles": walls}
    scene = scene_from_dict(doc, source="<test>")
    return dataclasses.replace(scene, obstacles=tuple(sliced(scene.obstacles, pieces)))


@settings(max_examples=25, deadline=None)
@example(pieces=1, angle=0.3)
@example(pieces=4, angle=-2.3)
@given(pieces=st.integers(1, 5), angle=st.floats(-math.pi, math.pi))
def test_walls_that_touch_edge_to_edge_give_the_frame_of_the_angle_they_are_turned_by(pieces,
                                                                                    angle):
    quarter = 0.5 * math.pi
    off_axes = (angle + 0.25 * math.pi) % quarter - 0.25 * math.pi  # in [-pi/4, pi/4)
    assume(abs(off_axes) > 1e-3)
    scene = rotate_scene(_touching_hall(pieces), angle)
    frame = wall_frame(scene)
    assert frame is not None
    assert (frame.yaw - off_axes + 0.25 * math.pi) % quarter - 0.25 * math.pi == \
        pytest.approx(0.0, abs=1e-6)
    # the floor is the hall's, not the bounds' round it: the turned bounds hold the hall and
    # the assembly's reach round it, no more
    u0, v0, u1, v1 = frame.scene.bounds
    reach = max(p.reach for g in (0, 1) for p in held_bodies(scene, g))
    longest, shortest = max(u1 - u0, v1 - v0), min(u1 - u0, v1 - v0)
    assert longest < 30.0 + 2.0 * (reach + 1.0) + 1.0
    assert shortest < 3.0 + 2.0 * (reach + 1.0) + 1.0
    box = shapely.box(u0, v0, u1, v1)
    for pose in (frame.scene.start, frame.scene.goal):
        assert box.contains(shapely.Point(pose[:2]))


@settings(max_examples=30, deadline=None)
@given(yaw=st.floats(-3.0, 3.0), extra=st.floats(0.05, 0.7))
def test_the_aligned_share_is_the_length_along_a_direction(yaw, extra):
    from pivot_ompl.scene import BoxObstacle, CylinderObstacle
    from pivot_ompl.scene.walls import aligned_share

    along = [BoxObstacle((0.0, 0.0), (4.0, 1.0), yaw, 1.0),
             BoxObstacle((5.0, 5.0), (2.0, 2.0), yaw + 0.5 * math.pi, 1.0)]
    off = BoxObstacle((9.0, 0.0), (3.0, 3.0), yaw + extra, 1.0)  # 12 m of 30 off the axes
    disk = CylinderObstacle((0.0, 9.0), 1.0, 1.0)
    assert aligned_share(along + [disk], yaw) == pytest.approx(1.0)
    assert aligned_share(along + [off], yaw) == pytest.approx(18.0 / 30.0)
    assert aligned_share([disk], yaw) == 0.0

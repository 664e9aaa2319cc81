"""ROS map_server maps imported as scenes: the frame, the cells, the modes, the errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from map_factories import FREE, OCCUPIED, UNKNOWN, room, write_map

import pivot_ompl
from pivot_ompl import MapCleaning, MapError, import_map, scene_from_map
from pivot_ompl.maps.rectangles import cell_rectangles


def covered(scene, x: float, y: float) -> int:
    """How many of the scene's boxes hold the point (x, y) (boxes of any yaw)."""
    n = 0
    for o in scene.obstacles:
        c, s = math.cos(o.yaw), math.sin(o.yaw)
        dx, dy = x - o.center[0], y - o.center[1]
        n += abs(c * dx + s * dy) < 0.5 * o.size[0] and abs(-s * dx + c * dy) < 0.5 * o.size[1]
    return n


@settings(max_examples=60, deadline=None)
@given(arrays(bool, st.tuples(st.integers(1, 25), st.integers(1, 25))))
def test_rectangles_cover_exactly_the_blocked_cells_without_overlap(blocked):
    rects = cell_rectangles(blocked)
    painted = np.zeros(blocked.shape, dtype=np.int64)
    for r0, c0, r1, c1 in rects:
        assert r0 < r1 and c0 < c1
        painted[r0:r1, c0:c1] += 1
    assert np.array_equal(painted, blocked.astype(np.int64))


def test_a_wall_is_one_box_however_long():
    blocked = np.zeros((50, 300), dtype=bool)
    blocked[10:12, :] = True
    blocked[:, 100:103] = True
    assert len(cell_rectangles(blocked)) == 3


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.05, 0.1, 0.25]),
       st.floats(-50, 50), st.floats(-50, 50))
def test_every_cell_lands_where_the_map_frame_puts_it(tmp_path_factory, seed, res, ox, oy):
    rng = np.random.default_rng(seed)
    px = room(30, 20)
    inner = rng.random((14, 24)) < 0.15
    px[3:-3, 3:-3][inner] = rng.choice([OCCUPIED, UNKNOWN], size=int(inner.sum()))
    px[9:11, 14:16] = FREE  # the poses' cells stay free
    folder = tmp_path_factory.mktemp("map")
    path = write_map(folder, px, resolution=res, origin=(ox, oy, 0.0))
    h = px.shape[0]
    centre = (ox + 15 * res, oy + (h - 10) * res)  # the corner of the four free cells
    result = import_map(path, start=(*centre, 0.0), goal=(*centre, 0.0), box=(0.05, 0.05, 1))
    scene = result.scene
    # the floor area: the free cells' bounding rectangle (inside the walls)
    assert scene.bounds == pytest.approx((ox + 3 * res, oy + 3 * res, ox + 27 * res,
                                          oy + (h - 3) * res), abs=1e-9)
    for r in range(3, h - 3):
        for c in range(3, 27):
            x, y = ox + (c + 0.5) * res, oy + (h - r - 0.5) * res  # row 0 is the top
            assert covered(scene, x, y) == (0 if px[r, c] == FREE else 1), (r, c)
    assert result.blocked_cells == int(np.count_nonzero(px[3:-3, 3:-3] != FREE))


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(-math.pi, math.pi), st.floats(-20, 20),
       st.floats(-20, 20))
def test_a_rotated_map_turns_every_cell_and_blocks_what_the_image_does_not_cover(
        tmp_path_factory, seed, yaw, ox, oy):
    rng = np.random.default_rng(seed)
    res = 0.1
    px = room(30, 20)
    inner = rng.random((14, 24)) < 0.15
    px[3:-3, 3:-3][inner] = OCCUPIED
    px[9:11, 14:16] = FREE
    folder = tmp_path_factory.mktemp("map")
    path = write_map(folder, px, resolution=res, origin=(ox, oy, yaw))
    h = px.shape[0]
    c, s = math.cos(yaw), math.sin(yaw)

    def to_map(u, v):  # image frame (m) -> map frame
        return ox + c * u - s * v, oy + s * u + c * v

    centre = to_map(15 * res, (h - 10) * res)
    scene = scene_from_map(path, start=(*centre, 0.0), goal=(*centre, 0.0),
                           box=(0.05, 0.05, 1))
    for r in range(3, h - 3):
        for col in range(3, 27):
            x, y = to_map((col + 0.5) * res, (h - r - 0.5) * res)
            assert (covered(scene, x, y) == 0) == (px[r, col] == FREE), (r, col)
    b = scene.bounds
    for x, y in rng.uniform((b[0], b[1]), (b[2], b[3]), size=(300, 2)):
        u, v = c * (x - ox) + s * (y - oy), -s * (x - ox) + c * (y - oy)  # map -> image
        col, r = math.floor(u / res), h - 1 - math.floor(v / res)
        inside = 3 <= r < h - 3 and 3 <= col < 27
        if abs(u / res - round(u / res)) < 1e-6 or abs(v / res - round(v / res)) < 1e-6:
            continue  # on a cell edge
        assert (covered(scene, x, y) == 0) == (inside and px[r, col] == FREE), (x, y)


@pytest.mark.parametrize("value, free", [(254, True), (206, True), (205, False), (100, False),
                                         (0, False)])
def test_trinary_thresholds_follow_map_server(tmp_path, value, free):
    # p = (255 - v) / 255 is free below free_thresh 0.196: v = 206 gives 0.192, 205 0.196+
    px = room()
    px[10:14, 10:14] = value
    path = write_map(tmp_path, px)
    scene = scene_from_map(path, start=(3.0, 2.0, 0.0), goal=(3.0, 2.0, 0.0))
    assert covered(scene, 1.2, 2.8) == (0 if free else 1)


def test_negate_swaps_black_and_white(tmp_path):
    px = 255 - room()
    path = write_map(tmp_path, px, extra="")
    path.write_text(path.read_text().replace("negate: 0", "negate: 1"))
    scene = scene_from_map(path, start=(3.0, 2.0, 0.0), goal=(3.0, 2.0, 0.0))
    assert scene.bounds == pytest.approx((0.3, 0.3, 5.7, 3.7))
    assert covered(scene, 3.0, 2.0) == 0


def test_ascii_pgm_png_and_colour_png_read_alike(tmp_path):
    px = room()
    px[15:20, 20:40] = OCCUPIED
    scenes = []
    for i, fmt in enumerate(("pgm", "p2", "png")):
        folder = tmp_path / str(i)
        folder.mkdir()
        scenes.append(scene_from_map(write_map(folder, px, fmt=fmt), start=(1, 1, 0),
                                     goal=(5, 3, 0)).obstacles)
    rgb = np.repeat(px[:, :, None], 3, axis=2)
    folder = tmp_path / "rgb"
    folder.mkdir()
    scenes.append(scene_from_map(write_map(folder, rgb, fmt="png"), start=(1, 1, 0),
                                 goal=(5, 3, 0)).obstacles)
    assert all(s == scenes[0] for s in scenes)


def test_scale_mode_makes_transparent_pixels_unknown(tmp_path):
    px = np.repeat(room()[:, :, None], 4, axis=2)
    px[:, :, 3] = 255
    px[10:14, 10:14, 3] = 0
    path = write_map(tmp_path, px, fmt="png", extra="mode: scale\n")
    assert covered(scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0)), 1.2, 2.8) == 1
    path.write_text(path.read_text().replace("mode: scale", "mode: trinary"))
    assert covered(scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0)), 1.2, 2.8) == 0


def test_raw_mode_reads_percent_occupancy(tmp_path):
    px = np.zeros((40, 60), dtype=np.uint8)  # 0 % occupied: free
    px[0, :] = 255  # ROS's -1: unknown
    px[10:14, 10:14] = 100
    path = write_map(tmp_path, px, extra="mode: raw\n")
    scene = scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0))
    assert covered(scene, 1.2, 2.8) == 1 and covered(scene, 3.0, 2.0) == 0
    assert scene.bounds[3] == pytest.approx(3.9)


def test_specks_and_streaks_are_cleaned_as_documented(tmp_path):
    px = room(80, 60)
    px[20:22, 20:22] = OCCUPIED  # a speck of four cells (0.04 m2)
    px[30:36, 30:36] = OCCUPIED  # a pillar of 0.36 m2
    px[3:12, 50] = OCCUPIED  # a streak hanging off the top wall, 9 cells
    px[3:-3, 65] = OCCUPIED  # a thin wall from top to bottom wall: stays
    px[9:13, 38:43] = OCCUPIED  # a block held by a short thin wall (6 cells) from the top
    px[3:9, 40] = OCCUPIED  # wall: it touches at two places and stays
    px[40, 3:20] = OCCUPIED  # a line of 17 cells (1.7 m) off the left wall: too long, stays
    path = write_map(tmp_path, px)
    pose = (2.5, 2.5, 0.0)
    plain = import_map(path, start=pose, goal=pose)
    cleaned = import_map(path, start=pose, goal=pose,
                         cleaning=MapCleaning(specks=0.05, streaks=1.0))
    assert cleaned.cleaned.specks == 1 and cleaned.cleaned.speck_cells == 4
    assert cleaned.cleaned.streaks == 1 and cleaned.cleaned.streak_cells == 9
    assert cleaned.blocked_cells == plain.blocked_cells - 13
    scene = cleaned.scene
    h = px.shape[0]

    def at(r, c):
        return covered(scene, (c + 0.5) * 0.1, (h - r - 0.5) * 0.1)

    assert at(20, 20) == 0 and at(5, 50) == 0  # speck and streak gone
    assert at(33, 33) == 1 and at(30, 65) == 1 and at(40, 10) == 1  # pillar, walls kept
    assert at(5, 40) == 1
    assert "specks of at most 0.05 m2 made free (1 groups, 4 cells)" in cleaned.header


def test_gaps_close_one_cell_rays_and_the_floor_area_shrinks_to_what_remains(tmp_path):
    px = room()
    px[0:3, 30] = FREE  # a ray through the top wall to the image's edge
    px[10, 10:20] = OCCUPIED
    px[11, 10:20] = FREE
    px[12, 10:20] = OCCUPIED  # a one-cell free sliver between two walls
    path = write_map(tmp_path, px)
    pose = (3.0, 2.0, 0.0)
    plain = import_map(path, start=pose, goal=pose)
    assert plain.scene.bounds[3] == pytest.approx(4.0)
    cleaned = import_map(path, start=pose, goal=pose, cleaning=MapCleaning(gaps=0.2))
    assert cleaned.scene.bounds == pytest.approx((0.3, 0.3, 5.7, 3.7))
    assert cleaned.cleaned.gap_cells == 3 + 10
    assert covered(cleaned.scene, 1.45, 2.85) == 1 and covered(plain.scene, 1.45, 2.85) == 0
    assert "free gaps narrower than 0.2 m made blocked (13 cells)" in cleaned.header
    # below two cells a side nothing is done
    same = import_map(path, start=pose, goal=pose, cleaning=MapCleaning(gaps=0.15))
    assert same.cleaned.gap_cells == 0 and same.scene.bounds == plain.scene.bounds


@pytest.mark.parametrize("edit, field", [
    (lambda t: t.replace("image: map.pgm", "image: nowhere.pgm"), "image"),
    (lambda t: t.replace("free_thresh: 0.196", "free_thresh: 0.9"), "free_thresh"),
    (lambda t: t.replace("occupied_thresh: 0.65", "occupied_thresh: 1.5"), "occupied_thresh"),
    (lambda t: t.replace("negate: 0", "negate: 2"), "negate"),
    (lambda t: t.replace("resolution: 0.1", "resolution: fine"), "resolution"),
    (lambda t: t.replace("resolution: 0.1", "resolution: 0"), "resolution"),
    (lambda t: t.replace("origin: [0.0, 0.0, 0.0]", "origin: [.nan, 0, 0]"), "origin[0]"),
    (lambda t: t.replace("origin: [0.0, 0.0, 0.0]", "origin: [0, 0, .inf]"), "origin[2]"),
    (lambda t: t.replace("origin: [0.0, 0.0, 0.0]", "origin: [2.0e4, 0, 0]"), "origin[0]"),
    (lambda t: t.replace("origin: [0.0, 0.0, 0.0]", "origin: 3"), "origin"),
    (lambda t: t + "mode: fancy\n", "mode"),
    (lambda t: t.replace("image: map.pgm\n", ""), "image"),
    (lambda t: "- a list\n", "<document>"),
])
def test_a_bad_map_names_its_field(tmp_path, edit, field):
    path = write_map(tmp_path, room())
    path.write_text(edit(path.read_text()))
    with pytest.raises(MapError) as e:
        scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0))
    assert e.value.field == field


def test_an_image_that_is_not_one_or_too_large_is_refused_before_decoding(tmp_path):
    path = write_map(tmp_path, room())
    (tmp_path / "map.pgm").write_bytes(b"P5\n9000 9000\n255\n" + b"\0" * 16)
    with pytest.raises(MapError, match="larger than") as e:
        scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0))
    assert e.value.field == "image"
    (tmp_path / "map.pgm").write_bytes(b"not an image")
    with pytest.raises(MapError, match="cannot be read as an image"):
        scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0))


def test_a_16_bit_image_is_refused_naming_its_mode(tmp_path):
    path = write_map(tmp_path, room().astype(np.uint16) * 257, fmt="png")
    with pytest.raises(MapError, match="8-bit") as e:
        scene_from_map(path, start=(3, 2, 0), goal=(3, 2, 0))
    assert e.value.field == "image"


@pytest.mark.parametrize("start, message", [((0.35, 2.0, 0.0), "leaves the map's free area"),
                                            ((40.0, 2.0, 0.0), "leaves the map's free area"),
                                            ((1.2, 1.25, 0.0), "overlaps an occupied")])
def test_a_pose_off_the_floor_is_refused(tmp_path, start, message):
    px = room()
    px[25:30, 10:14] = OCCUPIED
    path = write_map(tmp_path, px)
    with pytest.raises(MapError, match=message) as e:
        scene_from_map(path, start=start, goal=(3, 2, 0))
    assert e.value.field == "start"


def test_the_public_api_exports_the_importer():
    assert pivot_ompl.scene_from_map is scene_from_map
    assert "scene_from_map" in pivot_ompl.__all__ and "MapError" in pivot_ompl.__all__
    assert math.isfinite(pivot_ompl.MapCleaning().specks)

"""The raster regrasp bound: sound (never above the exact polygons' bound) and fast."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from cover_sampling import near_contact_states_covered
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.bound_levels import scaled_lower_bound
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.raster_bound import raster_lower_bound
from pivot_ompl.analysis.raster_cover import Dilation, lattice_rows, raster_cover
from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import generate, rotate_scene

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cell=st.sampled_from([0.05, 0.1, 0.13]))
def test_a_blocked_cell_is_blocked_at_every_point(seed, cell):
    """Every point of a blocked cell puts the body on an obstacle cell (the dilation's claim)."""
    rng = np.random.default_rng(seed)
    raster = FloorRaster((0.0, 0.0, 3.0, 2.0), min_cell=cell, max_cells=10**6)
    obstacles = rng.random(raster.shape) < 0.03
    body = shapely.MultiPoint(rng.normal(0.0, 0.25, (6, 2))).convex_hull
    if body.geom_type != "Polygon":
        return
    points = np.asarray(body.exterior.coords)[:-1]
    blocked = Dilation(obstacles, 20).blocked(lattice_rows(points, raster.cell))
    (x0, y0), h = raster.origin, raster.cell
    solid = shapely.union_all([shapely.box(x0 + i * h, y0 + j * h, x0 + (i + 1) * h,
                                           y0 + (j + 1) * h) for i, j in zip(*np.nonzero(obstacles),
                                                                             strict=True)])
    ii, jj = np.nonzero(blocked)
    for k in rng.choice(len(ii), size=min(30, len(ii)), replace=False) if len(ii) else []:
        p = (x0 + (ii[k] + rng.random()) * h, y0 + (jj[k] + rng.random()) * h)
        placed = shapely.affinity.translate(body, *p)
        assert placed.intersects(solid), (p, ii[k], jj[k])
    # and the dilation is complete: a cell whose centre-offset body holds an obstacle centre
    centres = [(x0 + (i + 0.5) * h, y0 + (j + 0.5) * h) for i, j in zip(*np.nonzero(obstacles),
                                                                          strict=True)]
    for i, j in zip(*np.nonzero(~blocked), strict=True):
        if (i + j) % 7:
            continue
        placed = shapely.affinity.translate(body, x0 + (i + 0.5) * h, y0 + (j + 0.5) * h)
        shrunk = placed.buffer(-1e-6)
        assert not any(shrunk.contains(shapely.Point(c)) for c in centres)


@pytest.mark.parametrize("turn", [None, 0.7])
def test_the_raster_cover_holds_every_valid_state(turn):
    """Sampled valid states, many within 3 cm of contact, all lie in free cells."""
    scene = shipped("fig10") if turn is None else rotate_scene(shipped("fig10"), turn)
    cover = raster_cover(scene, cell=0.1)
    assert cover is not None
    near = near_contact_states_covered(scene, cover, samples=2500, seed=3)
    assert near > 20


def test_the_raster_cover_excludes_most_colliding_states():
    scene = shipped("fig10")
    cover = raster_cover(scene, cell=0.05)
    assert cover is not None
    ck = PivotChecker(scene, seed=0)
    rng = np.random.default_rng(4)
    hit = out = 0
    for _ in range(1500):
        q = (float(rng.uniform(0, 12)), float(rng.uniform(0, 7)), float(rng.uniform(-3, 3)))
        if not ck.world.box_in_bounds(q) or ck.world.box_distance(q) > 0:
            continue
        hit += 1
        out += not any(cover.covers(q, g) for g in range(4))
    assert hit > 100 and out > 0.7 * hit


def _case(seed: int):
    rng = np.random.default_rng(seed)
    family = ("walls", "corridor", "clutter", "building")[seed % 4]
    scene = generate(family, seed=int(rng.integers(0, 50))).scene
    return rotate_scene(scene, float(rng.uniform(-math.pi, math.pi)))


@pytest.mark.parametrize("seed", range(6))
def test_the_raster_bound_never_exceeds_the_exact_one(seed):
    """Generated scenes, turned by a random angle: raster <= polygons, routes too."""
    scene = _case(seed)
    exact = regrasp_lower_bound(scene)
    for cell in (0.05, 0.1):
        fast = raster_lower_bound(scene, cell=cell)
        assert fast.solvable is not None
        if exact.solvable:
            assert fast.solvable and fast.regrasps <= exact.regrasps
            assert fast.shortest_route <= exact.shortest_route + 1e-6 or \
                fast.shortest_route <= math.dist(scene.start[:2], scene.goal[:2]) + 1e-9
        elif fast.solvable is False:  # a raster proof of "no plan" is one of the polygons'
            assert exact.solvable is False


@pytest.mark.parametrize(("name", "exact"), [("fig10", 2), ("slot", 1), ("door", 1)])
def test_coarse_to_fine_equals_the_exact_bound_on_the_shipped_scenes(name, exact):
    b = scaled_lower_bound(shipped(name))
    assert b.regrasps == exact and b.exhaustive


def test_the_raster_alone_proves_a_walled_in_goal_unreachable():
    b = raster_lower_bound(shipped("enclosed"))
    assert b.solvable is False and b.regrasps is None and not b.exhaustive
    assert scaled_lower_bound(shipped("enclosed")).solvable is False


def test_a_plan_met_by_the_raster_needs_no_polygons():
    """The target met (an open floor, 0 regrasps): the polygons are not run."""
    b = scaled_lower_bound(make_scene(), target=0)
    assert b.regrasps == 0 and not b.exhaustive


def test_stopping_gives_unknown():
    b = raster_lower_bound(shipped("fig10"), should_stop=lambda: True)
    assert b.solvable is None and b.regrasps is None


def test_finer_rasters_run_when_the_polygons_do_not_fit():
    """fig10 with a 1 s budget: its polygons (about 1.5 s estimated) give way to 5 cm cells."""
    coarse = raster_lower_bound(shipped("fig10"))
    b = scaled_lower_bound(shipped("fig10"), refine_seconds=1.0)
    assert not b.exhaustive and b.bins > coarse.bins
    assert b.regrasps is not None and coarse.regrasps <= b.regrasps <= 2



@settings(max_examples=60, deadline=None)
@given(i=st.integers(0, 150), j=st.integers(0, 150), w=st.integers(1, 40), d=st.integers(1, 40))
def test_a_box_on_cell_edges_fills_its_cells(i, j, w, d):
    """A map's box (edges on the pixel grid, so on cell edges): every cell of it is an obstacle
    cell, whatever the floating point of its centre and size."""
    from pivot_ompl.analysis.raster_cover import obstacle_cells
    from pivot_ompl.scene import BoxObstacle
    from pivot_ompl.validity.footprints import obstacle_pieces

    h = 0.05
    raster = FloorRaster((0.0, 0.0, 10.0, 10.0), min_cell=h, max_cells=10**6)
    box = BoxObstacle(center=((i + 0.5 * w) * h, (j + 0.5 * d) * h), size=(w * h, d * h),
                      yaw=0.0, height=1.0)
    cells = obstacle_cells(raster, obstacle_pieces([box]))
    assert cells.sum() == w * d
    assert cells[i:i + w, j:j + d].all()


def test_a_real_map_plan_carries_its_proven_minimum_within_seconds(tmp_path):
    """The TurtleBot3 arena (157 boxes): its polygons are estimated at about 18 s, so the
    rasters alone prove the 4 regrasps the exhaustive relaxation proves (13 s on main), well
    inside a plan's limit."""
    import time

    from factories import benchmark_script

    from pivot_ompl.analysis.bound_cache import clear_memory
    from pivot_ompl.analysis.plan_bounds import plan_bounds
    from pivot_ompl.scene import load_scene

    mod = benchmark_script("buildings")
    m = next(m for m in mod.CORPUS if m.name == "turtlebot3_world")
    scene = load_scene(mod.import_corpus_map(m, tmp_path)["scene"])
    clear_memory()
    end = time.monotonic() + 30.0
    t0 = time.perf_counter()
    regrasps, route = plan_bounds(scene, 4, should_stop=lambda: time.monotonic() > end)
    assert regrasps == 4 and route is not None and route >= 3.8
    assert time.perf_counter() - t0 < 15.0

"""The late proof's relaxations handed to the plan's regrasp bound (built once, same bound)."""

from __future__ import annotations

import dataclasses

import pytest
from factories import shipped

import pivot_ompl.analysis.bound_levels as bound_levels
import pivot_ompl.analysis.regrasp_bound as regrasp_bound
import pivot_ompl.analysis.relaxation_handoff as relaxation_handoff
from pivot_ompl.analysis.bound_levels import CELLS, scaled_lower_bound
from pivot_ompl.analysis.late_proof import LateProof
from pivot_ompl.analysis.plan_bounds import plan_bounds
from pivot_ompl.analysis.regrasp_bound import RESOLUTION
from pivot_ompl.analysis.relaxation_handoff import take_coarse, take_exact
from pivot_ompl.analysis.turning import turning_place
from pivot_ompl.analysis.turning_raster import raster_turning_place
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE


def _own(name: str, grow: float) -> Scene:
    """A shipped scene with its bounds grown by ``grow`` m: a geometry no other test keeps."""
    s = shipped(name)
    return dataclasses.replace(s, bounds=(*s.bounds[:3], s.bounds[3] + grow))


def _taken(scene: Scene):
    return take_coarse(scene, cell=CELLS[0], clearance=KEEP_CLEARANCE)


def _exact(scene: Scene):
    return take_exact(scene, resolution=RESOLUTION, clearance=KEEP_CLEARANCE)


def _fields(b):
    return b.regrasps, b.solvable, b.shortest_route, b.pieces, b.bins, b.exhaustive


def _never(*args, **kwargs):
    raise AssertionError("the relaxation was built again")


@pytest.mark.parametrize("name", ["slot", "door"])
def test_the_bound_reads_the_late_proofs_raster_once_and_bounds_as_without_it(
        name, monkeypatch):
    scene = _own(name, 0.0171)
    built = scaled_lower_bound(scene, refine_seconds=0.0)  # the coarsest raster, its own
    assert _taken(scene) is None  # the bound keeps nothing
    assert raster_turning_place(scene, cell=CELLS[0], keep=True) is None  # joined: kept

    monkeypatch.setattr(bound_levels, "raster_cover", _never)
    handed = scaled_lower_bound(scene, refine_seconds=0.0)
    assert _fields(handed) == _fields(built) and built.solvable
    assert _taken(scene) is None  # handed over once, then forgotten


def test_the_late_proof_keeps_its_raster_when_it_proves_nothing():
    scene = _own("slot", 0.0172)
    late = LateProof(scene, begin=0.0, end=1e-3, clock=lambda: 0.0)  # the raster, not polygons
    assert late() is False and late.proof is None
    kept = _taken(scene)
    assert kept is not None
    cover, graph = kept
    assert cover.raster.cell >= CELLS[0] and graph.total > 0
    assert raster_turning_place(scene, cell=CELLS[0]) is None and _taken(scene) is None


def test_a_large_cover_is_not_kept(monkeypatch):
    monkeypatch.setattr(relaxation_handoff, "MAX_KEPT_CELLS", 10)
    scene = _own("slot", 0.0173)
    assert raster_turning_place(scene, cell=CELLS[0], keep=True) is None
    assert _taken(scene) is None


@pytest.mark.parametrize("name", ["slot", "door"])
def test_the_bound_reads_the_late_proofs_polygons_once_and_bounds_as_without_them(
        name, monkeypatch):
    scene = _own(name, 0.0174)
    built = scaled_lower_bound(scene)  # the coarsest raster, then the polygons: its own
    assert built.exhaustive and built.solvable and _exact(scene) is None
    assert turning_place(scene, keep=True) is None  # joined: kept
    monkeypatch.setattr(regrasp_bound, "free_cover", _never)
    monkeypatch.setattr(regrasp_bound, "cover_graph", _never)
    handed = scaled_lower_bound(scene)
    assert _fields(handed) == _fields(built)
    assert _exact(scene) is None  # handed over once, then forgotten


def test_the_late_proof_keeps_its_polygons_when_they_prove_nothing():
    scene = _own("slot", 0.0175)
    late = LateProof(scene, begin=0.0, end=1e9, clock=lambda: 0.0)  # the polygons fit
    assert late() is False and late.proof is None
    kept = _exact(scene)
    assert kept is not None
    cover, graph = kept
    assert len(graph.nodes) > 0 and cover.bins >= 8
    assert turning_place(scene) is None and _exact(scene) is None  # kept only when asked


def test_a_large_polygon_cover_is_not_kept(monkeypatch):
    monkeypatch.setattr(relaxation_handoff, "MAX_KEPT_PIECES", 10)
    scene = _own("slot", 0.0176)
    assert turning_place(scene, keep=True) is None
    assert _exact(scene) is None


def test_a_plan_without_regrasps_forgets_what_the_late_proof_kept():
    scene = _own("slot", 0.0177)
    assert raster_turning_place(scene, cell=CELLS[0], keep=True) is None
    assert turning_place(scene, keep=True) is None
    assert plan_bounds(scene, 0)[0] == 0  # its bound needs no relaxation
    assert _taken(scene) is None and _exact(scene) is None


def test_a_raster_of_other_cells_is_not_handed_as_the_bounds():
    scene = _own("slot", 0.0178)
    assert raster_turning_place(scene, cell=2 * CELLS[0], keep=True) is None
    assert _taken(scene) is None

"""The late proof's coarse raster handed to the plan's regrasp bound (built once, same bound)."""

from __future__ import annotations

import dataclasses

import pytest
from factories import shipped

import pivot_ompl.analysis.bound_levels as bound_levels
import pivot_ompl.analysis.coarse_handoff as coarse_handoff
from pivot_ompl.analysis.bound_levels import CELLS, scaled_lower_bound
from pivot_ompl.analysis.coarse_handoff import take_coarse
from pivot_ompl.analysis.late_proof import LateProof
from pivot_ompl.analysis.turning_raster import raster_turning_place
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE


def _own(name: str, grow: float) -> Scene:
    """A shipped scene with its bounds grown by ``grow`` m: a geometry no other test keeps."""
    s = shipped(name)
    return dataclasses.replace(s, bounds=(*s.bounds[:3], s.bounds[3] + grow))


def _taken(scene: Scene):
    return take_coarse(scene, cell=CELLS[0], clearance=KEEP_CLEARANCE)


def _fields(b):
    return b.regrasps, b.solvable, b.shortest_route, b.pieces, b.bins


@pytest.mark.parametrize("name", ["slot", "door"])
def test_the_bound_reads_the_late_proofs_raster_once_and_bounds_as_without_it(
        name, monkeypatch):
    scene = _own(name, 0.0171)
    built = scaled_lower_bound(scene, refine_seconds=0.0)  # the coarsest raster, its own
    assert _taken(scene) is None  # the bound keeps nothing
    assert raster_turning_place(scene, cell=CELLS[0], keep=True) is None  # joined: kept

    def no_cover(*args, **kwargs):
        raise AssertionError("the raster cover was built again")

    monkeypatch.setattr(bound_levels, "raster_cover", no_cover)
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
    monkeypatch.setattr(coarse_handoff, "MAX_KEPT_CELLS", 10)
    scene = _own("slot", 0.0173)
    assert raster_turning_place(scene, cell=CELLS[0], keep=True) is None
    assert _taken(scene) is None

"""The assembly field is rasterised once per scene: later plans' lattices share it, and the
shared grids are those a fresh field computes (plans do not change)."""

from __future__ import annotations

import dataclasses

import numpy as np
from factories import shipped, two_rooms

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.shared_fields import assembly_field
from pivot_ompl.validity.assembly_field import FIELD_YAWS, AssemblyField


def test_lattices_of_one_scene_share_the_field_with_a_fresh_fields_grids():
    scene = shipped("slot")
    first = TransferLattice(PivotChecker(scene, seed=0), CostModel())
    again = TransferLattice(PivotChecker(shipped("slot"), seed=1), CostModel())
    assert again.field is first.field  # another checker, another Scene object, same geometry
    ck = PivotChecker(scene, seed=2)
    fresh = AssemblyField(ck.model, ck.world, first.resolution)
    for parity in (0, 1):
        for k in range(len(FIELD_YAWS)):
            assert np.array_equal(first.field.fits(parity, k), fresh.fits(parity, k))


def test_another_geometry_or_spacing_gets_its_own_field():
    ck = PivotChecker(two_rooms(1.2), seed=0)
    field = assembly_field(ck, 0.1)
    assert assembly_field(PivotChecker(two_rooms(1.6), seed=0), 0.1) is not field
    assert assembly_field(ck, 0.2) is not field
    moved = dataclasses.replace(ck.scene, start=(ck.scene.start[0] + 0.1, *ck.scene.start[1:]))
    assert assembly_field(PivotChecker(moved, seed=0), 0.1) is not field  # a new digest
    assert assembly_field(PivotChecker(two_rooms(1.2), seed=3), 0.1) is field


def test_lattice_components_are_computed_once_per_field_and_region():
    import pytest
    import shapely

    scene = shipped("slot")
    x0, y0, x1, y1 = scene.bounds
    left = shapely.box(x0, y0, 0.5 * (x0 + x1), y1)
    first = TransferLattice(PivotChecker(scene, seed=0), CostModel(), region=left)
    again = TransferLattice(PivotChecker(shipped("slot"), seed=1), CostModel(),
                            region=shapely.box(x0, y0, 0.5 * (x0 + x1), y1))
    whole = TransferLattice(PivotChecker(scene, seed=2), CostModel())
    ids, labels = first.components(0)
    assert again.components(0)[1] is labels
    assert whole.components(0)[1] is not labels  # another region: its own components
    assert int((whole.components(0)[0] >= 0).sum()) > int((ids >= 0).sum())
    with pytest.raises(ValueError, match="read-only"):
        labels[0] = 7  # shared: no lattice may change another's


def test_lattice_routes_are_shared_by_scene_and_prices_and_a_stop_still_stops():
    import pytest

    from pivot_ompl.errors import Interrupted

    scene = shipped("open")
    first = TransferLattice(PivotChecker(scene, seed=0), CostModel())
    poses, cost = first.route(scene.start, scene.goal, 0)
    assert len(poses) >= 2 and cost > 0
    again = TransferLattice(PivotChecker(shipped("open"), seed=1), CostModel())
    assert again.route(scene.start, scene.goal, 0)[0] is poses  # not searched again
    other = TransferLattice(PivotChecker(scene, seed=0), CostModel(), max_expansions=10_000)
    assert other.route(scene.start, scene.goal, 0)[0] is not poses  # another search limit
    stopped = TransferLattice(PivotChecker(scene, seed=2), CostModel())
    with pytest.raises(Interrupted):  # known to another plan, still stopped as when searched
        stopped.route(scene.start, scene.goal, 0, should_stop=lambda: True)

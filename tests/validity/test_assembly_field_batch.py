"""The assembly field's grids, every yaw of a parity computed in one batch, are the grids of
one yaw at a time (the sums and raster each yaw had alone); with the opposite yaws' sums
reflected, the same to rounding."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.validity import assembly_field
from pivot_ompl.validity.assembly_field import FIELD_YAWS, AssemblyField, assembly_bodies
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.minkowski import meeting_edges
from pivot_ompl.validity.rasters import grid_union


def _one_yaw(field: AssemblyField, checker: PivotChecker, parity: int, k: int) -> np.ndarray:
    """The grid of yaw ``k`` computed alone (the field's former way)."""
    world, model = checker.world, checker.model
    yaw = FIELD_YAWS[k]
    c, s = math.cos(yaw), math.sin(yaw)
    rot = np.array([[c, -s], [s, c]]).T
    b = world.bounds
    xs = b[0] + field.resolution * np.arange(field.nx)
    ys = b[1] + field.resolution * np.arange(field.ny)
    corners = np.concatenate(assembly_bodies(model, parity, 0.0)) @ rot
    ok = ((xs + corners[:, 0].min() > b[0]) & (xs + corners[:, 0].max() < b[2]))[:, None] \
        & ((ys + corners[:, 1].min() > b[1]) & (ys + corners[:, 1].max() < b[3]))[None, :]
    pieces = obstacle_pieces(world.obstacles)
    if pieces:
        bodies = [body @ rot for body in assembly_bodies(model, parity, world.clearance)]
        edges = meeting_edges(pieces * len(bodies), [bd for bd in bodies for _ in pieces],
                              certify=False)
        ok &= ~grid_union(edges, xs, ys, groups=np.zeros(len(pieces) * len(bodies), dtype=int),
                          n_groups=1)[0]
    return ok


@pytest.mark.parametrize("cells", [None, 1])
@pytest.mark.parametrize("batch", [None, 1])
@pytest.mark.parametrize("name", ["fig10", "door", "cluttered_room", "open_fig7"])
def test_every_yaw_s_grid_is_the_grid_computed_alone(name, batch, cells, monkeypatch):
    if batch is not None:  # one opposite pair a batch, as on a floor of thousands of pieces
        monkeypatch.setattr(assembly_field, "BATCH_POLYGONS", batch)
    if cells is not None:  # one yaw a raster call, as on a large floor
        monkeypatch.setattr(assembly_field, "RASTER_CELLS", cells)
    checker = PivotChecker(shipped(name))
    field = AssemblyField(checker.model, checker.world, 0.1, reflect=False)
    paired = AssemblyField(checker.model, checker.world, 0.1)
    for parity in (1, 0):
        for k in (5, *range(len(FIELD_YAWS))):  # a first ask from the middle too
            alone = _one_yaw(field, checker, parity, k)
            assert np.array_equal(field.fits(parity, k), alone)
            # reflected: a grid point exactly on an edge may fall either side of it
            assert int((paired.fits(parity, k) != alone).sum()) <= max(8, alone.size // 1000)


def test_a_large_floor_s_rasters_look_at_the_stop_between_yaws(monkeypatch):
    """A 200 m floor's 32 yaws at 0.4 m were one raster call (0.34 s, the stop never asked)."""
    scene = make_scene(bounds=[0.0, 0.0, 200.0, 200.0], start=[3.0, 3.0, 0.0],
                       goal=[197.0, 197.0, 0.0], object={"size": [0.8, 0.6, 1.3]},
                       obstacles=[{"type": "box", "center": [20.0 + 8 * i, 50.0 + 3 * i],
                                   "size": [1.5, 0.8], "height": 1.5} for i in range(20)])
    checker = PivotChecker(scene)
    calls = []
    real = assembly_field.grid_union

    def counted(*args, **kwargs):
        calls.append(kwargs["n_groups"])
        return real(*args, **kwargs)

    monkeypatch.setattr(assembly_field, "grid_union", counted)
    field = AssemblyField(checker.model, checker.world, 0.4)
    assert field.nx * field.ny * len(FIELD_YAWS) > assembly_field.RASTER_CELLS
    with pytest.raises(Interrupted):
        field.fits(0, 0, should_stop=lambda: bool(calls))
    assert calls and sum(calls) < len(FIELD_YAWS)  # stopped after its first raster call
    calls.clear()
    whole = AssemblyField(checker.model, checker.world, 0.4)
    whole.fits(0, 0, should_stop=lambda: False)
    assert max(calls) * field.nx * field.ny <= assembly_field.RASTER_CELLS

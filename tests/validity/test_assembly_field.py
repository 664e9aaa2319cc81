"""Where the held assembly fits: half the sums reflected, and a field restricted to a region.

The field's yaws come in opposite pairs; the second of a pair reflects the first's sums for
the centrally symmetric pieces (:func:`~pivot_ompl.validity.assembly_field.reflected`). A
field restricted to an area (:meth:`~pivot_ompl.validity.assembly_field.AssemblyField.restrict`)
leaves out the pieces no assembly there can meet. Both must give the rasters the plain
computation gives.
"""

from __future__ import annotations

import numpy as np
import pytest
from factories import shipped
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.validity.assembly_field import FIELD_YAWS, AssemblyField, symmetric_centres

HALF = len(FIELD_YAWS) // 2


@pytest.fixture(scope="module", params=["fig10", "cluttered_room", "t_junction"])
def checker(request):
    return PivotChecker(shipped(request.param), seed=0)


def test_the_opposite_yaws_reflected_are_the_yaws_summed(checker):
    ck = checker
    paired = AssemblyField(ck.model, ck.world, 0.1)
    for parity in (0, 1):
        for k in range(len(FIELD_YAWS)):  # each second yaw of a pair reflects the first's
            paired.fits(parity, k)
    _, symmetric = symmetric_centres(paired.pieces)  # what can be reflected
    assert paired.sums_reflected == 2 * 2 * HALF * int(symmetric.sum())  # 2 bodies, 2 parities
    alone = AssemblyField(ck.model, ck.world, 0.1, reflect=False)  # every sum its own
    for parity in (0, 1):
        for k in range(HALF, len(FIELD_YAWS)):  # the same regions, to rounding: a grid
            # point exactly on a sum's edge (axis-aligned walls at yaw pi, whose sine is
            # 1e-16, not 0) may fall either side of it
            differ = int((paired.fits(parity, k) != alone.fits(parity, k)).sum())
            assert differ <= max(8, paired.nx * paired.ny // 1000), (parity, k, differ)
    assert alone.sums_reflected == 0


def test_a_rectangle_is_symmetric_and_a_triangle_is_not():
    rect = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    centres, symmetric = symmetric_centres([rect, tri])
    assert symmetric.tolist() == [True, False]
    assert np.allclose(centres[0], [1.0, 0.5])


@settings(max_examples=6, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(box=st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)),
       k=st.integers(0, len(FIELD_YAWS) - 1), parity=st.sampled_from([0, 1]))
def test_a_restricted_field_is_the_whole_fields_within_its_area(checker, box, k, parity):
    ck = checker
    whole = AssemblyField(ck.model, ck.world, 0.1)
    area = np.zeros((whole.nx, whole.ny), dtype=bool)
    x0, x1 = sorted((int(box[0] * whole.nx), int(box[1] * whole.nx)))
    y0, y1 = sorted((int(box[2] * whole.ny), int(box[3] * whole.ny)))
    area[x0:x1 + 1, y0:y1 + 1] = True
    part = AssemblyField(ck.model, ck.world, 0.1)
    part.restrict(area)
    assert np.array_equal(part.fits(parity, k), whole.fits(parity, k) & area)
    assert len(part.pieces) <= len(whole.pieces)  # the pieces summed


def test_a_state_asked_of_a_field_not_yet_computed_stops_when_told():
    # a lattice search asks the field for its start and goal states: the yaw's grid is
    # computed then (seconds on a 10 000-point polygon) and must honour the stop
    from pivot_ompl.errors import Interrupted

    ck = PivotChecker(shipped("fig10"), seed=0)
    field = AssemblyField(ck.model, ck.world, 0.1)
    asked = []

    def stop_on_second() -> bool:
        asked.append(1)
        return len(asked) > 1

    with pytest.raises(Interrupted):
        field.state_fits(field.nx // 2, field.ny // 2, 0, 0, stop_on_second)
    assert len(asked) >= 2  # asked again inside the computation, not only before it
    assert field.state_fits(field.nx // 2, field.ny // 2, 0, 0) in (True, False)

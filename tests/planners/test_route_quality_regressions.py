"""Plans of a generated walls scene: no detour left where the arcs' estimates hid the turns."""

from __future__ import annotations

import pytest

from pivot_ompl.api import plan
from pivot_ompl.generate import GeneratorParams, generate


@pytest.fixture(scope="module")
def walls():
    return generate("walls", 1, params=GeneratorParams(walls=2)).scene


def test_leaving_a_slot_the_box_is_pulled_out_and_turned_not_looped(walls):
    """Seed 1 kept a loop after its second regrasp (route 1.58 x the bound, 1389 s).

    The followed route's arcs looked cheaper than a pull out of the slot, a turn and a
    straight pull, which the checks find cheaper; the turns are now offered too.
    """
    res = plan(walls, seed=1, time_limit=60.0)
    q = res.plan.extra["quality"]
    assert res.solved and q["regrasps"] == 2
    assert q["route_ratio"] <= 1.5
    assert q["cost"] < 1350.0

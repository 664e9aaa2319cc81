"""The route repair's tuning constants are configuration parameters (``repair.*``)."""

from __future__ import annotations

import pytest

from pivot_ompl.errors import InputError
from pivot_ompl.planners import RegraspConfig
from pivot_ompl.planners.config import parameters

#: The defaults the repair had as module constants: unchanged.
DEFAULTS = {"repair.join_step": 0.25, "repair.detour_spacing": 0.75,
            "repair.detour_targets": 3, "repair.detour_checks": 60,
            "repair.polish_checks_per_state": 4, "repair.polish_kept": 4}


def test_the_repair_knobs_are_listed_with_their_defaults_and_ranges():
    listed = {p.name: p for p in parameters() if p.name.startswith("repair.")}
    assert {n: p.default for n, p in listed.items()} == DEFAULTS
    assert all(p.range is not None and p.doc for p in listed.values())


@pytest.mark.parametrize("name, value", [("repair.join_step", "0"),
                                         ("repair.detour_checks", "-1"),
                                         ("repair.detour_targets", "1.5")])
def test_a_repair_knob_out_of_its_range_is_refused_by_name(name, value):
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({name: value})
    assert e.value.field == name


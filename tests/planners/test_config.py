"""The regrasp planner's configuration: dotted names, values from a command line, checks."""

from __future__ import annotations

import pytest

from pivot_ompl.errors import InputError
from pivot_ompl.planners.config import RegraspConfig


def test_every_leaf_has_a_dotted_name_and_round_trips():
    cfg = RegraspConfig()
    flat = cfg.flat()
    assert {"search.weight", "cost.regrasp", "sampling.slot_spacing", "grasps",
            "cost.durations.per_pivot"} <= set(flat)
    assert cfg.with_values(flat) == cfg


def test_values_from_a_command_line_take_the_leaf_type():
    cfg = RegraspConfig().with_values({"search.weight": "1.5", "cost.regrasp": "30",
                                       "search.turns": "false", "grasps": "0,2",
                                       "sampling.slot_approach": "0.4 0.7",
                                       "search.neighbours": "12"})
    assert cfg.search.weight == 1.5 and cfg.cost.regrasp == 30.0
    assert cfg.search.turns is False and cfg.grasps == (0, 2)
    assert cfg.sampling.slot_approach == (0.4, 0.7) and cfg.search.neighbours == 12


@pytest.mark.parametrize(("name", "value", "field"), [
    ("search.colour", "1", "param"), ("search", "1", "param"),
    ("search.weight", "heavy", "search.weight"), ("search.weight", "0.5", "search.weight"),
    ("search.neighbours", "1.5", "search.neighbours"), ("cost.regrasp", "-1", "cost.regrasp"),
    ("cost.regrasp", "nan", "cost.regrasp"), ("grasps", "0,7", "grasps"),
    ("search.turns", "maybe", "search.turns")])
def test_bad_values_name_the_parameter(name, value, field):
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({name: value})
    assert e.value.field == field

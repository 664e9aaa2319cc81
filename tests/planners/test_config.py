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


def test_every_numeric_parameter_declares_its_range_beside_its_field():
    from dataclasses import fields

    from pivot_ompl.planners.config import (
        OptimiserConfig,
        SamplingConfig,
        SearchConfig,
        SingleGraspConfig,
    )

    for cls in (SamplingConfig, SearchConfig, SingleGraspConfig, OptimiserConfig):
        for f in fields(cls):
            if f.type != "bool":
                assert "range" in f.metadata, (cls.__name__, f.name)


@pytest.mark.parametrize(("name", "value", "reason"), [
    ("search.weight", "0.5", "must be >= 1"), ("search.weight", "-1", "must be finite and >= 0"),
    ("search.neighbours", "0", "must be >= 1"), ("sampling.guard_failures", "0", "must be >= 1"),
    ("sampling.slot_spacing", "0", "must be > 0"), ("sampling.visibility_area", "0", "must be > 0"),
    ("sampling.goal_bias", "1.5", "must be <= 1"),
    ("cost.regrasp", "inf", "must be finite and >= 0"),
    ("sampling.slot_approach", "0.4 -0.7", "must be finite and >= 0")])
def test_a_value_out_of_its_declared_range_is_named_with_the_range(name, value, reason):
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({name: value})
    assert e.value.field == name and e.value.reason == reason


def test_the_listed_parameters_are_the_leaves_with_their_defaults_and_ranges():
    from pivot_ompl.planners.config import parameters

    listed = parameters()
    assert [p.name for p in listed] == list(RegraspConfig().flat())
    assert [p.default for p in listed] == list(RegraspConfig().flat().values())
    by = {p.name: p for p in listed}
    assert str(by["search.weight"].range) == "[1, inf)"
    assert str(by["search.neighbours"].range) == "[1, inf) integer"
    assert str(by["sampling.slot_spacing"].range) == "(0, inf)"
    assert str(by["sampling.goal_bias"].range) == "[0, 1]"
    assert by["search.turns"].range is None
    assert all(p.doc for p in listed)  # every leaf is documented in its class
    for p in listed:  # each default lies in its range, and the range's bounds are enforced
        if p.range is None or isinstance(p.default, tuple):
            continue
        RegraspConfig().with_values({p.name: p.default})
        below = p.range.low - (0 if p.range.low_open else (1 if p.range.integer else 1e-6))
        if below >= 0:
            with pytest.raises(InputError):
                RegraspConfig().with_values({p.name: below})


def test_bench_param_help_lists_every_sweepable_parameter(capsys):
    from pivot_ompl.cli.main import main

    assert main(["bench", "--param", "help"]) == 0
    out = capsys.readouterr().out
    for name, value in RegraspConfig().flat().items():
        line = next(ln for ln in out.splitlines() if ln.split()[:1] == [name])
        assert " [" in line or " (" in line or "true or false" in line or name == "grasps"
        if isinstance(value, float):
            assert f"{value:g}" in line
    assert "search.weight" in out and "[1, inf)" in out
    for markup in ("``", ":mod:", ":func:", ":data:"):
        assert markup not in out
    assert main(["bench"]) == 2  # a sweep still needs a scene

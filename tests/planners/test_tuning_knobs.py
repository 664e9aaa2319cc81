"""The object roadmap's and the lattice routes' tuning constants are configuration parameters.

``sampling.extend_step`` (the diffusion), ``sampling.max_rejects`` (the reachable-pose
sampler) and ``optimiser.run_spacing`` (the poses kept along a lattice route): listed with
their defaults (the former module constants) and ranges, and a value other than the default
reaches the code that uses it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from factories import shipped

from pivot_ompl import plan, scene_from_map
from pivot_ompl.base.problem import make_problem
from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.planners import improve as improve_module
from pivot_ompl.planners.config import RegraspConfig, parameters
from pivot_ompl.planners.regrasp_search import RegraspSearch

#: The defaults the constants had: unchanged (the seeded plans stay the same).
DEFAULTS = {"sampling.extend_step": 0.05, "sampling.max_rejects": 200,
            "optimiser.run_spacing": 6}
RANGES = {"sampling.extend_step": "(0, inf)", "sampling.max_rejects": "[0, inf) integer",
          "optimiser.run_spacing": "[1, inf) integer"}
HOUSE = Path(__file__).resolve().parents[2] / "scenes" / "maps" / "aws_small_house" / "map.yaml"


def test_the_knobs_are_listed_with_their_defaults_and_ranges(capsys):
    listed = {p.name: p for p in parameters()}
    assert {n: listed[n].default for n in DEFAULTS} == DEFAULTS
    assert {n: str(listed[n].range) for n in RANGES} == RANGES
    assert all(listed[n].doc for n in DEFAULTS)
    assert main(["bench", "--param", "help"]) == 0
    names = {ln.split()[0] for ln in capsys.readouterr().out.splitlines() if ln.strip()}
    assert set(DEFAULTS) <= names


@pytest.mark.parametrize("name, value", [("sampling.extend_step", "0"),
                                         ("sampling.max_rejects", "-1"),
                                         ("sampling.max_rejects", "1.5"),
                                         ("optimiser.run_spacing", "0")])
def test_a_knob_out_of_its_range_is_refused_by_name(name, value):
    with pytest.raises(InputError) as e:
        RegraspConfig().with_values({name: value})
    assert e.value.field == name


def _search(values: dict[str, str]) -> RegraspSearch:
    scene = shipped("fig10")
    return RegraspSearch(make_problem(scene).checker, scene.start, scene.goal,
                         RegraspConfig().with_values(values), np.random.default_rng(0))


def test_the_extend_step_reaches_the_diffusion():
    fine, coarse = _search({}), _search({"sampling.extend_step": "0.5"})
    moved = 0
    for _ in range(60):
        near, target = fine.sampler.uniform(), fine.sampler.uniform()
        if not fine.checker.box_valid(near):
            continue
        a, b = fine.diffusion.extend(near, target), coarse.diffusion.extend(near, target)
        assert coarse.checker.box_valid(b)  # the last free pose, whatever the step
        moved += a != b
    assert moved >= 3  # extensions that meet an obstacle stop elsewhere


def test_max_rejects_reaches_the_sampler():
    for value, same in (("0", True), ("200", False)):
        sampler = _search({"sampling.max_rejects": value}).sampler
        state = sampler.rng.bit_generator.state
        drawn = [sampler.reachable() for _ in range(5)]
        sampler.rng.bit_generator.state = state
        uniform = [sampler.uniform() for _ in range(5)]
        # none allowed: every draw falls back to the floor's bounds at once
        assert (drawn == uniform) is same, value


def test_the_run_spacing_reaches_the_lattice_routes_made_real():
    house = scene_from_map(HOUSE, start=(-6.0, -3.0, 0.0), goal=(7.0, -1.0, 0.5 * math.pi))
    runs = {}
    for spacing in ("6", "40"):
        cfg = RegraspConfig().with_values({"single_grasp.checks": "0", "optimiser.enabled":
                                           "false", "optimiser.run_spacing": spacing})
        res = plan(house, time_limit=30.0, seed=0, config=cfg, bound=False)
        assert res.solved and res.roadmap["single_grasp_by"] == "lattice"
        runs[spacing] = res
    # fewer poses kept along the straight runs: fewer transfers to certify, another chain
    assert runs["40"].motion_checks["valid"] < runs["6"].motion_checks["valid"]
    assert runs["40"].plan.phases != runs["6"].plan.phases


def test_the_run_spacing_reaches_the_re_routing(monkeypatch):
    # the re-routing's chain gives every pending transfer its cheap test before any full
    # check, so on fig10 both spacings now make the same full checks: the knob is followed
    # to the re-routing's call instead
    fig10 = shipped("fig10")
    passed = []
    real = improve_module.refine

    def spied(*args, **kwargs):
        passed.append(kwargs["run_spacing"])
        return real(*args, **kwargs)

    monkeypatch.setattr(improve_module, "refine", spied)
    for spacing in ("6", "40"):
        cfg = RegraspConfig().with_values({"optimiser.eliminate": "false",
                                           "optimiser.run_spacing": spacing})
        res = plan(fig10, time_limit=30.0, seed=0, config=cfg, bound=False)
        assert res.solved and res.roadmap["refined"] >= 1
    assert passed == [6, 40]

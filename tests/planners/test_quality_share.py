"""The share of a run's checks spent on quality: one explicit knob, scaling every stage."""

from __future__ import annotations

import subprocess
import sys

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.cli.plan import planner_with_share
from pivot_ompl.errors import InputError
from pivot_ompl.planners.config import QUALITY_SHARE, RegraspConfig, quality_scale
from pivot_ompl.planners.registry import parse_spec


def test_the_default_share_keeps_every_stage_as_it_is():
    assert quality_scale(QUALITY_SHARE) == pytest.approx(1.0)
    assert RegraspConfig().optimiser.quality_share == QUALITY_SHARE
    assert quality_scale(0.0) == 0.0


@given(st.floats(0.0, 0.95), st.floats(0.0, 0.95))
def test_more_share_more_checks(a, b):
    if a < b:
        assert quality_scale(a) < quality_scale(b)


def test_the_share_is_a_config_field_within_its_range():
    cfg = RegraspConfig().with_values({"optimiser.quality_share": "0.3"})
    assert cfg.optimiser.quality_share == 0.3
    with pytest.raises(InputError, match="quality_share"):
        RegraspConfig().with_values({"optimiser.quality_share": "0.96"})


def test_the_cli_flag_joins_the_planner_parameters():
    name, values = parse_spec(planner_with_share("regrasp[search.weight=1.5]", 0.3))
    assert name == "regrasp"
    assert values == {"search.weight": "1.5", "optimiser.quality_share": "0.3"}
    assert planner_with_share("regrasp", None) == "regrasp"
    with pytest.raises(InputError, match="quality-share"):
        planner_with_share("rrtconnect", 0.3)


@pytest.mark.parametrize("args", [["--quality-share", "0.99"],
                                  ["--quality-share", "0.5", "--planner", "rrtconnect"]])
def test_a_bad_share_exits_2(args):
    out = subprocess.run([sys.executable, "-m", "pivot_ompl", "plan", "open", "--time", "5",
                          *args], capture_output=True, text=True, timeout=120)
    assert out.returncode == 2 and "--quality-share" in out.stderr

"""The command line explains itself: clean help with defaults, examples, exit codes; plurals."""

from __future__ import annotations

import argparse
import re
import types

import pytest

from pivot_ompl.cli.main import build_parser, main
from pivot_ompl.cli.plan import regrasps_text, result_line
from pivot_ompl.errors import counted
from pivot_ompl.planners import REFUSED
from pivot_ompl.resources import shipped_scenes

VERBS = sorted(next(a for a in build_parser()._actions
                    if isinstance(a, argparse._SubParsersAction)).choices)


def _help(capsys, *argv: str) -> str:
    assert main([*argv, "--help"]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("verb", VERBS)
def test_every_verbs_help_is_clean_with_defaults_examples_and_exit_codes(verb, capsys):
    text = _help(capsys, verb)
    for markup in ("``", ":mod:", ":func:", ":class:", ":data:"):
        assert markup not in text, markup
    assert "examples:" in text and f"pivot-ompl {verb} " in text.split("examples:")[1]
    assert "exit codes: 0 success, 1 " in text and "2 bad input" in text
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    flat = " ".join(text.split())
    for action in sub.choices[verb]._actions:
        d = action.default
        if not action.option_strings or d is None or isinstance(d, bool) or d in ((), []) \
                or d == argparse.SUPPRESS:
            continue
        shown = [f"default: {d}", f"default {d}", f"default {d:g}" if isinstance(d, float)
                 else f"default: {d}"]
        assert any(s in flat for s in shown), (action.dest, d)


def test_the_top_level_help_names_the_verbs_and_exit_codes(capsys):
    text = _help(capsys)
    assert "``" not in text and "exit codes:" in text and "examples:" in text
    assert all(v in text for v in VERBS)


def test_plan_offers_no_planner_it_refuses(capsys):
    text = " ".join(_help(capsys, "plan").split())
    assert REFUSED and not any(re.search(rf"\b{name}\b", text) for name in REFUSED)


def test_plurals_and_bounds_read_as_english():
    assert counted(1, "regrasp") == "1 regrasp" and counted(0, "regrasp") == "0 regrasps"
    assert regrasps_text(1, 1) == "1 regrasp (proven minimum)"
    assert regrasps_text(3, 0) == "3 regrasps"  # a bound of 0 proves nothing
    assert regrasps_text(3, 2) == "3 regrasps (at least 2)"
    res = types.SimpleNamespace(status="TIMEOUT", solved=False, pivots=0, regrasps=0,
                                timings={"solve": 1.0}, time_limit=1.0)
    line = result_line(res)  # type: ignore[arg-type]
    assert "0 pivots" not in line and "no plan" in line
    res.status, res.solved, res.pivots, res.regrasps = "EXACT_SOLUTION", True, 1, 1
    assert result_line(res).startswith("EXACT_SOLUTION: 1 pivot, 1 regrasp,")  # type: ignore


def test_an_unknown_scene_name_lists_the_shipped_scenes(capsys):
    assert main(["plan", "nosuch", "--time", "1"]) == 2
    err = capsys.readouterr().err
    assert "'nosuch'" in err and all(name in err for name in shipped_scenes())

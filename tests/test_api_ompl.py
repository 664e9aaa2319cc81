"""The API with OMPL's planners: lazy names listed, seeds reproducible in one process, OMPL's
log quiet, an approximate path never written as a plan."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import pivot_ompl
from pivot_ompl.cli.main import main
from pivot_ompl.errors import PlanningError


def test_the_lazy_exports_are_listed_by_dir():
    names = dir(pivot_ompl)
    for name in ("plan", "make_setup", "PivotSteering", "PlanResult", "PivotProblem"):
        assert name in names and name in pivot_ompl.__all__
    assert set(pivot_ompl.__all__) <= set(names)
    assert callable(pivot_ompl.plan)


def _phases(seed: int) -> str:
    res = pivot_ompl.plan("cluttered_room", planner="rrtconnect", seed=seed, time_limit=10.0,
                          bound=False)
    assert res.solved
    return json.dumps(res.plan.to_dict()["phases"])


def test_a_second_seeded_ompl_plan_in_one_process_is_reproducible(capfd):
    first = _phases(5)
    other = _phases(3)
    again = _phases(5)
    assert again == first and other != first
    out, err = capfd.readouterr()
    assert "already started" not in err  # OMPL's warning for a second seed is not shown


def test_ompls_log_is_quiet_by_default_and_shown_with_log_level_debug(tmp_path):
    code = ("import pivot_ompl; pivot_ompl.plan('open', planner='rrtconnect', time_limit=5.0, "
            "bound=False)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120, check=True)  # a process of its own: no test's log level
    assert "Info:" not in r.stdout + r.stderr and "Debug:" not in r.stdout + r.stderr
    r = subprocess.run([sys.executable, "-m", "pivot_ompl.cli", "--log-level", "DEBUG", "plan",
                        "open", "--planner", "rrtconnect", "--no-bound"],
                       capture_output=True, text=True, timeout=120, check=True)
    assert "Info:" in r.stdout + r.stderr


@pytest.fixture(scope="module")
def approximate():
    """OMPL's RRT stopped early on fig10: its closest path does not reach the goal."""
    res = pivot_ompl.plan("fig10", planner="rrt", time_limit=2.0, seed=1, bound=False)
    assert res.status == "APPROXIMATE_SOLUTION"
    return res


def test_an_approximate_result_is_never_written_as_a_plan(approximate, tmp_path, capsys):
    assert not approximate.solved
    with pytest.raises(PlanningError, match="approximate path is not a plan"):
        approximate.to_json(tmp_path / "p.json")
    assert not (tmp_path / "p.json").exists()
    out = tmp_path / "cli.json"
    assert main(["plan", "fig10", "--planner", "rrt", "--time", "2", "--seed", "1",
                 "--no-bound", "--out", str(out)]) == 1
    text = capsys.readouterr()
    assert "APPROXIMATE_SOLUTION: the planner's closest path does not reach the goal" in text.out
    assert "0 pivots" not in text.out and not out.exists()

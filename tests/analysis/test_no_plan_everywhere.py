"""No plan for want of room to turn: said with its place by every planner and by replanning."""

from __future__ import annotations

import copy
import math
import time

import pytest
import yaml
from corner_factories import tight_corner
from cpu_share import with_cpu_limit

from pivot_ompl.api import plan
from pivot_ompl.base.staged_solve import solve_staged
from pivot_ompl.cli.main import main
from pivot_ompl.scene import scene_from_dict
from pivot_ompl.session import PlanningSession

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

LIMIT = 30.0


def _proven_in_a_tenth(res, took: float, limit: float) -> bool:
    return res.status == "INFEASIBLE" and took <= 0.1 * limit


def _assert_placed(res, corner, took, limit):
    # limit: LIMIT, or more where a loaded machine gave the run less than a core
    # (tests/cpu_share.py); the answer within a tenth of the limit the run had
    assert res.status == "INFEASIBLE" and not res.solved, res.status
    assert took <= 0.1 * limit, took
    assert res.turn is not None and math.dist(res.turn.center, corner) < 1.0
    x, y = res.turn.center
    reason = res.infeasible_reason
    assert reason is not None and reason.startswith("no plan: the box cannot turn at")
    assert f"({x:.2f}, {y:.2f})" in reason
    assert res.plan.extra["no_plan"] == reason and res.plan.extra["turn"]["reason"] == reason
    assert not res.plan.phases


@pytest.mark.parametrize(("planner", "seed"), [("rrtconnect", 0), ("rrtconnect", 5),
                                               ("kpiece1", 1), ("visprm", 2)])
def test_every_planner_says_where_the_box_cannot_turn(planner, seed):
    # OMPL's planners poll nothing of ours: their solve is stopped once to ask the proof
    doc, corner = tight_corner(seed)
    scene = scene_from_dict(doc, source="<test>")
    res, took, limit = with_cpu_limit(
        lambda lim: plan(scene, planner=planner, time_limit=lim, seed=seed), LIMIT,
        _proven_in_a_tenth)
    _assert_placed(res, corner, took, limit)


@pytest.mark.parametrize("seed", [0, 3])
def test_a_replan_says_where_the_box_cannot_turn(seed):
    # the session plans without the quality block's bounds, yet its search asks the proof
    doc, corner = tight_corner(seed)
    scene = scene_from_dict(doc, source="<test>")
    res, took, limit = with_cpu_limit(  # a fresh session each run
        lambda lim: PlanningSession(scene, seed=seed).replan(box=scene.start, time_limit=lim),
        LIMIT, _proven_in_a_tenth)
    _assert_placed(res, corner, took, limit)


@pytest.mark.parametrize("seed", [1, 4])
def test_an_added_wall_that_leaves_no_room_to_turn_is_said_with_its_place(seed):
    # regression: the replan after added obstacles said "the regrasp bound's relaxation joins
    # no start to the goal" with no place, after repairing the old route for half its limit
    doc, corner = tight_corner(seed)
    open_doc = copy.deepcopy(doc)
    inner = open_doc["obstacles"].pop(2)  # the block inside the L: an open room without it
    scene = scene_from_dict(open_doc, source="<test>")

    def run(limit: float):  # a fresh session each run; the replan timed
        session = PlanningSession(scene, seed=seed)
        assert session.plan(time_limit=LIMIT).solved
        t0 = time.monotonic()
        res = session.replan(box=scene.start, add_obstacles=[inner], time_limit=limit)
        return session, res, time.monotonic() - t0

    (session, res, took), _, limit = with_cpu_limit(
        run, LIMIT, lambda r, _, limit: _proven_in_a_tenth(r[1], r[2], limit))
    _assert_placed(res, corner, took, limit)
    assert session.last is res


def test_cli_plan_with_an_ompl_planner_exits_1_with_the_reason(tmp_path, capsys):
    doc, _ = tight_corner(6)
    path, out = tmp_path / "corner.yaml", tmp_path / "plan.json"
    path.write_text(yaml.safe_dump(doc))

    def run(limit: float) -> tuple[int, str]:
        rc = main(["plan", str(path), "--planner", "rrtconnect", "--time", str(limit),
                   "--out", str(out)])
        return rc, capsys.readouterr().out

    (rc, text), _, _ = with_cpu_limit(run, LIMIT, lambda r, took, limit: "INFEASIBLE" in r[1])
    assert rc == 1
    line = [ln for ln in text.splitlines() if ln.startswith("INFEASIBLE")]
    assert len(line) == 1 and "cannot turn at" in line[0]
    assert not out.exists()


class _Setup:
    """A stand-in for OMPL's SimpleSetup: each solve spends its time, solved after ``need``."""

    def __init__(self, clock, need):
        self.clock, self.need, self.calls, self.spent = clock, need, [], 0.0

    def solve(self, seconds):
        self.calls.append(seconds)
        if self.spent + seconds >= self.need:
            self.clock[0] += self.need - self.spent
            return "Exact solution"
        self.spent += seconds
        self.clock[0] += seconds
        return "Timeout"


def test_the_staged_solve_asks_once_only_while_it_has_no_path():
    now = [0.0]
    asked = []

    def proof(answer):
        def ask():
            asked.append(now[0])
            return answer
        return ask

    # no path at the stage's end: asked once there; nothing proven, the solve goes on
    ss = _Setup(now, need=5.0)
    assert solve_staged(ss, 10.0, 0.0, proof=proof(False), ask_at=0.2,
                        clock=lambda: now[0]) == "EXACT_SOLUTION"
    assert asked == [0.2] and ss.calls == [pytest.approx(0.2), pytest.approx(9.8)]
    # proven: the solve ends at the stage's end
    asked.clear()
    now[0] = 0.0
    ss = _Setup(now, need=5.0)
    assert solve_staged(ss, 10.0, 0.0, proof=proof(True), ask_at=0.2,
                        clock=lambda: now[0]) == "TIMEOUT"
    assert asked == [0.2] and len(ss.calls) == 1
    # a path in the first stage: never asked
    asked.clear()
    now[0] = 0.0
    ss = _Setup(now, need=0.1)
    assert solve_staged(ss, 10.0, 0.0, proof=proof(True), ask_at=0.2,
                        clock=lambda: now[0]) == "EXACT_SOLUTION"
    assert asked == [] and len(ss.calls) == 1

"""The prover beside the search: the answers of one process, and no process left behind."""

from __future__ import annotations

import logging
import os
import socket
import subprocess
import sys
import threading
import time
from multiprocessing.connection import Connection
from pathlib import Path

import pytest
import yaml
from corner_factories import ragged_slot
from factories import benchmark_script, shipped

from pivot_ompl.analysis import late_proof, passage, plan_bounds
from pivot_ompl.analysis.bound_cache import CACHE_ENV
from pivot_ompl.analysis.bound_levels import exhaustive_estimate
from pivot_ompl.analysis.late_proof import LateProof
from pivot_ompl.analysis.passage import PassageOnce
from pivot_ompl.analysis.pose_proof import proof_estimate
from pivot_ompl.analysis.prover import Prover, serve, wanted
from pivot_ompl.api import plan
from pivot_ompl.errors import InputError
from pivot_ompl.generate import rotate_scene

pytestmark = pytest.mark.timed  # two processes, each wanting its core


def test_no_plan_is_proven_beside_the_search_with_the_reason_a_person_acts_on():
    scene = ragged_slot(0)
    res = plan(scene, time_limit=60.0, parallel=True)
    assert res.status == "INFEASIBLE"
    assert res.infeasible_reason is not None and "0.90 m" in res.infeasible_reason
    assert res.plan.extra["no_plan"] == res.infeasible_reason


def _served(scene, answer) -> list[str]:  # noqa: ANN001
    """The kinds of the messages a prover sends for ``scene`` given the passage ``answer``."""
    ours, theirs = socket.socketpair()
    conn, child = Connection(ours.detach()), Connection(theirs.detach())
    conn.send(("job", (scene, time.monotonic() + 30.0, None, logging.WARNING, answer)))
    worker = threading.Thread(target=serve, args=(child,))
    worker.start()
    kinds: list[str] = []
    while not kinds or kinds[-1] not in ("done", "failed"):
        kinds.append(conn.recv()[0])
    conn.send(("stop", None))
    worker.join(30.0)
    conn.close()
    child.close()
    return kinds


def test_the_prover_takes_the_plan_s_passage_instead_of_searching_again(monkeypatch):
    scene = ragged_slot(0)
    passages = PassageOnce(scene)
    passages()
    assert passages.answer is not None

    search = passage.passage_search

    def searched_again(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        if kwargs.get("gaps_below") is None:  # the scene's passage (not an explanation's)
            raise AssertionError("the passage was searched again")
        return search(*args, **kwargs)

    monkeypatch.setattr(passage, "passage_search", searched_again)
    assert _served(scene, passages.answer)[-2:] == ["no plan", "done"]
    assert _served(scene, None)[-1] == "failed"  # the spy sees a search of its own


def test_a_plan_made_beside_a_prover_carries_the_prover_s_bounds(monkeypatch):
    scene = rotate_scene(shipped("fig10"), 0.0123)  # a geometry no other test has bounded
    monkeypatch.setenv(CACHE_ENV, "0")  # the answers reach the plan through the pipe alone

    def computed_here(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        raise AssertionError("the regrasp bound was computed in the plan's own process")

    monkeypatch.setattr(plan_bounds, "lower_bound", computed_here)
    two = plan(scene, time_limit=30.0, seed=1, parallel=True)
    monkeypatch.undo()
    one = plan(scene, time_limit=30.0, seed=1, parallel=False)
    assert one.solved and two.solved
    assert (two.pivots, two.regrasps) == (one.pivots, one.regrasps) == (two.pivots, 2)
    q = two.plan.extra["quality"]
    assert q["regrasps_lower_bound"] == 2
    assert q["shortest_route"] is not None and q["route_ratio"] >= 1.0


def test_a_script_without_a_main_guard_plans_beside_a_prover(tmp_path):
    script = tmp_path / "plan_it.py"  # a user's script: no `if __name__ == "__main__"`
    script.write_text("from pivot_ompl.api import plan\n"
                      "res = plan('fig10', time_limit=30.0, parallel=True)\n"
                      "print(res.status, res.plan.extra['quality']['regrasps_lower_bound'])\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["EXACT_SOLUTION", "2"]


@pytest.mark.parametrize("interpreter", ["exits at once", "missing"])
def test_no_plan_is_still_proven_when_the_prover_s_process_fails(tmp_path, monkeypatch,
                                                                 interpreter):
    python = tmp_path / "python"  # an interpreter that cannot import the package, or none
    if interpreter == "exits at once":
        python.write_text("#!/bin/sh\nexit 1\n")
        python.chmod(0o755)
    monkeypatch.setattr(sys, "executable", str(python))
    res = plan(ragged_slot(0), time_limit=20.0, parallel=True)
    assert res.status == "INFEASIBLE"
    assert res.infeasible_reason is not None and "0.90 m" in res.infeasible_reason


def test_an_error_of_the_prover_s_proofs_is_not_met_again_in_the_plan(tmp_path, monkeypatch):
    (tmp_path / "sitecustomize.py").write_text(  # the prover's interpreter: its proofs broken
        "import pivot_ompl.analysis.prover as prover\n"
        "def broken(*args, **kwargs):\n"
        "    raise RuntimeError('a broken proof')\n"
        "prover._no_plan = prover._bounds = broken\n")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), *sys.path]))

    def met_again(self):  # noqa: ANN001, ANN202
        raise RuntimeError("the prover's error met again in the plan's process")

    monkeypatch.setattr(LateProof, "__call__", met_again)
    res = plan(ragged_slot(0), time_limit=5.0, parallel=True)
    assert res.status == "TIMEOUT"  # the plan went on without the proofs, as one would


def test_the_process_ends_with_the_plan_and_when_its_parent_stops_listening():
    scene = shipped("fig10")
    with Prover(scene, end=time.monotonic() + 60.0) as prover:
        prover.start()
        assert prover.running
    t0 = time.monotonic()
    assert not prover.running and time.monotonic() - t0 < 1.0


def test_the_process_ends_when_the_plan_s_process_is_gone(tmp_path):
    hall = tmp_path / "hall.yaml"  # a floor whose bounds take the prover a long while
    hall.write_text(yaml.safe_dump(benchmark_script("halls").hall(200.0, 60, 0)))
    script = tmp_path / "gone.py"  # a plan's process killed: no close, no "stop"
    script.write_text("import os, sys, time\n"
                      "from pivot_ompl.analysis.prover import Prover\n"
                      "from pivot_ompl.scene import load_scene\n"
                      f"p = Prover(load_scene({str(hall)!r}), end=time.monotonic() + 600.0)\n"
                      "p.start()\n"
                      "print(p.pid, flush=True)\n"
                      "time.sleep(3.0)\n"
                      "os._exit(0)\n")
    parent = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, text=True)
    assert parent.stdout is not None
    pid = int(parent.stdout.readline())  # not waiting for the pipe to close: the prover has it
    parent.wait(120)
    deadline = time.monotonic() + 30.0
    while Path(f"/proc/{pid}").exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not Path(f"/proc/{pid}").exists() or "zombie" in _state(pid)


def _state(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/status").read_text().split("State:")[1].split("\n")[0]
    except (OSError, IndexError):
        return "zombie"


def test_small_scenes_plan_in_one_process_and_bad_choices_are_named():
    assert not wanted(shipped("fig10"), None) and wanted(shipped("fig10"), True)
    with pytest.raises(InputError, match="parallel"):
        plan(shipped("fig10"), parallel="yes")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="parallel"):
        plan(shipped("fig10"), parallel=True, bound=False)


@pytest.mark.parametrize("cheaper_first", [True, False])
def test_the_prover_s_no_plan_tries_the_cheaper_proof_first(monkeypatch, cheaper_first):
    scene = ragged_slot(2, 0.35)  # a geometry of its own: answers are kept per scene
    assert exhaustive_estimate(scene) > proof_estimate(scene)  # the held poses are cheaper
    exact: list[int] = []
    polygons = late_proof.turning_place

    def spy(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        exact.append(1)
        return polygons(*args, **kwargs)

    monkeypatch.setattr(late_proof, "turning_place", spy)
    late = LateProof(scene, begin=0.0, end=1000.0, clock=lambda: 1.0,
                     exact_seconds=proof_estimate(scene) if cheaper_first else None)
    if cheaper_first:
        assert late() is True and late.proof is not None and not exact
    else:  # in one process's windows the exact polygons run where they fit
        late()
        assert exact == [1]

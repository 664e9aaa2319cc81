"""Replaying a replanned plan after the plan it replaced (``replay NEW --before OLD``)."""

from __future__ import annotations

import json
import math

import pytest
from factories import scene_file, shipped

from pivot_ompl.cli.main import main as cli_main
from pivot_ompl.planfile import TransferPhase, load_plan
from pivot_ompl.viz.plan_view import replanned_plan, show_replanned
from pivot_ompl.viz.recorder import recording_visualizer


@pytest.fixture(scope="module")
def old_and_new(tmp_path_factory):
    d = tmp_path_factory.mktemp("replanned")
    old = d / "old.json"
    assert cli_main(["plan", str(scene_file("slot")), "--out", str(old), "--time", "30"]) == 0
    p = load_plan(old)
    ph = next(x for x in p.phases if isinstance(x, TransferPhase))
    q = ph.steps[len(ph.steps) // 2].object
    box = (q[0] + 0.05 * math.cos(q[2]), q[1] + 0.05 * math.sin(q[2]), q[2] + 0.08)
    new, scene = d / "new.json", d / "new.yaml"
    assert cli_main(["replan", str(scene_file("slot")), str(old), "--box", *map(str, box),
                     "--grasp", str(ph.grasp), "--out", str(new), "--scene-out",
                     str(scene)]) == 0
    return d, old, new, scene, len(ph.steps) // 2 + 1


def test_the_old_plan_runs_up_to_the_drift_then_the_new_one(old_and_new):
    _, old_path, new_path, _, kept_steps = old_and_new
    old, new = load_plan(old_path), load_plan(new_path)
    both, switch = replanned_plan(old, new)
    assert both.start == old.start
    assert both.phases[switch:] == new.phases
    cut = both.phases[switch - 1]
    assert isinstance(cut, TransferPhase) and len(cut.steps) == kept_steps
    first = new.phases[0]
    assert (first.object_start if isinstance(first, TransferPhase) else first.object_pose) \
        == pytest.approx(new.start)


def test_the_replay_has_a_chapter_at_the_switch(old_and_new, tmp_path):
    _, old_path, new_path, scene_path, _ = old_and_new
    old, new = load_plan(old_path), load_plan(new_path)
    vis = recording_visualizer()
    from pivot_ompl.scene import load_scene
    info = show_replanned(vis, load_scene(scene_path), old, new)
    both, switch = replanned_plan(old, new)
    marks = [c for c in info.guide.chapters if c.title.startswith("replanned")]
    assert len(marks) == 1 and marks[0].phase == switch
    starts = [c.time for c in info.guide.chapters if c.phase == switch and c.kind != "moment"]
    assert marks[0].time == starts[0] > 0
    html = tmp_path / "replay.html"
    assert cli_main(["replay", str(new_path), "--before", str(old_path), "--scene",
                     str(scene_path), "--html", str(html)]) == 0
    assert "replanned" in html.read_text(encoding="utf-8")
    assert json.loads(new_path.read_text())["start"] == pytest.approx(list(new.start))
    assert shipped("slot").name == both.scene

"""Chapters, phase labels and camera framing of replays (no browser)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import TransferPhase, TransitPhase
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.viz import (
    follow_pose,
    motion_guide,
    overview_pose,
    recording_visualizer,
    replay_guide,
    show_plan,
    top_pose,
)
from pivot_ompl.viz.overlay import CAMERA_FOV
from pivot_ompl.viz.plan_figure import plan_figure
from pivot_ompl.viz.samples import SCENE_YAML, sample_plan
from pivot_ompl.viz.timeline import plan_keyframes


@pytest.fixture(scope="module")
def plan():
    return sample_plan()


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    p = tmp_path_factory.mktemp("scene") / "sample.yaml"
    p.write_text(SCENE_YAML)
    return load_scene(p)


def test_plan_chapters_one_per_phase_with_counts(plan):
    kf = plan_keyframes(plan)
    g = replay_guide(kf.times, kf.phase, kf.step, plan=plan)
    phases = [c for c in g.chapters if c.kind != "moment"]
    assert [c.phase for c in phases] == list(range(len(plan.phases)))
    for c in phases:
        ph = plan.phases[c.phase]
        if isinstance(ph, TransferPhase):
            assert f"· {len(ph.steps)} pivots (grasp {ph.grasp})" in c.title
        else:
            assert isinstance(ph, TransitPhase)
            assert c.kind == "regrasp" and f"walk {ph.length:.1f} m" in c.title
        # the chapter starts at the phase's first key
        assert c.time == pytest.approx(kf.times[kf.phase.index(c.phase)])
        assert g.chapter_at(c.time + 1e-6) == c
    # the first transfer starts at once: it is the first chapter, no "start" beside it at 0:00
    assert g.chapters[0].kind == "transfer" and g.chapters[0].time == kf.times[0]
    assert all(c.title != "start" for c in g.chapters)
    assert g.chapters[-1].title == "goal reached" and g.chapter_at(kf.duration) is not None
    # at the end the label names the goal and the last chapter is the goal's
    assert g.label_at(kf.duration) == (f"goal reached · {plan.pivots} pivots, "
                                       f"{plan.regrasps} regrasp")
    assert g.chapters[-1].time == pytest.approx(kf.duration)
    times = [c.time for c in g.chapters]
    assert times == sorted(times)


def test_labels_count_pivots_up_to_the_total(plan):
    kf = plan_keyframes(plan)
    g = replay_guide(kf.times, kf.phase, kf.step, plan=plan)
    nums = []
    for t, text in g.marks:
        m = re.fullmatch(r"transfer (\d)/2 · pivot (\d+)/(\d+)", text)
        if m:
            assert int(m.group(3)) == plan.pivots
            nums.append(int(m.group(2)))
        elif t == kf.duration:
            assert text.startswith("goal reached · ")
        else:
            assert text.startswith("regrasp 1/1 · walk")
        assert g.label_at(t) == text
    assert nums == sorted(nums) and nums[-1] == plan.pivots
    # every pivot is announced once while it rotates
    assert sorted(set(nums) - {0}) == list(range(1, plan.pivots + 1))
    # the label a step's keys show names that step
    i = kf.step.index(4, kf.phase.index(2))  # 5th rotation of the second transfer
    first = len(plan.phases[0].steps)
    assert g.label_at(kf.times[i]) == f"transfer 2/2 · pivot {first + 5}/{plan.pivots}"


def test_narrowest_passage_is_the_smallest_clearance(plan, scene):
    kf = plan_keyframes(plan)
    g = replay_guide(kf.times, kf.phase, kf.step, plan=plan, scene=scene, narrow_below=10.0)
    world = CollisionWorld.from_scene(scene, clearance=0.0)  # true distances
    moments = [c for c in g.chapters if c.title.startswith("narrowest passage")]
    assert len(moments) == 2  # one per transfer phase
    for c in moments:
        ph = plan.phases[c.phase]
        d = [min(world.box_distance(s.object), world.held_distance(s.robot, ph.grasp))
             for s in ph.steps]
        j = int(np.argmin(d))
        assert f"{100 * d[j]:.0f} cm clear" in c.title
        assert c.time == pytest.approx(kf.times[[k for k in range(len(kf.times))
                                                 if kf.phase[k] == c.phase
                                                 and kf.step[k] == j][0]])
    # with the default threshold (30 cm) the open sample scene has no narrow passage
    g2 = replay_guide(kf.times, kf.phase, kf.step, plan=plan, scene=scene)
    assert not any(c.title.startswith("narrowest") for c in g2.chapters)


def test_guide_bad_input(plan):
    with pytest.raises(InputError, match="phase"):
        replay_guide([0.0, 1.0], [0], [0, 0], plan=plan)
    with pytest.raises(InputError, match="phase"):
        replay_guide([0.0, 1.0], [0, 7], None, plan=plan)


def test_motion_guide_from_phase_and_step_arrays(plan):
    n = 400
    t = 10.0 + np.arange(n) * 0.1  # motions need not start at 0
    phase = np.repeat([0, 1, 2], [150, 100, 150])
    step = np.full(n, -1)
    step[10:150] = np.minimum((np.arange(140) // 8), len(plan.phases[0].steps) - 1)
    step[260:400] = np.arange(140) // 5
    m = Motion(t=t, q=np.zeros((n, 7)), joint_names=(), urdf="x", box=np.zeros((n, 7)),
               phase=phase, step=step)
    g = motion_guide(m, plan=plan)
    kinds = [c.kind for c in g.chapters]
    assert kinds.count("transfer") == 2 and kinds.count("regrasp") == 1
    reg = next(c for c in g.chapters if c.kind == "regrasp")
    assert reg.time == pytest.approx(15.0)
    assert g.label_at(15.5).startswith("regrasp 1/1 · walk")
    first = len(plan.phases[0].steps)
    assert g.label_at(t[300] - t[0]) == f"transfer 2/2 · pivot {first + 9}/{plan.pivots}"
    assert g.duration == pytest.approx(t[-1] - t[0])
    # a motion without phases: one label; a plan that does not match: numbered phases
    m2 = Motion(t=t, q=np.zeros((n, 7)), joint_names=(), urdf="x", box=np.zeros((n, 7)))
    assert motion_guide(m2).label_at(3.0) == "motion"
    m3 = Motion(t=t, q=np.zeros((n, 7)), joint_names=(), urdf="x", box=np.zeros((n, 7)),
                phase=phase + 5)
    assert motion_guide(m3, plan=plan).label_at(1.0) == "phase 6/8"


def test_show_plan_returns_the_guide_with_the_frame(plan, scene):
    info = show_plan(recording_visualizer(), scene, plan)
    assert info.guide is not None
    assert info.guide.bounds == scene.bounds
    assert info.guide.height >= max(o.height for o in scene.obstacles)
    js = info.guide.to_json()
    assert len(js["chapters"]) == len(info.guide.chapters) and js["bounds"] == list(scene.bounds)


def test_the_replay_legend_explains_every_shape_drawn(plan, scene):
    from pivot_ompl.viz import draw

    info = show_plan(recording_visualizer(), scene, plan)
    legend = info.guide.to_json()["legend"]
    drawn = set(info.nodes) - {"floor"}
    assert len(legend) == len(drawn) >= 6  # one entry per kind of shape, none for absent ones
    texts = " | ".join(text for _, text in legend)
    for word in ("obstacles", "box", "robot", "Reeds-Shepp", "regrasp walk", "pivot corners",
                 "where the robot stands"):
        assert word in texts, word
    colours = {c for c, _ in legend}
    assert draw.css_colour(draw.PIVOT_COLOR) in colours and all(
        re.fullmatch(r"#[0-9a-f]{6}", c) for c in colours)


def _project(pose, pts, aspect=1.6):
    """Pinhole projection (meshcat's 75 deg vertical field of view) to NDC."""
    eye, target = np.array(pose.eye), np.array(pose.target)
    f = target - eye
    f /= np.linalg.norm(f)
    up = np.array([0.0, 0.0, 1.0])
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    tv = math.tan(math.radians(CAMERA_FOV) / 2)
    out = []
    for p in np.asarray(pts, dtype=float):
        d = p - eye
        z = d @ f
        out.append((d @ r / (z * tv * aspect), d @ u / (z * tv), z))
    return np.array(out)


bounds_st = st.tuples(st.floats(-50, 50), st.floats(-50, 50), st.floats(0.5, 40),
                      st.floats(0.5, 40), st.floats(0.2, 4.0))


@settings(max_examples=60, deadline=None)
@given(bounds_st)
def test_overview_frames_the_whole_scene_from_three_quarters(b):
    x0, y0, w, h, height = b
    bounds = (x0, y0, x0 + w, y0 + h)
    pose = overview_pose(bounds, height=height)
    corners = [(x, y, z) for x in (bounds[0], bounds[2]) for y in (bounds[1], bounds[3])
               for z in (0.0, height)]
    ndc = _project(pose, corners)
    assert np.all(ndc[:, 2] > 0) and np.all(np.abs(ndc[:, :2]) <= 1.0)
    # from the front left, above: a three-quarter view
    d = np.array(pose.eye) - np.array(pose.target)
    assert d[0] < 0 and d[1] < 0 and 0.4 < d[2] / np.linalg.norm(d) < 0.8


@settings(max_examples=40, deadline=None)
@given(bounds_st)
def test_top_pose_sees_the_floor_from_above(b):
    x0, y0, w, h, height = b
    bounds = (x0, y0, x0 + w, y0 + h)
    pose = top_pose(bounds, height=height)
    assert pose.eye[2] > height
    assert math.hypot(pose.eye[0] - pose.target[0], pose.eye[1] - pose.target[1]) \
        < 0.01 * pose.eye[2]
    half_v = (pose.eye[2]) * math.tan(math.radians(CAMERA_FOV) / 2)
    assert 0.5 * h <= half_v and 0.5 * w <= half_v * 1.6


def test_follow_pose_keeps_robot_and_box_in_view():
    rng = np.random.default_rng(3)
    for _ in range(50):
        c = rng.uniform(-20, 20, 3) * [1, 1, 0]
        pts = c + rng.uniform([-1, -1, 0], [1, 1, 1.6], (16, 3))
        pose = follow_pose(pts)
        ndc = _project(pose, pts)
        assert np.all(np.abs(ndc[:, :2]) <= 1.0)
        assert pose.distance < 6.0  # close: the robot is not a few pixels high


def test_plan_figure_labels_regrasps_and_walks(plan, scene):
    import matplotlib.pyplot as plt

    fig = plan_figure(plan, scene=scene)
    texts = [t.get_text() for t in fig.axes[0].texts]
    plt.close(fig)
    walk = plan.phases[1]
    assert "regrasp 1: grasp 0→1" in texts
    assert f"walk 1: {walk.length:.1f} m" in texts
    assert len([t for t in texts if t.startswith("regrasp")]) == plan.regrasps


def test_cli_html_carries_the_controls_and_chapters(tmp_path):
    import json

    from pivot_ompl.cli.main import main as cli_main
    from pivot_ompl.viz.samples import write_samples

    s = write_samples(tmp_path)
    for src, extra in ((s.plan, []), (s.motion, ["--plan", str(s.plan), "--urdf", str(s.urdf)])):
        out = tmp_path / f"{src.stem}.html"
        assert cli_main(["replay", str(src), "--scene", str(s.scene), "--html", str(out),
                         *extra]) == 0
        text = out.read_text()
        cfg = json.loads(re.search(r"window\.PIVOT_REPLAY = (\{.*?\});</script>", text).group(1))
        assert cfg["speeds"] == [1, 5, 20, 50] and cfg["bounds"] == [-2.0, -2.0, 4.0, 4.0]
        assert any(c["kind"] == "regrasp" and c["title"].startswith("regrasp 1/1")
                   for c in cfg["chapters"]) == (src == s.plan)  # the sample motion: 1 phase
        assert "window.replayUI" in text and "replayUI.start()" in text


def test_failed_export_keeps_the_existing_file(tmp_path, plan, scene):
    from pivot_ompl.viz import write_html

    vis = recording_visualizer()
    info = show_plan(vis, scene, plan)
    out = tmp_path / "replay.html"
    out.write_text("previous replay")
    bad = info.guide.with_frame(scene.bounds, 2.0)
    bad.extra["oops"] = object()  # not JSON: the export fails while building the page
    with pytest.raises(TypeError):
        write_html(vis, out, guide=bad)
    assert out.read_text() == "previous replay"
    assert not (tmp_path / "replay.html.part").exists()
    write_html(vis, out, guide=info.guide)
    assert "PIVOT_REPLAY" in out.read_text()


def _crowded_plan():
    """The sample plan with four regrasps round one resting box: their labels crowd one spot."""
    import dataclasses

    from pivot_ompl.grasp import BoxGraspModel

    base = sample_plan()
    first = base.phases[0]
    model = BoxGraspModel(base.object_size, base.robot_footprint, base.standoff)
    obj = first.object_end
    walks = []
    for k in range(4):
        a, b = model.robot_pose(obj, k), model.robot_pose(obj, (k + 1) % 4)
        mid = (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), a[2])
        walks.append(TransitPhase(k, (k + 1) % 4, (a, mid, b), obj))
    return dataclasses.replace(base, phases=[first, *walks])


def test_plan_figure_labels_never_overlap():
    import matplotlib.pyplot as plt

    from pivot_ompl.viz.labels import text_box

    fig = plan_figure(_crowded_plan())
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [text_box(t, renderer) for t in fig.axes[0].texts if t.get_text()]
    plt.close(fig)
    assert len(boxes) == 8  # four regrasps, four walks
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a, b)


def test_plan_figure_explains_every_marker_beside_the_floor(plan, scene):
    import matplotlib.pyplot as plt

    fig = plan_figure(plan, scene=scene)
    ax = fig.axes[0]
    legend = ax.get_legend()
    names = [t.get_text() for t in legend.get_texts()]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend_box = legend.get_window_extent(renderer)
    axes_box = ax.get_window_extent(renderer)
    centre = [ln for ln in ax.lines if ln.get_label() == "box centre, grasp 0"]
    plt.close(fig)
    for name in ("start", "goal", "pivot corners", "box footprint on the way",
                 "robot's stance as it grasps", "regrasp walk", "regrasp position",
                 "box centre, grasp 0", "box centre, grasp 1"):
        assert name in names
    assert names.index("box centre, grasp 0") < names.index("box centre, grasp 1")
    assert legend_box.x0 >= axes_box.x1  # beside the floor, never over the goal
    first = plan.phases[0]
    xs, ys = centre[0].get_data()
    assert (xs[0], ys[0]) == pytest.approx(first.object_start[:2])
    assert (xs[-1], ys[-1]) == pytest.approx(first.steps[-1].object[:2])

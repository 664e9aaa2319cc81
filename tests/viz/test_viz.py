"""Unit tests of pivot_ompl.viz: scene tree, animation keys, HTML export, CLI, live server."""

from __future__ import annotations

import math
import os
import re
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
import umsgpack

from pivot_ompl.cli.main import main as cli_main
from pivot_ompl.errors import InputError
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.planfile import load_plan
from pivot_ompl.resources import urdf_path
from pivot_ompl.scene import load_scene
from pivot_ompl.se2 import pose_distance, triangulate
from pivot_ompl.viz import (
    load_motion,
    recording_visualizer,
    show_motion,
    show_plan,
    show_roadmap,
    show_scene,
    write_html,
)
from pivot_ompl.viz.animation import matrix_to_quat_xyzw
from pivot_ompl.viz.motion_view import footsteps
from pivot_ompl.viz.samples import sample_motion_arrays, sample_plan, tiny_urdf, write_samples
from pivot_ompl.viz.shapes import box_transform, prism_mesh, quat_xyzw_to_matrix
from pivot_ompl.viz.timeline import plan_keyframes
from pivot_ompl.viz.urdf_visuals import load_robot

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    return write_samples(tmp_path_factory.mktemp("viz"))


def _animation(vis) -> dict[str, dict[str, list]]:
    """Recorded animation as {node path: {track name: [(time, value), ...]}}."""
    data = umsgpack.unpackb(vis.window.animation)
    out: dict[str, dict[str, list]] = {}
    for a in data["animations"]:
        out[a["path"]] = {tr["name"]: [(k["time"], k["value"]) for k in tr["keys"]]
                          for tr in a["clip"]["tracks"]}
    return out


# -- geometry -------------------------------------------------------------------------------

def test_triangulate_concave_polygon_covers_its_area():
    pts = [(0, 0), (4, 0), (4, 3), (2, 1), (0, 3)]
    tris = triangulate(pts)
    assert len(tris) == 3

    def area(a, b, c):
        return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    assert sum(area(*(pts[i] for i in t)) for t in tris) == pytest.approx(8.0)
    assert all(area(*(pts[i] for i in t)) > 0 for t in tris)
    # clockwise input gives the same area
    assert sum(abs(area(*(pts[::-1][i] for i in t))) for t in triangulate(pts[::-1])) == \
        pytest.approx(8.0)
    verts, faces = prism_mesh(pts, 1.5)
    assert verts.shape == (10, 3) and verts[:, 2].max() == 1.5
    assert len(faces) == 2 * 3 + 2 * 5


@pytest.mark.parametrize("grasp", [0, 1, 2, 3])
def test_box_tilts_towards_robot_about_supporting_edge(grasp):
    model = BoxGraspModel((0.8, 0.6, 1.3))
    obj = (1.0, 2.0, 0.7)
    t = box_transform(model, obj, grasp=grasp, tilt=math.radians(5))
    w, d, h = model.object_size
    corners = np.array([[sx * w / 2, sy * d / 2, sz * h / 2, 1.0]
                        for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    world = (t @ corners.T).T[:, :3]
    assert world[:, 2].min() == pytest.approx(0.0, abs=1e-12)  # rests on an edge
    on_floor = world[np.abs(world[:, 2]) < 1e-9]
    assert len(on_floor) == 2
    robot = model.robot_pose(obj, grasp)
    rc = np.array(robot[:2])
    # the supporting edge is the footprint edge nearest the robot
    edge_dist = np.linalg.norm(on_floor[:, :2] - rc, axis=1).mean()
    flat = np.array(model.object_corners(obj))
    assert edge_dist <= np.sort(np.linalg.norm(flat - rc, axis=1))[:2].mean() + 1e-9
    # the top leans towards the robot
    top = t @ np.array([0, 0, h / 2, 1.0])
    assert np.linalg.norm(top[:2] - rc) < np.linalg.norm(np.array(obj[:2]) - rc)


def test_quaternion_round_trip():
    rng = np.random.default_rng(0)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    r = quat_xyzw_to_matrix(q)
    q2 = matrix_to_quat_xyzw(r)
    assert np.allclose(quat_xyzw_to_matrix(q2), r, atol=1e-9)


# -- plan replay ----------------------------------------------------------------------------

def test_plan_keyframes_follow_the_plan():
    plan = sample_plan()
    kf = plan_keyframes(plan)
    assert np.all(np.diff(kf.times) >= 0) and kf.times[0] == 0.0
    end = np.asarray(kf.box[-1])
    got = (end[0, 3], end[1, 3], math.atan2(end[1, 0], end[0, 0]))
    d, a = pose_distance(got, plan.object_end)
    assert d < 1e-9 and a < 1e-9
    assert end[2, 3] == pytest.approx(0.65)  # upright again at the end
    rob = np.asarray(kf.robot[-1])
    last = plan.phases[-1].robot_end
    assert math.hypot(rob[0, 3] - last[0], rob[1, 3] - last[1]) < 1e-9


def test_show_scene_tree_has_floor_and_obstacles(samples):
    vis = recording_visualizer()
    show_scene(vis, load_scene(samples.scene))
    paths = vis.window.paths()
    for p in ("/meshcat/floor", "/meshcat/obstacles/0", "/meshcat/obstacles/1",
              "/meshcat/obstacles/2"):
        assert p in paths
    assert vis.window.animation is None


def test_show_plan_scene_tree_and_animation(samples):
    vis = recording_visualizer()
    plan = load_plan(samples.plan)
    info = show_plan(vis, load_scene(samples.scene), plan)
    paths = set(vis.window.paths())
    for p in ("/meshcat/box", "/meshcat/robot/footprint", "/meshcat/robot/body",
              "/meshcat/rs_path/0", "/meshcat/rs_path/2", "/meshcat/walks/1",
              "/meshcat/pivots/0", "/meshcat/footsteps/0", "/meshcat/obstacles/2"):
        assert p in paths, p
    assert info.pivots == plan.pivots
    assert sum(p.startswith("/meshcat/pivots/") for p in paths) == plan.pivots
    anim = _animation(vis)
    assert set(anim) == {"/meshcat/box", "/meshcat/robot"}
    for node in anim.values():
        pos = node[".position"]
        assert len(pos) == info.keys
        assert np.linalg.norm(np.subtract(pos[-1][1], pos[0][1])) > 0.5  # moved
    box_pos = np.array([v for _, v in anim["/meshcat/box"][".position"]])
    assert box_pos[-1, :2] == pytest.approx(plan.object_end[:2], abs=1e-4)
    assert info.duration == pytest.approx(anim["/meshcat/box"][".position"][-1][0], abs=1e-3)
    # transfer keys incline the box about a bottom edge: its centre rises above h/2
    assert box_pos[:, 2].max() > 0.65 + 1e-3 and box_pos[:, 2].min() > 0.65 - 1e-6


def test_replay_replaces_previous_one(samples):
    vis = recording_visualizer()
    show_plan(vis, load_scene(samples.scene), load_plan(samples.plan))
    show_motion(vis, load_motion(samples.motion), urdf=samples.urdf)
    paths = vis.window.paths()
    assert not any(p.startswith(("/meshcat/pivots", "/meshcat/obstacles", "/meshcat/robot/body"))
                   for p in paths)
    assert "/meshcat/robot/base_link/visual_0" in paths


def test_plan_without_scene_draws_floor_around_plan():
    vis = recording_visualizer()
    show_plan(vis, None, sample_plan())
    paths = vis.window.paths()
    assert "/meshcat/floor" in paths and not any("obstacles" in p for p in paths)


def test_show_roadmap():
    vis = recording_visualizer()
    info = show_roadmap(vis, [(0, 0, 0), (1, 0, 0.5), (1, 1, 0)], [(0, 1), (1, 2)], name="prm")
    assert info.nodes == ("roadmap/prm",)
    assert {"/meshcat/roadmap/prm/nodes", "/meshcat/roadmap/prm/edges"} <= set(vis.window.paths())


# -- motion replay --------------------------------------------------------------------------

def test_load_motion_checks_contract(tmp_path, samples):
    m = load_motion(samples.motion)
    assert m.q.shape[1] == 7 + len(m.joint_names) and m.duration == pytest.approx(4.0)
    arrays = sample_motion_arrays(duration=1.0)
    bad = dict(arrays)
    bad.pop("box")
    np.savez(tmp_path / "nobox.npz", urdf=np.array("x.urdf"), **bad)
    with pytest.raises(InputError, match="box"):
        load_motion(tmp_path / "nobox.npz")
    bad = dict(arrays, joint_names=np.array(["a"]))
    np.savez(tmp_path / "names.npz", urdf=np.array("x.urdf"), **bad)
    with pytest.raises(InputError, match="joint_names"):
        load_motion(tmp_path / "names.npz")
    (tmp_path / "junk.npz").write_text("not a zip")
    with pytest.raises(InputError):
        load_motion(tmp_path / "junk.npz")
    # pinocchio's names with the root joints are accepted
    ok = dict(arrays, joint_names=np.array(["universe", "root_joint", *arrays["joint_names"]]))
    np.savez(tmp_path / "pin.npz", urdf=np.array("x.urdf"), **ok)
    assert load_motion(tmp_path / "pin.npz").joint_names == tuple(arrays["joint_names"])


def test_kinematics_match_yourdfpy(tmp_path):
    import yourdfpy

    path = tmp_path / "tiny.urdf"
    path.write_text(tiny_urdf())
    model = load_robot(path)
    ref = yourdfpy.URDF.load(str(path), load_meshes=False)
    cfg = {"left_hip": 0.3, "left_ankle": -0.2, "right_hip": -0.4, "right_ankle": 0.1,
           "shoulder": 1.1}
    ref.update_cfg(cfg)
    names = tuple(cfg)
    vals = model.joint_values(np.array([[cfg[n] for n in names]]), names)
    wt = model.world_transforms(np.eye(4)[None], vals, ["left_foot", "arm", "head"])
    for link in ("left_foot", "arm", "head"):
        assert np.allclose(wt[link][0], ref.get_transform(link, "base_link"), atol=1e-9)


def test_show_motion_tree_tracks_and_footsteps(samples):
    vis = recording_visualizer()
    m = load_motion(samples.motion)
    info = show_motion(vis, m, scene=load_scene(samples.scene), fps=20,
                       plan=load_plan(samples.plan), urdf=samples.urdf)
    paths = set(vis.window.paths())
    for p in ("/meshcat/box", "/meshcat/robot/base_link/visual_0",
              "/meshcat/robot/base_link/left_leg/left_foot/visual_0",
              "/meshcat/robot/base_link/arm/visual_0", "/meshcat/robot/base_link/head/visual_0",
              "/meshcat/obstacles/0", "/meshcat/zmp", "/meshcat/footsteps/0",
              "/meshcat/rs_path/0", "/meshcat/pivots/0"):
        assert p in paths, p
    anim = _animation(vis)
    root = anim["/meshcat/robot/base_link"]
    assert set(root) == {".position", ".quaternion"}
    assert np.linalg.norm(np.subtract(root[".position"][-1][1], root[".position"][0][1])) > 1.0
    arm = anim["/meshcat/robot/base_link/arm"]
    assert set(arm) == {".quaternion"}  # revolute: rotation only
    assert "/meshcat/robot/base_link/head" not in anim  # fixed joint: not animated
    box = anim["/meshcat/box"]
    assert np.subtract(box[".position"][-1][1], box[".position"][0][1])[0] > 1.0
    assert 75 <= info.keys <= 85  # samples at 20 fps over 4 s
    # keys linear interpolation reproduces are dropped: the root walks in a straight line
    assert len(root[".position"]) <= 10 < info.keys
    assert len(root[".position"]) < len(arm[".quaternion"]) <= info.keys
    assert info.footsteps >= 2  # both feet rest during the first second


def test_reduce_keys_stays_within_tolerance():
    from pivot_ompl.viz.animation import reduce_keys

    t = np.linspace(0, 20, 501)
    sig = np.stack([np.sin(t), np.where(t < 10, 0.0, t - 10), 0.3 * np.cos(0.5 * t)], axis=1)
    values = np.stack([sig, sig[:, ::-1]])
    keep, out = reduce_keys(t, values, np.array([1e-3, 0.0]))
    assert keep[1].all() and np.array_equal(out[1], values[1])  # tol 0 keeps everything
    k = keep[0]
    assert k[0] and k[-1] and k.sum() < 0.6 * len(t)
    interp = np.stack([np.interp(t, t[k], out[0, k, d]) for d in range(3)], axis=1)
    assert np.abs(interp - values[0]).max() <= 2e-3


def test_footsteps_detects_rest_periods():
    t = np.linspace(0, 3, 301)
    x = np.where(t < 1, 0.0, np.where(t < 2, 0.3 * (t - 1), 0.3))
    z = np.where((t > 1) & (t < 2), 0.05 * np.sin(np.pi * (t - 1)), 0.0)
    tf = np.repeat(np.eye(4)[None], len(t), axis=0)
    tf[:, 0, 3], tf[:, 2, 3] = x, z
    steps = footsteps(tf, t)
    assert len(steps) == 2
    assert steps[0][0] == pytest.approx(0.0) and steps[1][0] == pytest.approx(0.3)


# -- HTML export ----------------------------------------------------------------------------

def test_html_is_self_contained(samples, tmp_path):
    vis = recording_visualizer()
    show_plan(vis, load_scene(samples.scene), load_plan(samples.plan))
    res = write_html(vis, tmp_path / "r.html")
    text = res.path.read_text()
    assert res.size_bytes == res.path.stat().st_size and 0.5e6 < res.size_bytes < 3e6
    assert not re.search(r"<script[^>]+src\s*=", text, re.I)
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", text, re.I)
    assert not re.search(r"""\bfetch\(\s*["']https?:""", text)
    assert "new MeshCat.Viewer" in text and "window.viewer = viewer" in text
    assert res.commands == len(vis.window.commands())
    # the animation is the last command, after every object
    last = umsgpack.unpackb(vis.window.commands()[-1])
    assert last["type"] == "set_animation" and last["options"]["play"] is True


def test_html_compresses_large_animation(samples, tmp_path):
    import base64
    import gzip
    import json

    vis = recording_visualizer()
    show_motion(vis, load_motion(samples.motion), urdf=samples.urdf)
    text = write_html(vis, tmp_path / "m.html").path.read_text()
    cmds = json.loads(re.search(r"var cmds = (\[.*?\]);\n", text, re.S).group(1))
    packed = [c for c in cmds if isinstance(c, dict)]
    assert packed  # the animation is stored gzip-compressed
    assert gzip.decompress(base64.b64decode(packed[-1]["gz"])) == vis.window.commands()[-1]


def test_write_html_needs_recording_visualizer(tmp_path):
    class Fake:
        window = object()

    with pytest.raises(InputError):
        write_html(Fake(), tmp_path / "x.html")


def _long_plan():
    """A plan of 24 transfer phases with regrasps in between (a few hundred pivots)."""
    from pivot_ompl.pivoting.steering import PivotSteering
    from pivot_ompl.pivoting.transfer import transfer_phase
    from pivot_ompl.planfile import Plan, TransitPhase

    model = BoxGraspModel((0.8, 0.6, 1.3))
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    phases = []
    obj = (0.0, 0.0, 0.0)
    grasp = 0
    for i in range(24):
        goal = (obj[0] + 1.5 * math.cos(0.5 * i), obj[1] + 1.5 * math.sin(0.5 * i),
                obj[2] + 0.4)
        ph = transfer_phase(model, steering, [obj, goal], grasp)
        phases.append(ph)
        obj = ph.object_end
        nxt = (grasp + 1) % 4
        phases.append(TransitPhase(grasp, nxt, (ph.robot_end, model.robot_pose(obj, nxt)), obj))
        grasp = nxt
    return Plan("free", "exact", (0.8, 0.6, 1.3), (0.4, 0.7), 0.25, math.pi / 8,
                (0.0, 0.0, 0.0), phases)


def test_long_plan_html_size_and_speed(tmp_path):
    plan = _long_plan()
    t0 = time.perf_counter()
    vis = recording_visualizer()
    show_plan(vis, None, plan)
    res = write_html(vis, tmp_path / "long.html")
    elapsed = time.perf_counter() - t0
    print(f"long plan: {plan.pivots} pivots, {res.size_bytes / 1e6:.2f} MB, {elapsed:.2f} s")
    assert res.size_bytes < 20e6 and elapsed < 10.0


def test_long_motion_html_size_and_speed(tmp_path):
    """A fig10-sized motion: 150 s at 200 Hz of a 31-joint robot (HRP-2 has 30 + hands)."""
    links, joints = ['<link name="base_link"><visual><geometry><box size="0.3 0.3 0.5"/>'
                     '</geometry></visual></link>'], []
    for chain in range(4):
        parent = "base_link"
        for k in range(8 if chain < 3 else 7):
            name = f"c{chain}_l{k}"
            links.append(f'<link name="{name}"><visual><geometry><cylinder radius="0.04" '
                         f'length="0.2"/></geometry></visual></link>')
            joints.append(f'<joint name="j_{name}" type="revolute"><parent link="{parent}"/>'
                          f'<child link="{name}"/><origin xyz="0 0.1 -0.1"/><axis xyz="0 1 0"/>'
                          '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
            parent = name
    urdf = tmp_path / "big.urdf"
    urdf.write_text('<robot name="big">' + "".join(links + joints) + "</robot>")
    names = [j.split('"')[1] for j in joints]
    t = np.arange(0, 150, 0.005)
    n = len(t)
    q = np.zeros((n, 7 + len(names)))
    q[:, 0] = 0.05 * t
    q[:, 6] = 1.0
    q[:, 7:] = 0.3 * np.sin(t[:, None] + np.arange(len(names)))
    box = np.zeros((n, 7))
    box[:, 0], box[:, 2], box[:, 6] = q[:, 0] + 1, 0.65, 1.0
    path = tmp_path / "big.npz"
    np.savez(path, t=t, q=q, joint_names=np.array(names), urdf=np.array(str(urdf)), box=box)
    t0 = time.perf_counter()
    vis = recording_visualizer()
    show_motion(vis, load_motion(path), urdf=urdf)
    res = write_html(vis, tmp_path / "big.html")
    elapsed = time.perf_counter() - t0
    print(f"long motion: {res.size_bytes / 1e6:.2f} MB, {elapsed:.2f} s")
    assert res.size_bytes < 20e6 and elapsed < 10.0


# -- CLI --------------------------------------------------------------------------------------

def test_cli_replay_plan_and_motion(samples, tmp_path, capsys):
    out = tmp_path / "p.html"
    assert cli_main(["replay", str(samples.plan), "--scene", str(samples.scene),
                     "--html", str(out)]) == 0
    assert out.is_file() and str(out) in capsys.readouterr().out
    out2 = tmp_path / "m.html"
    assert cli_main(["replay", str(samples.motion), "--html", str(out2)]) == 2  # foreign URDF
    assert cli_main(["replay", str(samples.motion), "--urdf", str(samples.urdf), "--html",
                     str(out2)]) == 0
    assert out2.is_file()
    out3 = tmp_path / "mp.html"
    assert cli_main(["replay", str(samples.motion), "--plan", str(samples.plan),
                     "--scene", str(samples.scene), "--urdf", str(samples.urdf),
                     "--html", str(out3)]) == 0
    assert out3.stat().st_size > out2.stat().st_size  # + paths, pivots and obstacles


def test_cli_replay_warns_without_scene(samples, tmp_path, caplog):
    with caplog.at_level("WARNING"):
        assert cli_main(["replay", str(samples.plan), "--html", str(tmp_path / "x.html")]) == 0
    assert any("no obstacles" in r.getMessage() for r in caplog.records)


def test_cli_replay_finds_scene_by_name(samples, tmp_path, monkeypatch, capsys):
    import pivot_ompl.cli.scenes as scenes_cli

    monkeypatch.setattr(scenes_cli, "shipped_scenes", lambda: {"sample": samples.scene})
    vis = recording_visualizer()
    monkeypatch.setattr("pivot_ompl.viz.recorder.recording_visualizer", lambda **k: vis)
    assert cli_main(["replay", str(samples.plan), "--html", str(tmp_path / "x.html")]) == 0
    assert "/meshcat/obstacles/2" in vis.window.paths()


def test_cli_replay_bad_input(tmp_path, samples):
    assert cli_main(["replay", str(tmp_path / "missing.json")]) == 2
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "other"}')
    assert cli_main(["replay", str(bad)]) == 2
    assert cli_main(["replay", str(samples.plan), "--scene", str(tmp_path / "no.yaml")]) == 2
    assert cli_main(["replay", str(samples.plan), "--fps", "0"]) == 2
    assert cli_main(["replay", str(samples.plan), "--plan", str(samples.plan)]) == 2


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().split(")")[1].split()[0] == "Z")


def _as_from_a_terminal() -> None:
    """Ctrl-C's default disposition in the server, as a terminal gives it: a suite started
    from a background job inherits SIGINT ignored, and the server's Ctrl-C would never come."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_server(plan: Path, scene: Path) -> tuple[subprocess.Popen, str, int]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "pivot_ompl.cli", "replay", str(plan), "--scene", str(scene),
         "--serve"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=_as_from_a_terminal)
    url = pid = None
    deadline = time.monotonic() + 30
    while url is None and time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            break
        m = re.search(r"(http://\S+)", line)
        if m:
            url = m.group(1)
    assert url, proc.stderr.read() if proc.poll() is not None else "no URL printed"
    # the server pid is logged before the URL is printed
    err = ""
    while pid is None and time.monotonic() < deadline:
        err += proc.stderr.readline()
        m = re.search(r"meshcat server pid (\d+)", err)
        if m:
            pid = int(m.group(1))
    assert pid
    return proc, url, pid


def test_serve_two_viewers_and_clean_stop(samples):
    a, url_a, pid_a = _start_server(samples.plan, samples.scene)
    try:
        b, url_b, pid_b = _start_server(samples.plan, samples.scene)
    except BaseException:
        a.send_signal(signal.SIGINT)
        raise
    try:
        assert url_a != url_b  # no port clash
        for url in (url_a, url_b):
            with urllib.request.urlopen(url, timeout=10) as r:
                body = r.read()
                assert r.status == 200 and b"MeshCat.Viewer" in body and b"PIVOT_REPLAY" in body
        assert _pid_alive(pid_a) and _pid_alive(pid_b)
    finally:
        a.send_signal(signal.SIGINT)  # Ctrl-C
        b.send_signal(signal.SIGTERM)
        ra, rb = a.wait(timeout=20), b.wait(timeout=20)
    assert (ra, rb) == (0, 0)
    deadline = time.monotonic() + 10
    while (_pid_alive(pid_a) or _pid_alive(pid_b)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _pid_alive(pid_a) and not _pid_alive(pid_b), "stray meshcat server"


@pytest.mark.skipif(not urdf_path().is_file(),
                    reason="robots/hrp2/hrp2.urdf not written yet")
def test_hrp2_motion_replay(tmp_path):
    """HRP-2 from robots/hrp2 with pinocchio's joint order; kinematics agree with pinocchio."""
    import pinocchio as pin

    from pivot_ompl.viz.samples import write_urdf_motion

    urdf = urdf_path()
    path = write_urdf_motion(tmp_path, urdf)
    pmodel = pin.buildModelFromUrdf(str(urdf), pin.JointModelFreeFlyer())
    motion = load_motion(path)
    vis = recording_visualizer()
    info = show_motion(vis, motion)
    model = load_robot(urdf)
    paths = set(vis.window.paths())
    for link in ("left_foot", "right_foot"):  # sole frames: their parents carry the visuals
        parent = model.joints[link].parent
        assert any(p.startswith(f"/meshcat/robot/{model.node_path(parent)}/visual_")
                   for p in paths)
    assert sum(p.startswith("/meshcat/robot/") for p in paths) >= 20
    t, q = motion.t, motion.q
    assert info.duration == pytest.approx(t[-1], abs=0.05)
    data = pmodel.createData()
    k = len(t) // 2
    pin.framesForwardKinematics(pmodel, data, q[k])
    from pivot_ompl.viz.motion_view import pose7_to_matrix

    wt = model.world_transforms(pose7_to_matrix(q[k:k + 1, :7]),
                                model.joint_values(q[k:k + 1, 7:], motion.joint_names),
                                ["left_foot", "right_foot"])
    for link, tf in wt.items():
        assert np.allclose(tf[0], data.oMf[pmodel.getFrameId(link)].homogeneous, atol=1e-9)

"""Browser test of the offline replay HTML: headless Chromium driven over DevTools (CDP).

No extra dependency: Chromium is started with ``--remote-debugging-pipe`` and spoken to over
its fds 3/4 (NUL-separated JSON). Needs Debian's ``chromium`` (``/usr/bin/chromium``); the
test is skipped, with that reason, only when no Chromium binary exists.
Screenshots go to ``test-artifacts/`` under the repository root.
"""

from __future__ import annotations

import base64
import fcntl
import json
import math
import os
import select
import shutil
import subprocess
import time
from pathlib import Path

import pytest
from factories import ROOT as REPO  # noqa: E402

from pivot_ompl.cli.main import main as cli_main
from pivot_ompl.resources import urdf_path
from pivot_ompl.viz.samples import write_samples

ARTIFACTS = REPO / "test-artifacts"
CHROMIUM_CANDIDATES = ("/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=960,720",
         "--hide-scrollbars", "--mute-audio")


def find_chromium() -> str | None:
    for c in CHROMIUM_CANDIDATES:
        if os.access(c, os.X_OK):
            return c
    return shutil.which("chromium") or shutil.which("chromium-browser")


CHROMIUM = find_chromium()
NO_BROWSER = ("no Chromium browser installed (/usr/bin/chromium missing): "
              "apt-get install -y chromium chromium-driver")
#: Set (e.g. in CI) to turn the missing-browser skip into a failure.
REQUIRE_ENV = "PIVOT_OMPL_REQUIRE_BROWSER"
pytestmark = [pytest.mark.browser, pytest.mark.timed]


class CDPError(RuntimeError):
    pass


class Chromium:
    """Headless Chromium with a DevTools session on one page, over --remote-debugging-pipe."""

    def __init__(self, binary: str, profile: Path) -> None:
        to_chrome_r, self._w = os.pipe()
        self._r, from_chrome_w = os.pipe()

        def child_fds() -> None:  # runs in the child before exec
            a = fcntl.fcntl(to_chrome_r, fcntl.F_DUPFD, 10)
            b = fcntl.fcntl(from_chrome_w, fcntl.F_DUPFD, 10)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.log = open(profile.parent / "chromium.log", "wb")  # noqa: SIM115
        self.proc = subprocess.Popen(
            [binary, *FLAGS, f"--user-data-dir={profile}", "--remote-debugging-pipe",
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self.log, stderr=self.log,
            pass_fds=(3, 4), preexec_fn=child_fds, start_new_session=True)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buf = b""
        self._id = 0
        self.events: list[dict] = []
        self.session: str | None = None

    def close(self) -> None:
        try:
            if self.proc.poll() is None:
                try:
                    self.call("Browser.close", timeout=5)
                except Exception:  # noqa: BLE001
                    pass
                try:
                    self.proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait()
        finally:
            for fd in (self._w, self._r):
                try:
                    os.close(fd)
                except OSError:
                    pass
            self.log.close()

    def _read_message(self, deadline: float) -> dict:
        while b"\0" not in self._buf:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no answer from Chromium")
            ready, _, _ = select.select([self._r], [], [], left)
            if ready:
                chunk = os.read(self._r, 1 << 20)
                if not chunk:
                    raise CDPError(f"Chromium closed the pipe (exit {self.proc.poll()})")
                self._buf += chunk
        msg, self._buf = self._buf.split(b"\0", 1)
        return json.loads(msg)

    def call(self, method: str, params: dict | None = None, *, session: bool = True,
             timeout: float = 30.0) -> dict:
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            ans = self._read_message(deadline)
            if "method" in ans:
                self.events.append(ans)
            if ans.get("id") == self._id:
                if "error" in ans:
                    raise CDPError(f"{method}: {ans['error']}")
                return ans.get("result", {})

    def attach_page(self) -> None:
        deadline = time.monotonic() + 30
        while True:
            targets = self.call("Target.getTargets", session=False)["targetInfos"]
            pages = [t for t in targets if t["type"] == "page"]
            if pages:
                break
            if time.monotonic() > deadline:
                raise CDPError("no page target")
            time.sleep(0.1)
        self.session = self.call("Target.attachToTarget",
                                 {"targetId": pages[0]["targetId"], "flatten": True},
                                 session=False)["sessionId"]
        self.call("Page.enable")
        self.call("Runtime.enable")
        self.call("Network.enable")

    def evaluate(self, expr: str, *, timeout: float = 30.0):
        res = self.call("Runtime.evaluate", {"expression": expr, "returnByValue": True,
                                             "awaitPromise": True}, timeout=timeout)
        if "exceptionDetails" in res:
            raise CDPError(f"JS error in {expr[:60]!r}: {res['exceptionDetails']}")
        return res["result"].get("value")

    def wait_for(self, expr: str, *, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while not self.evaluate(expr):
            thrown = [e for e in self.events if e["method"] == "Runtime.exceptionThrown"]
            if thrown:
                raise CDPError(f"page error: {thrown[0]['params']['exceptionDetails']}")
            if time.monotonic() > deadline:
                raise TimeoutError(f"waiting for {expr}")
            time.sleep(0.1)

    def screenshot(self, path: Path) -> bytes:
        data = base64.b64decode(self.call("Page.captureScreenshot", {"format": "png"},
                                          timeout=60)["data"])
        path.write_bytes(data)
        return data


# JS helpers evaluated in the page: tree lookup without creating nodes, world placement.
HELPERS = """
window.__node = function (path) {
  let n = viewer.scene_tree;
  for (const p of path.split('/').filter(x => x)) { n = n.children[p]; if (!n) return null; }
  return n;
};
window.__world = function (path) {
  const n = __node(path); if (!n) return null;
  n.object.updateMatrixWorld(true); return Array.from(n.object.matrixWorld.elements);
};
window.__frame = function () {
  return new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))));
};
true
"""


def _dist(a: list[float], b: list[float]) -> float:
    return max(abs(x - y) for x, y in zip(a, b, strict=True))


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    if CHROMIUM is None:
        if os.environ.get(REQUIRE_ENV):
            pytest.fail(f"{NO_BROWSER} (and {REQUIRE_ENV} is set)")
        pytest.skip(NO_BROWSER)
    tmp = tmp_path_factory.mktemp("chromium")
    b = Chromium(CHROMIUM, tmp / "profile")
    try:
        b.attach_page()
        yield b
    finally:
        b.close()
    assert b.proc.poll() is not None, "Chromium still running after the test"


def _open(browser: Chromium, html: Path, fragment: str = "") -> None:
    browser.events.clear()
    browser.call("Page.navigate", {"url": html.resolve().as_uri() + fragment})
    browser.wait_for("window.replayLoaded === true || !!window.replayError", timeout=60)
    assert browser.evaluate("window.replayError || ''") == ""
    browser.evaluate(HELPERS)
    # offline: the page asked for nothing but itself (and data: URLs)
    urls = [e["params"]["request"]["url"] for e in browser.events
            if e["method"] == "Network.requestWillBeSent"]
    assert urls and all(u.startswith(("file:", "data:", "about:")) for u in urls), urls


def _seek_and_shoot(browser: Chromium, t: float, name: str, paths: list[str]):
    browser.evaluate(f"viewer.animator.seek({t}); viewer.animator.display_progress({t}); "
                     "__frame()")
    browser.evaluate("__frame()")
    poses = {p: browser.evaluate(f"__world({json.dumps(p)})") for p in paths}
    png = browser.screenshot(ARTIFACTS / name)
    return poses, png


def test_motion_replay_in_chromium(browser, tmp_path):
    ARTIFACTS.mkdir(exist_ok=True)
    s = write_samples(tmp_path)
    html = tmp_path / "motion.html"
    assert cli_main(["replay", str(s.motion), "--scene", str(s.scene), "--plan", str(s.plan),
                     "--urdf", str(s.urdf), "--html", str(html)]) == 0
    _open(browser, html)

    # The scene holds obstacles, box and robot links (with their visual objects).
    for p in ("meshcat/floor", "meshcat/obstacles/0", "meshcat/obstacles/1",
              "meshcat/obstacles/2", "meshcat/box", "meshcat/robot/base_link",
              "meshcat/robot/base_link/left_leg/left_foot",
              "meshcat/robot/base_link/arm", "meshcat/footsteps/0", "meshcat/rs_path/0",
              "meshcat/pivots/0", "meshcat/zmp"):
        assert browser.evaluate(f"__node({json.dumps(p)}) !== null"), p
    n_meshes = browser.evaluate(
        "(() => { let k = 0; __node('meshcat/robot').object.traverse(o => { if (o.isMesh) k++; });"
        " return k; })()")
    assert n_meshes >= 7  # every link's visual
    # The animation was loaded and started playing once the scene was built.
    assert browser.evaluate("viewer.animator.actions.length") > 0
    assert browser.evaluate("viewer.animator.duration") == pytest.approx(4.0, abs=0.05)
    # it started by itself: still playing, or (slow machine) already played to some time
    assert browser.evaluate("viewer.animator.playing || viewer.animator.time > 0") is True

    browser.evaluate("viewer.animator.pause(); true")
    paths = ["meshcat/box", "meshcat/robot/base_link", "meshcat/robot/base_link/arm"]
    p1, png1 = _seek_and_shoot(browser, 0.5, "motion_t0.5.png", paths)
    p2, png2 = _seek_and_shoot(browser, 3.5, "motion_t3.5.png", paths)
    assert browser.evaluate("viewer.animator.playing") is False
    for p in paths:
        assert _dist(p1[p], p2[p]) > 0.05, f"{p} did not move"
    # world x of the box moved by about 1.2 m * (3.5-1)/3 along the walk
    assert abs(p2["meshcat/box"][12] - p1["meshcat/box"][12]) > 0.5 or \
        abs(p2["meshcat/box"][13] - p1["meshcat/box"][13]) > 0.5 or \
        abs(p2["meshcat/box"][14] - p1["meshcat/box"][14]) > 0.5
    assert png1 != png2
    assert len(png1) > 5000 and len(png2) > 5000  # something was rendered


def test_plan_replay_in_chromium(browser, tmp_path):
    ARTIFACTS.mkdir(exist_ok=True)
    s = write_samples(tmp_path)
    html = tmp_path / "plan.html"
    assert cli_main(["replay", str(s.plan), "--scene", str(s.scene), "--html", str(html)]) == 0
    _open(browser, html)
    for p in ("meshcat/obstacles/2", "meshcat/box", "meshcat/robot/footprint",
              "meshcat/rs_path/0", "meshcat/pivots/0", "meshcat/footsteps/0"):
        assert browser.evaluate(f"__node({json.dumps(p)}) !== null"), p
    assert browser.evaluate("viewer.animator.playing || viewer.animator.time > 0") is True
    browser.evaluate("viewer.animator.pause(); true")
    dur = browser.evaluate("viewer.animator.duration")
    paths = ["meshcat/box", "meshcat/robot"]
    p1, png1 = _seek_and_shoot(browser, 0.2 * dur, "plan_early.png", paths)
    p2, png2 = _seek_and_shoot(browser, 0.9 * dur, "plan_late.png", paths)
    for p in paths:
        assert _dist(p1[p], p2[p]) > 0.1, f"{p} did not move"
    assert png1 != png2


def test_live_viewer_in_chromium(browser, tmp_path):
    """The --serve path: a browser connecting to the live server gets scene and animation."""
    from pivot_ompl.planfile import load_plan
    from pivot_ompl.scene import load_scene
    from pivot_ompl.viz import show_plan
    from pivot_ompl.viz.serve import LiveViewer

    s = write_samples(tmp_path)
    with LiveViewer() as live:
        show_plan(live.vis, load_scene(s.scene), load_plan(s.plan))
        browser.call("Page.navigate", {"url": live.url})
        browser.wait_for("!!window.viewer && viewer.animator.actions.length > 0", timeout=60)
        browser.evaluate(HELPERS)
        browser.wait_for("__node('meshcat/footsteps/0') !== null && "
                         "__node('meshcat/obstacles/2') !== null", timeout=30)
        assert browser.evaluate("__node('meshcat/box/<object>') !== null")
        assert browser.evaluate("viewer.animator.playing") is True
        t0 = browser.evaluate("viewer.animator.time")
        time.sleep(1.0)
        assert browser.evaluate("viewer.animator.time") > t0  # it plays
        pid = live.pid
    browser.call("Page.navigate", {"url": "about:blank"})
    assert not Path(f"/proc/{pid}").exists() or \
        Path(f"/proc/{pid}/stat").read_text().split(")")[1].split()[0] == "Z"


HRP2 = urdf_path()


@pytest.mark.skipif(not HRP2.is_file(), reason="robots/hrp2/hrp2.urdf not in this checkout")
def test_hrp2_motion_in_chromium(browser, tmp_path):
    from pivot_ompl.viz.samples import write_urdf_motion
    from pivot_ompl.viz.urdf_visuals import load_robot

    ARTIFACTS.mkdir(exist_ok=True)
    npz = write_urdf_motion(tmp_path, HRP2, duration=2.0)
    html = tmp_path / "hrp2.html"
    assert cli_main(["replay", str(npz), "--html", str(html)]) == 0
    _open(browser, html)
    model = load_robot(HRP2)
    links = [lk for lk in model.links if lk.startswith(("LLEG", "RARM", "CHEST", "HEAD"))]
    for lk in links:
        assert browser.evaluate(f"__node({json.dumps('meshcat/robot/' + model.node_path(lk))})"
                                " !== null"), lk
    n_meshes = browser.evaluate(
        "(() => { let k = 0; __node('meshcat/robot').object.traverse(o => { if (o.isMesh) k++; });"
        " return k; })()")
    assert n_meshes >= 20
    browser.evaluate("viewer.animator.pause(); true")
    hand = "meshcat/robot/" + model.node_path("RARM_LINK6")
    paths = ["meshcat/box", "meshcat/robot/" + model.root, hand]
    p1, png1 = _seek_and_shoot(browser, 0.2, "hrp2_t0.2.png", paths)
    p2, png2 = _seek_and_shoot(browser, 1.8, "hrp2_t1.8.png", paths)
    for p in paths:
        assert _dist(p1[p], p2[p]) > 0.05, f"{p} did not move"
    assert png1 != png2
    # follow mode frames the real robot model too, big enough to watch
    _viewport(browser)
    browser.evaluate(VIEW_HELPERS)
    browser.evaluate("replayUI.setView('follow'); replayUI.seek(1.0); true")
    _settle(browser)
    frac = browser.evaluate("__projectedFraction('meshcat/robot')")
    browser.screenshot(ARTIFACTS / "hrp2_follow.png")
    assert frac >= 0.05, f"HRP-2 covers {frac:.3f} of the viewport"


# -- the replay's own controls: camera views, follow mode, speeds, chapters ------------------

#: In-page measurements of the camera's view (independent of the page's own script).
VIEW_HELPERS = """
window.__cam = function () { const c = viewer.camera; c.updateMatrixWorld(true);
  c.updateProjectionMatrix(); return c; };
window.__ndc = function (pts) {  // scene points (z up) -> normalised device coordinates
  const T = MeshCat.THREE, c = __cam(); viewer.scene.updateMatrixWorld(true);
  return pts.map(p => { const v = new T.Vector3(p[0], p[1], p[2])
    .applyMatrix4(viewer.scene.matrixWorld).project(c); return [v.x, v.y, v.z]; });
};
window.__eye = function () {  // camera position in the scene's frame (z up)
  const e = new MeshCat.THREE.Vector3(); __cam().getWorldPosition(e);
  e.applyMatrix4(viewer.scene.matrixWorld.clone().invert()); return [e.x, e.y, e.z];
};
window.__projectedFraction = function (path) {  // bbox of a node on screen / viewport
  const T = MeshCat.THREE, n = __node(path); n.object.updateMatrixWorld(true);
  const b = new T.Box3().setFromObject(n.object), pts = [];
  for (const x of [b.min.x, b.max.x]) for (const y of [b.min.y, b.max.y])
    for (const z of [b.min.z, b.max.z]) pts.push([x, y, z]);
  const q = __ndc(pts).filter(v => v[2] < 1);
  if (q.length < 8) return 0;
  const cl = v => Math.max(-1, Math.min(1, v));
  const xs = q.map(v => cl(v[0])), ys = q.map(v => cl(v[1]));
  return (Math.max(...xs) - Math.min(...xs)) * (Math.max(...ys) - Math.min(...ys)) / 4;
};
window.__rate = async function (ms) {  // animation seconds per wall second while playing
  const a = viewer.animator;
  const t0 = replayUI.time(), w0 = a.clock.oldTime;
  await new Promise(r => setTimeout(r, ms));
  const t1 = replayUI.time(), w1 = a.clock.oldTime;  // the clock ticks with each update
  return (t1 - t0) / ((w1 - w0) / 1000);
};
window.__settled = function () { return !replayUI.state.glide; };
true
"""


def _viewport(browser: Chromium, width: int = 1280, height: int = 800) -> None:
    browser.call("Emulation.setDeviceMetricsOverride",
                 {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})


#: Horizontal distance (m) from the camera's target to the robot's centre.
TARGET_FROM_ROBOT = """(() => { const T = MeshCat.THREE; viewer.scene.updateMatrixWorld(true);
  const inv = viewer.scene.matrixWorld.clone().invert();
  const tgt = viewer.controls.target.clone().applyMatrix4(viewer.camera.parent.matrixWorld)
    .applyMatrix4(inv);
  const c = new T.Box3().setFromObject(__node('meshcat/robot').object).applyMatrix4(inv)
    .getCenter(new T.Vector3());
  return Math.hypot(tgt.x - c.x, tgt.y - c.y); })()"""


def _settle(browser: Chromium) -> None:
    browser.wait_for("__settled()", timeout=20)
    browser.evaluate("__frame()")
    browser.evaluate("__frame()")


def _label(browser: Chromium) -> str:
    return browser.evaluate("document.getElementById('pr-label').dataset.label")


def _floor_corners_in_view(browser: Chromium, bounds) -> bool:
    x0, y0, x1, y1 = bounds
    corners = [[x0, y0, 0], [x1, y0, 0], [x0, y1, 0], [x1, y1, 0]]
    ndc = browser.evaluate(f"__ndc({json.dumps(corners)})")
    return all(abs(v[0]) <= 1.0 and abs(v[1]) <= 1.0 and v[2] < 1 for v in ndc)


def test_replay_controls_in_chromium(browser, tmp_path):
    """Framed on load, then following; chapters seek and relabel; 20x plays 20x as fast."""
    from pivot_ompl.planfile import load_plan
    from pivot_ompl.scene import load_scene
    from pivot_ompl.viz import ReplayTiming, recording_visualizer, show_plan, write_html

    ARTIFACTS.mkdir(exist_ok=True)
    s = write_samples(tmp_path)
    scene = load_scene(s.scene)
    bounds = scene.bounds
    html = tmp_path / "plan.html"
    vis = recording_visualizer()
    # slow timing (about 4.5 min) so that 2 s at 50x stay inside the animation
    info = show_plan(vis, scene, load_plan(s.plan),
                     timing=ReplayTiming(pivot_speed=0.05, walk_speed=0.05, turn_speed=0.1))
    assert info.duration > 150
    write_html(vis, html, guide=info.guide)
    _viewport(browser)
    # on load: the scene framed from a three-quarter view (held here so the test sees it)
    _open(browser, html, "#overview=600")
    browser.evaluate(VIEW_HELPERS)
    browser.evaluate("__frame()")
    assert browser.evaluate("replayUI.state.view") == "overview"
    assert _floor_corners_in_view(browser, bounds)
    view = browser.evaluate("__eye()")
    cx, cy = 0.5 * (bounds[0] + bounds[2]), 0.5 * (bounds[1] + bounds[3])
    assert view[0] < cx and view[1] < cy and view[2] > 2.0  # from the front left, above
    browser.screenshot(ARTIFACTS / "controls_on_load.png")
    # as a user opens it: after the framed view, the camera follows robot and box
    _open(browser, html)
    browser.evaluate(VIEW_HELPERS)
    browser.wait_for("replayUI.state.view === 'follow'", timeout=10)
    _settle(browser)
    assert browser.evaluate("viewer.animator.playing") is True
    frac = browser.evaluate("__projectedFraction('meshcat/robot')")
    browser.screenshot(ARTIFACTS / "controls_follow_after_load.png")
    assert frac >= 0.05, f"robot covers {frac:.3f} of the viewport"
    # the chapter list is closed on load and opens with its button, every title whole
    hidden = "getComputedStyle(document.getElementById('%s')).display === 'none'"
    assert browser.evaluate(hidden % "pr-chapters") is True
    browser.evaluate("document.querySelector('[data-key=chapters]').click(); true")
    browser.evaluate("__frame()")
    assert browser.evaluate(hidden % "pr-chapters") is False
    assert browser.evaluate("Array.from(document.querySelectorAll('#pr-chapters div'))"
                            ".every(d => d.scrollWidth <= d.clientWidth + 1)")
    # the legend panel, shown on load: one line per kind of shape drawn
    assert browser.evaluate(hidden % "pr-legend") is False
    legend = browser.evaluate("Array.from(document.querySelectorAll('#pr-legend div'))"
                              ".map(d => d.textContent)")
    assert legend == [text for _, text in info.guide.extra["legend"]] and len(legend) >= 6
    browser.screenshot(ARTIFACTS / "controls_chapters_and_legend.png")

    # speed: 20x advances the animation time about 20 times as fast as 1x
    browser.evaluate("replayUI.seek(0); replayUI.setSpeed(1); true")
    r1 = browser.evaluate("__rate(1500)")
    browser.evaluate("replayUI.seek(0); document.querySelector('[data-key=speed20]').click(); true")
    assert browser.evaluate("viewer.animator.mixer.timeScale") == 20
    r20 = browser.evaluate("__rate(2000)")
    assert browser.evaluate("viewer.animator.playing") is True
    assert r1 == pytest.approx(1.0, rel=0.1)
    assert r20 / r1 == pytest.approx(20.0, rel=0.1)
    assert "20×" in browser.evaluate("document.getElementById('pr-label').textContent")

    # chapters: one entry per phase plus key moments; clicking one seeks and relabels
    browser.evaluate("viewer.animator.pause(); replayUI.setSpeed(1); replayUI.seek(3); true")
    browser.evaluate("__frame()")
    first = _label(browser)
    assert first.startswith("transfer 1/2 · pivot")
    titles = browser.evaluate("Array.from(document.querySelectorAll('#pr-chapters div'))"
                              ".map(d => d.textContent)")
    assert sum("transfer" in t for t in titles) == 2 and sum("regrasp" in t for t in titles) == 1
    t_regrasp = browser.evaluate("replayUI.chapters.find(c => c.kind === 'regrasp').time")
    browser.evaluate("Array.from(document.querySelectorAll('#pr-chapters div'))"
                     ".find(d => d.textContent.includes('regrasp')).click(); true")
    _settle(browser)
    assert browser.evaluate("replayUI.time()") == pytest.approx(t_regrasp, abs=0.05)
    assert _label(browser).startswith("regrasp 1/1 · walk")
    assert browser.evaluate("document.querySelector('#pr-chapters .pr-current').textContent"
                            ).find("regrasp") >= 0
    browser.screenshot(ARTIFACTS / "controls_regrasp_chapter.png")
    # following a regrasp walk frames the robot alone (the box rests behind it)
    assert browser.evaluate("replayUI.state.view") == "follow"
    assert browser.evaluate("replayUI.state.walking") is True
    assert browser.evaluate(TARGET_FROM_ROBOT) < 0.05
    browser.evaluate("Array.from(document.querySelectorAll('#pr-chapters div'))"
                     ".find(d => d.textContent.includes('transfer 2/2')).click(); true")
    browser.evaluate("__frame()")
    t2 = next(c.time for c in info.guide.chapters if c.title.startswith("transfer 2/2"))
    expected = info.guide.label_at(t2)  # the page shows what the Python guide computes
    assert expected.startswith("transfer 2/2 · pivot ") and "/" in expected
    assert _label(browser).startswith(expected)
    assert browser.evaluate("replayUI.state.walking") is False  # robot and box again
    assert browser.evaluate(TARGET_FROM_ROBOT) > 0.2
    # at the end: the goal's chapter highlighted and the label names the goal
    browser.evaluate("replayUI.seek(viewer.animator.duration); true")
    browser.evaluate("__frame()")
    assert _label(browser).startswith("goal reached · ")
    assert "goal reached" in browser.evaluate(
        "document.querySelector('#pr-chapters .pr-current').textContent")
    browser.screenshot(ARTIFACTS / "controls_goal.png")
    browser.evaluate("replayUI.setView('follow'); true")

    # an obstacle between the camera and the robot is drawn translucent, others stay opaque
    browser.evaluate("""(() => { const T = MeshCat.THREE;
      const inv = viewer.scene.matrixWorld.clone().invert();
      const rb = new T.Box3().setFromObject(__node('meshcat/robot').object).applyMatrix4(inv);
      const ob = new T.Box3().setFromObject(__node('meshcat/obstacles/0').object)
        .applyMatrix4(inv);
      const r = rb.getCenter(new T.Vector3()), o = ob.getCenter(new T.Vector3());
      const eye = o.clone().add(o.clone().sub(r).setLength(1.5)); eye.z = r.z + 0.3;
      replayUI.state.glide = null; replayUI.place(r, eye); return true; })()""")
    browser.evaluate("__frame()")
    op = browser.evaluate("(() => { const o = []; __node('meshcat/obstacles').object.traverse("
                          "m => { if (m.isMesh) o.push(m.material.opacity); }); return o; })()")
    assert op[0] < 0.5 and all(v == 1.0 for v in op[1:]), op

    # top view: the whole floor from above
    browser.evaluate("document.querySelector('[data-key=top]').click(); true")
    _settle(browser)
    eye = browser.evaluate("__eye()")
    cx, cy = 0.5 * (bounds[0] + bounds[2]), 0.5 * (bounds[1] + bounds[3])
    assert eye[2] > 5.0 and math.hypot(eye[0] - cx, eye[1] - cy) < 0.05 * eye[2]  # above
    assert _floor_corners_in_view(browser, bounds)
    browser.screenshot(ARTIFACTS / "controls_top.png")
    # overview again, at the start: the framed scene a person sees on load
    browser.evaluate("replayUI.setView('overview'); replayUI.seek(0); true")
    _settle(browser)
    assert _floor_corners_in_view(browser, bounds)
    browser.screenshot(ARTIFACTS / "controls_framed_start.png")


def test_live_replay_page_in_chromium(browser, tmp_path):
    """--serve: the replay page with its controls shows the live scene over the relay."""
    from pivot_ompl.planfile import load_plan
    from pivot_ompl.scene import load_scene
    from pivot_ompl.viz import show_plan
    from pivot_ompl.viz.serve import LiveViewer, ReplayPage

    s = write_samples(tmp_path)
    with LiveViewer() as live:
        info = show_plan(live.vis, load_scene(s.scene), load_plan(s.plan))
        assert info.guide is not None
        with ReplayPage(live, info.guide) as page:
            _viewport(browser)
            browser.call("Page.navigate", {"url": page.url})
            browser.wait_for("window.replayLoaded === true", timeout=60)
            browser.evaluate(HELPERS)
            browser.evaluate(VIEW_HELPERS)
            assert browser.evaluate("__node('meshcat/obstacles/2') !== null")
            n = browser.evaluate("document.querySelectorAll('#pr-chapters div').length")
            assert n == len(info.guide.chapters)
            browser.evaluate("viewer.animator.pause(); replayUI.seek("
                             f"{info.guide.chapters[-2].time + 0.5}); true")
            browser.evaluate("__frame()")
            assert _label(browser) == info.guide.label_at(info.guide.chapters[-2].time + 0.5)
    browser.call("Page.navigate", {"url": "about:blank"})


(function () {
  "use strict";
  const cfg = window.PIVOT_REPLAY || {};
  const V = window.viewer, T = MeshCat.THREE;
  const FOV = %(fov)s, DIR = new T.Vector3(%(dir)s).normalize();
  const state = { view: "overview", follow: true, speed: 1, glide: null, lastSubject: null,
                  chapter: -1, faded: new Set(), userMoved: false, walking: false };
  const marks = cfg.marks || [], chapters = cfg.chapters || [];
  const markTimes = marks.map(m => m[0]);

  function node(path) {
    let n = V.scene_tree;
    for (const p of path.split("/").filter(x => x)) {
      n = n.children[p]; if (!n) return null;
    }
    return n;
  }
  function animTime() {
    const a = V.animator;
    if (!a.actions.length) return 0;
    return a.actions.reduce((acc, x) => Math.max(acc, x.time), 0);
  }
  function fmt(t) {
    t = Math.max(0, t);
    const m = Math.floor(t / 60), s = t - 60 * m;
    return m + ":" + (s < 10 ? "0" : "") + s.toFixed(1);
  }
  // Times are compared within 1 ms: the guide's are rounded to 0.1 ms, the animation's are
  // single precision (at the end of a long replay they fall short of the last mark).
  const EPS = 1e-3;
  function lastBefore(arr, t) {  // index of the last element <= t (binary search)
    let lo = 0, hi = arr.length - 1, best = -1;
    while (lo <= hi) {
      const mid = (lo + hi) >> 1;
      if (arr[mid] <= t + EPS) { best = mid; lo = mid + 1; } else hi = mid - 1;
    }
    return best;
  }
  function label(t) {
    const i = lastBefore(markTimes, t);
    return i >= 0 ? marks[i][1] : (marks.length ? marks[0][1] : "");
  }

  // ---- camera ------------------------------------------------------------------------
  // meshcat turns its z-up scene into three.js's y-up world (a rotation of the scene root):
  // every position here is in the scene's frame (z up), converted at the three.js boundary.
  function sceneMatrix() { V.scene.updateMatrixWorld(true); return V.scene.matrixWorld; }
  function toWorld(v) { return v.clone().applyMatrix4(sceneMatrix()); }
  function toScene(v) { return v.clone().applyMatrix4(sceneMatrix().clone().invert()); }
  function sceneBoxOf(obj) {  // axis-aligned box of an object, in the scene's frame
    const b = new T.Box3().setFromObject(obj);
    return b.isEmpty() ? b : b.applyMatrix4(sceneMatrix().clone().invert());
  }
  function currentPose() {  // target and eye in the scene's frame
    V.scene.updateMatrixWorld(true);
    const m = V.camera.parent.matrixWorld;
    return { target: toScene(V.controls.target.clone().applyMatrix4(m)),
             eye: toScene(V.camera.position.clone().applyMatrix4(m)) };
  }
  function place(target, eye) {  // scene-frame points (z up)
    const p = V.camera.parent;
    V.scene.updateMatrixWorld(true);  // also the camera's ancestors (stale until a render)
    const inv = p.matrixWorld.clone().invert();
    V.camera.position.copy(toWorld(eye).applyMatrix4(inv));
    V.controls.target.copy(toWorld(target).applyMatrix4(inv));
    V.controls.update();
    V.set_dirty();
  }
  function glideTo(target, eye, seconds) {
    const from = currentPose();
    state.glide = { from: from, target: target, eye: eye, t0: performance.now(),
                    dur: 1000 * (seconds === undefined ? 0.8 : seconds) };
  }
  function fitPose(box, dir, margin) {
    // Closest eye along dir (from the target) whose view holds the 8 corners of box within
    // margin of the pane's edges: exact for a pinhole camera, closed form per corner.
    const c = box.getCenter(new T.Vector3()), d = dir.clone().normalize();
    const f = d.clone().negate(), r = new T.Vector3().crossVectors(f, new T.Vector3(0, 0, 1));
    if (r.lengthSq() < 1e-9) r.set(1, 0, 0);
    r.normalize();
    const u = new T.Vector3().crossVectors(r, f);
    const tv = Math.tan(FOV * Math.PI / 360), aspect = V.camera.aspect || 1.6;
    let D = 0.5;
    for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y])
      for (const z of [box.min.z, box.max.z]) {
        const q = new T.Vector3(x, y, z).sub(c), z0 = q.dot(f);
        D = Math.max(D, Math.abs(q.dot(r)) / (margin * tv * aspect) - z0,
                     Math.abs(q.dot(u)) / (margin * tv) - z0, 0.3 - z0);
      }
    return { target: c, eye: c.clone().addScaledVector(d, D) };
  }
  function sceneBox() {
    const b = cfg.bounds, h = cfg.height || 1.5;
    if (b) return new T.Box3(new T.Vector3(b[0], b[1], 0), new T.Vector3(b[2], b[3], h));
    const box = new T.Box3();
    for (const k of ["floor", "obstacles", "robot", "box"]) {
      const n = node("meshcat/" + k); if (n) box.union(sceneBoxOf(n.object));
    }
    return box;
  }
  function overviewPose() { return fitPose(sceneBox(), DIR, 0.95); }
  function topPose() {
    const box = sceneBox(), c = box.getCenter(new T.Vector3()), s = box.getSize(new T.Vector3());
    const vf = FOV * Math.PI / 180, aspect = V.camera.aspect || 1.6;
    const d = 0.55 * Math.max(s.y, s.x / aspect) / Math.tan(vf / 2) + s.z;
    c.z = 0;
    return { target: c, eye: new T.Vector3(c.x, c.y - 1e-3 * d, d) };
  }
  function walkingAt(t) {  // in a regrasp walk the robot alone is the subject
    let kind = "";
    for (const c of chapters) if (c.kind !== "moment" && c.time <= t + EPS) kind = c.kind;
    return kind === "regrasp";
  }
  function subjectBox() {
    const box = new T.Box3();
    for (const k of (state.walking ? ["robot"] : ["robot", "box"])) {
      const n = node("meshcat/" + k);
      if (n) box.union(sceneBoxOf(n.object));
    }
    return box.isEmpty() ? null : box;
  }
  function followPose(box) {
    const b = box.clone(), c = b.getCenter(new T.Vector3());
    b.expandByPoint(c.clone().add(new T.Vector3(0.6, 0.6, 0.4)));  // a little context
    b.expandByPoint(c.clone().sub(new T.Vector3(0.6, 0.6, 0.4)));
    const cur = currentPose(), dir = cur.eye.clone().sub(cur.target);
    if (state.view !== "follow" || dir.lengthSq() < 1e-9 || dir.z < 0.05 * dir.length())
      dir.copy(DIR);
    return fitPose(b, dir, 0.9);
  }

  // ---- obstacles hiding the robot ----------------------------------------------------
  const obstacleMeshes = [];
  function collectObstacles() {
    obstacleMeshes.length = 0;
    const n = node("meshcat/obstacles"); if (!n) return;
    n.object.traverse(o => {
      if (o.isMesh && o.material) {
        o.material = o.material.clone();   // own material: fading one leaves others opaque
        obstacleMeshes.push({ mesh: o, opacity: o.material.opacity,
                              transparent: o.material.transparent });
      }
    });
  }
  function fadeOccluders() {
    const box = subjectBox(); if (!box || !obstacleMeshes.length) return;
    const eye = currentPose().eye, c = box.getCenter(new T.Vector3());
    const pts = [c, new T.Vector3(c.x, c.y, box.max.z), new T.Vector3(c.x, c.y, box.min.z + 0.1)];
    const ray = new T.Ray(), hit = new T.Vector3();
    for (const e of obstacleMeshes) {
      const ob = sceneBoxOf(e.mesh);
      let hides = false;
      if (state.view !== "top") {
        for (const p of pts) {
          ray.origin.copy(eye); ray.direction.copy(p).sub(eye);
          const dist = ray.direction.length(); ray.direction.normalize();
          if (ray.intersectBox(ob, hit) && hit.distanceTo(eye) < dist - 0.05) hides = true;
        }
      }
      const want = hides ? 0.22 : e.opacity;
      if (e.mesh.material.opacity !== want) {
        e.mesh.material.opacity = want;
        e.mesh.material.transparent = hides || e.transparent;
        e.mesh.material.depthWrite = !hides;
        e.mesh.material.needsUpdate = true;
        if (hides) state.faded.add(e.mesh.uuid); else state.faded.delete(e.mesh.uuid);
        V.set_dirty();
      }
    }
  }

  // ---- page elements -----------------------------------------------------------------
  const pane = document.getElementById("meshcat-pane") || document.body;
  const lab = document.createElement("div"); lab.id = "pr-label"; pane.appendChild(lab);
  const list = document.createElement("div"); list.id = "pr-chapters";
  list.className = "pr-hidden"; pane.appendChild(list);  // closed until asked for (c)
  const legend = document.createElement("div"); legend.id = "pr-legend"; pane.appendChild(legend);
  for (const [colour, text] of cfg.legend || []) {
    const d = document.createElement("div"), sw = document.createElement("i");
    sw.style.background = colour; d.appendChild(sw); d.appendChild(document.createTextNode(text));
    legend.appendChild(d);
  }
  if (!(cfg.legend || []).length) legend.classList.add("pr-hidden");
  const bar = document.createElement("div"); bar.id = "pr-bar"; pane.appendChild(bar);
  const buttons = {};
  function button(key, text, title, fn) {
    const b = document.createElement("button");
    b.textContent = text; b.title = title; b.dataset.key = key;
    b.addEventListener("click", fn); bar.appendChild(b); buttons[key] = b; return b;
  }
  function sep() { const s = document.createElement("span"); s.className = "pr-sep";
                   bar.appendChild(s); }
  button("play", "▶ / ❚❚", "play or pause (space)", () => togglePlay());
  sep();
  for (const s of cfg.speeds || [1, 5, 20, 50])
    button("speed" + s, s + "×", "play " + s + " times as fast", () => setSpeed(s));
  sep();
  button("follow", "follow", "keep robot and box in view while playing (f)",
         () => setView(state.view === "follow" ? "overview" : "follow"));
  button("overview", "overview", "the whole scene from a three-quarter view (o)",
         () => setView("overview"));
  button("top", "top", "the whole floor from above (t)",
         () => setView(state.view === "top" ? (state.follow ? "follow" : "overview") : "top"));
  button("chapters", "chapters", "show or hide the chapter list (c)",
         () => list.classList.toggle("pr-hidden"));
  button("legend", "legend", "show or hide what the shapes and colours are (l)",
         () => legend.classList.toggle("pr-hidden"));
  chapters.forEach((c, i) => {
    const d = document.createElement("div");
    d.className = "pr-" + c.kind; d.dataset.index = i;
    d.innerHTML = "<span>" + fmt(c.time) + "</span>";
    d.appendChild(document.createTextNode(c.title));
    d.title = c.title;
    d.addEventListener("click", () => seek(c.time));
    list.appendChild(d);
  });

  function refreshButtons() {
    for (const s of cfg.speeds || [1, 5, 20, 50])
      buttons["speed" + s].classList.toggle("pr-on", s === state.speed);
    for (const k of ["follow", "overview", "top"])
      buttons[k].classList.toggle("pr-on", state.view === k);
  }

  // ---- actions -----------------------------------------------------------------------
  function setSpeed(s) {
    state.speed = s;
    V.animator.mixer.timeScale = s;
    refreshButtons();
  }
  function setView(name) {
    state.view = name;
    if (name === "follow") {
      state.follow = true;
      const b = subjectBox(); if (b) { const p = followPose(b); glideTo(p.target, p.eye); }
    } else if (name === "overview") {
      state.follow = false;
      const p = overviewPose(); glideTo(p.target, p.eye);
    } else if (name === "top") {
      const p = topPose(); glideTo(p.target, p.eye);
    }
    state.lastSubject = null;
    refreshButtons();
  }
  function seek(t) {
    const a = V.animator;
    t = Math.max(0, Math.min(t, a.duration || t));
    if (!a.playing) for (const x of a.actions) { x.paused = false; x.enabled = true; }
    a.seek(t);
    a.display_progress(t);
    if (state.view === "follow") {
      const b = subjectBox(); if (b) { const p = followPose(b); glideTo(p.target, p.eye, 0.5); }
      state.lastSubject = null;
    }
    update(true);
  }
  function togglePlay() {
    const a = V.animator;
    if (a.playing) a.pause(); else {
      if (animTime() >= a.duration - 1e-3) seek(0);
      a.play();
    }
  }
  document.addEventListener("keydown", e => {
    if (e.target && /input|textarea/i.test(e.target.tagName)) return;
    const k = e.key;
    if (k === " ") { togglePlay(); e.preventDefault(); }
    else if (k === "f") buttons.follow.click();
    else if (k === "o") setView("overview");
    else if (k === "t") buttons.top.click();
    else if (k === "c") buttons.chapters.click();
    else if (k === "l") buttons.legend.click();
  });

  // ---- per frame ---------------------------------------------------------------------
  let lastLabel = "";
  function update(force) {
    const a = V.animator, t = animTime();
    if (a.mixer.timeScale !== state.speed) a.mixer.timeScale = state.speed;
    const text = label(t);
    const html = (text || "replay") + "<small>t = " + fmt(t) + " / " + fmt(a.duration ||
      cfg.duration || 0) + " · " + state.speed + "×" + (a.playing ? "" : " · paused") +
      "</small>";
    if (html !== lastLabel) { lab.innerHTML = html; lastLabel = html; }
    lab.dataset.label = text;
    let cur = -1;
    for (let i = 0; i < chapters.length; i++) if (chapters[i].time <= t + EPS) cur = i;
    if (cur !== state.chapter) {
      const old = list.querySelector(".pr-current"); if (old) old.classList.remove("pr-current");
      const el = list.children[cur];
      if (el) { el.classList.add("pr-current"); el.scrollIntoView({ block: "nearest" }); }
      state.chapter = cur;
    }
    const walking = walkingAt(t);
    if (walking !== state.walking) {  // the subject changes: frame the new one
      state.walking = walking;
      if (state.view === "follow") {
        const b = subjectBox(); if (b) { const p = followPose(b); glideTo(p.target, p.eye, 0.6); }
      }
      state.lastSubject = null;
    }
    if (state.glide) {
      const g = state.glide, s = Math.min(1, (performance.now() - g.t0) / g.dur);
      const e = s * s * (3 - 2 * s);
      place(g.from.target.clone().lerp(g.target, e), g.from.eye.clone().lerp(g.eye, e));
      if (s >= 1) state.glide = null;
    } else if (state.view === "follow" && (a.playing || force)) {
      const b = subjectBox();
      if (b) {
        const c = b.getCenter(new T.Vector3());
        if (state.lastSubject) {  // carry the camera with the subject, keeping the user's orbit
          const d = c.clone().sub(state.lastSubject);
          if (d.lengthSq() > 1e-10) {
            const p = currentPose();
            place(p.target.add(d), p.eye.add(d));
          }
        }
        state.lastSubject = c;
      }
    }
    fadeOccluders();
  }
  function loop() { requestAnimationFrame(loop); update(false); }

  function start() {
    // Orbit controls aim with lookAt (world coordinates): keep the camera's frame untranslated.
    V.set_transform(["Cameras", "default"], new T.Matrix4().toArray());
    collectObstacles();
    const p = overviewPose(); place(p.target, p.eye);
    setSpeed(state.speed);
    refreshButtons();
    // The view on load frames the scene; then, while playing, the camera follows the robot.
    // "#overview=<s>" in the address holds the framed view that long (default 1.5 s).
    const held = /overview=([0-9.]+)/.exec(location.hash);
    const secs = held ? Number(held[1])
      : (cfg.overviewSeconds === undefined ? 1.5 : cfg.overviewSeconds);
    window.setTimeout(() => {
      if (state.view === "overview" && state.follow) setView("follow");
    }, 1000 * secs);
    loop();
  }
  window.replayUI = { seek: seek, setSpeed: setSpeed, setView: setView, togglePlay: togglePlay,
                      label: () => label(animTime()), time: animTime, state: state,
                      chapters: chapters, start: start, overviewPose: overviewPose,
                      topPose: topPose, place: place };
})();

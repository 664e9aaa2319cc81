"""The replay page's own controls: camera views, follow mode, speed, chapters, phase label.

A small script block (no dependency beyond meshcat's viewer bundle, which exports
``MeshCat.THREE``) added to the offline HTML and to the live page of ``--serve``. It reads
``window.PIVOT_REPLAY`` (:meth:`~pivot_ompl.viz.chapters.ReplayGuide.to_json`) and offers

* **views**: *overview* (the scene's bounds framed from a three-quarter view, the view on
  load), *follow* (keeps robot and box framed while the animation plays; default on), *top*
  (the whole floor from above). Obstacles between the camera and the robot or the box are
  drawn translucent;
* **playback**: play/pause, speeds 1×, 5×, 20×, 50× (the animation mixer's time scale), the
  time, and the on-screen label of the current phase and pivot;
* **chapters**: a list of the phases and key moments (closed on load, ``c`` opens it; the
  current one highlighted, the goal's at the end); clicking one seeks there;
* **legend**: what each shape and colour is (``cfg.legend``: ``[colour, text]`` pairs), at
  the bottom right (``l`` hides it).

In *follow* the subject is robot and box, and the robot alone during a regrasp walk.

``window.replayUI`` exposes ``seek(t)``, ``setSpeed(s)``, ``setView(name)``, ``label()``,
``time()`` and ``state`` for tests and for the curious (browser console).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

#: Playback speeds offered (animation seconds per wall-clock second).
SPEEDS = (1, 5, 20, 50)
#: Vertical field of view of meshcat's default camera (deg).
CAMERA_FOV = 75.0
#: Three-quarter viewing direction (from the target towards the eye, world frame, z up).
THREE_QUARTER = (-0.55, -0.75, 0.62)

#: The overlay's style sheet and script (``%(fov)s`` and ``%(dir)s`` filled in), shipped beside
#: this module.
CSS = (Path(__file__).parent / "overlay.css").read_text(encoding="utf-8")
JS = (Path(__file__).parent / "overlay.js").read_text(encoding="utf-8")


def overlay_script(config: dict[str, Any]) -> str:
    """The ``<style>`` and ``<script>`` blocks for a page whose viewer is ``window.viewer``.

    ``config`` (JSON-serialisable, :meth:`ReplayGuide.to_json`) becomes
    ``window.PIVOT_REPLAY``; call ``replayUI.start()`` once the scene is loaded.
    """
    cfg = dict(config)
    cfg.setdefault("speeds", list(SPEEDS))
    data = json.dumps(cfg, separators=(",", ":")).replace("</", "<\\/")
    js = JS % {"fov": repr(CAMERA_FOV), "dir": ", ".join(repr(x) for x in THREE_QUARTER)}
    return (f"<style>{CSS}</style>\n<script>window.PIVOT_REPLAY = {data};</script>\n"
            f"<script>{js}</script>")

"""One self-contained offline HTML file from a recorded scene (no server, no network).

The file inlines meshcat's viewer bundle (three.js, from the meshcat wheel) and the recorded
commands as base64 strings; large ones (the animation of a long motion) are gzip-compressed
and inflated by the browser's ``DecompressionStream``. Every command is decoded first, then
all are applied in order: the scene is complete when the animation is loaded, and the
animation then starts playing. With a :class:`~pivot_ompl.viz.chapters.ReplayGuide` the page
also carries the replay controls of :mod:`pivot_ompl.viz.overlay` (camera views, follow
mode, speeds, chapters, phase label), started once the scene is loaded. ``window.viewer``
is the ``MeshCat.Viewer``; ``window.replayLoaded`` becomes ``true`` once every command has
been applied (``window.replayError`` holds a message if one failed).
"""

from __future__ import annotations

import base64
import gzip
import json
import logging
import time
from dataclasses import dataclass
from pathlib import Path

import meshcat

from pivot_ompl.errors import InputError
from pivot_ompl.fileio import atomic_output, input_path
from pivot_ompl.viz.chapters import ReplayGuide
from pivot_ompl.viz.overlay import overlay_script
from pivot_ompl.viz.recorder import RecordingWindow

log = logging.getLogger(__name__)

VIEWER_JS = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
#: Commands larger than this (bytes) are stored gzip-compressed.
GZIP_ABOVE = 8_000

_PAGE = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title>
<style>body {{ margin: 0; }} #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
</style></head>
<body>
<div id="meshcat-pane"></div>
<script>
{viewer_js}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
window.viewer = viewer;
window.replayLoaded = false;
{connect}</script>
{overlay}
<script>
{loader}</script>
</body>
</html>
"""

#: The offline page's loader: the recorded commands (gzip-compressed above GZIP_ABOVE bytes).
_OFFLINE_LOADER = """(async function () {{
  var cmds = {commands};
  function bytesOf(b64) {{
    var s = atob(b64), bytes = new Uint8Array(s.length);
    for (var j = 0; j < s.length; j++) bytes[j] = s.charCodeAt(j);
    return bytes;
  }}
  async function inflate(b64) {{
    if (typeof DecompressionStream === "undefined")
      throw new Error("this browser lacks DecompressionStream (needed for the animation)");
    var stream = new Blob([bytesOf(b64)]).stream()
      .pipeThrough(new DecompressionStream("gzip"));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }}
  try {{
    var decoded = [];
    for (var i = 0; i < cmds.length; i++)
      decoded.push(typeof cmds[i] === "string" ? bytesOf(cmds[i]) : await inflate(cmds[i].gz));
    for (var i = 0; i < decoded.length; i++) viewer.handle_command_bytearray(decoded[i]);
    if (window.replayUI) window.replayUI.start();
    window.replayLoaded = true;
  }} catch (e) {{
    window.replayError = String(e);
    console.error(e);
    document.body.insertAdjacentHTML("afterbegin",
      "<pre style='position:absolute;color:red;z-index:9'>replay failed: " + e + "</pre>");
  }}
}})();
"""


def replay_page(*, title: str, overlay: str, loader: str, connect: str = "") -> str:
    """A replay page: meshcat's viewer, the replay controls' ``overlay`` and a ``loader`` script.

    The offline export (:func:`html_text`) and the live page (:mod:`pivot_ompl.viz.serve`,
    ``connect`` opens its websocket) differ only by these.
    """
    safe_title = title.replace("&", "&amp;").replace("<", "&lt;")
    return _PAGE.format(title=safe_title, viewer_js=viewer_js(), overlay=overlay,
                        loader=loader, connect=connect)


@dataclass(frozen=True)
class HtmlExport:
    """Result of :func:`write_html`.

    Attributes:
        path: the file written.
        size_bytes: its size.
        seconds: wall time spent building the page and writing it.
        commands: number of scene commands embedded.
    """

    path: Path
    size_bytes: int
    seconds: float
    commands: int


def viewer_js() -> str:
    """Meshcat's viewer bundle, safe to inline in a ``<script>`` block."""
    js = VIEWER_JS.read_text(encoding="utf-8")
    if "</script" in js.lower():  # never true for meshcat 0.3.2; guard the inlining anyway
        js = js.replace("</script", "<\\/script").replace("</SCRIPT", "<\\/SCRIPT")
    return js


def html_text(window: RecordingWindow, *, title: str = "pivot-ompl replay",
              guide: ReplayGuide | None = None) -> str:
    """The self-contained page for the scene recorded in ``window``.

    With ``guide``, the page carries the replay controls (:mod:`pivot_ompl.viz.overlay`).
    """
    cmds: list[str | dict[str, str]] = []
    for c in window.commands():
        if len(c) > GZIP_ABOVE:
            cmds.append({"gz": base64.b64encode(gzip.compress(c, compresslevel=1,
                                                             mtime=0)).decode("ascii")})
        else:
            cmds.append(base64.b64encode(c).decode("ascii"))
    overlay = overlay_script(guide.to_json()) if guide is not None else ""
    loader = _OFFLINE_LOADER.format(commands=json.dumps(cmds, separators=(",\n", ":")))
    return replay_page(title=title, overlay=overlay, loader=loader)


def write_html(vis: meshcat.Visualizer, path: str | Path, *,
               title: str = "pivot-ompl replay", guide: ReplayGuide | None = None) -> HtmlExport:
    """Write the scene recorded by ``vis`` (a recording visualizer) to one HTML file.

    ``guide`` (the ``guide`` of the :class:`~pivot_ompl.viz.plan_view.ReplayInfo` a
    ``show_*`` call returns) adds the replay controls. The file is written to a temporary
    name first, so a failed export never destroys an existing file.

    Raises:
        InputError: ``vis`` is not backed by a :class:`RecordingWindow`.
    """
    t0 = time.perf_counter()
    window = getattr(vis, "window", None)
    if not isinstance(window, RecordingWindow):
        raise InputError("vis", type(window).__name__,
                         "offline export needs a recording visualizer "
                         "(pivot_ompl.viz.recording_visualizer())")
    path = input_path(path, field="path")
    n = len(window.commands())
    with atomic_output(path) as tmp:
        tmp.write_text(html_text(window, title=title, guide=guide), encoding="utf-8")
    out = HtmlExport(path, path.stat().st_size, time.perf_counter() - t0, n)
    log.info("wrote %s (%.1f MB, %d commands) in %.2f s", path, out.size_bytes / 1e6, n,
             out.seconds)
    return out

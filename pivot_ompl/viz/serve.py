"""Live meshcat viewer: a server process for as long as needed, then stopped cleanly.

``meshcat.Visualizer()`` starts meshcat's zmq/web server as a child process; its ports are
counted up from 6000 (zmq) and 7000 (web) until free ones bind, so a second viewer never
clashes with the first. :class:`LiveViewer` owns that process and always terminates it
(context exit, Ctrl-C, SIGTERM), leaving no stray server behind.

With a replay guide, :class:`ReplayPage` also serves the replay page with its controls
(:mod:`pivot_ompl.viz.overlay`: camera views, follow mode, speeds, chapters, phase label) on
its own local port; the page's websocket is relayed to meshcat's server, so it shows the
live scene (meshcat's server accepts websockets from its own origin only).
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import logging
import signal
import threading
import time
import webbrowser
from collections.abc import Callable
from types import FrameType
from typing import Any

import meshcat
import tornado.httpserver
import tornado.netutil
import tornado.web
import tornado.websocket

from pivot_ompl.viz.chapters import ReplayGuide

log = logging.getLogger(__name__)


class LiveViewer:
    """A meshcat server process and a visualizer connected to it.

    Attributes:
        vis: the ``meshcat.Visualizer``.
        url: the viewer's web address (``http://127.0.0.1:<port>/static/``).
        pid: the server process id.
    """

    def __init__(self) -> None:
        with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL itself
            self.vis = meshcat.Visualizer()
        self.url: str = self.vis.url()
        self.pid: int = self.vis.window.server_proc.pid
        log.info("meshcat server pid %d at %s", self.pid, self.url)

    def close(self, *, timeout: float = 5.0) -> None:
        """Stop the server process and close the zmq socket (idempotent)."""
        proc = self.vis.window.server_proc
        if proc is not None and proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=timeout)
            except Exception:  # noqa: BLE001 - subprocess.TimeoutExpired: force it
                proc.kill()
                proc.wait()
            log.info("meshcat server pid %d stopped", proc.pid)
        sock = getattr(self.vis.window, "zmq_socket", None)
        if sock is not None and not sock.closed:
            sock.close(linger=0)

    def __enter__(self) -> LiveViewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


#: The live page's loader: the scene arrives over the websocket, the animation last.
_LIVE_LOADER = """(function wait() {
  if (viewer.animator.actions.length > 0 && viewer.scene_tree.children.meshcat) {
    if (window.replayUI) window.replayUI.start();
    window.replayLoaded = true;
  } else setTimeout(wait, 100);
})();
"""


class _PageHandler(tornado.web.RequestHandler):
    def initialize(self, page: str) -> None:
        self.page = page

    def get(self) -> None:
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.set_header("Cache-Control", "no-store")
        self.write(self.page)


class _RelayHandler(tornado.websocket.WebSocketHandler):
    """Relays one browser websocket to meshcat's server, both ways."""

    def initialize(self, upstream: str) -> None:
        self.upstream_url = upstream
        self.upstream: Any = None

    async def open(self) -> None:
        self.upstream = await tornado.websocket.websocket_connect(self.upstream_url,
                                                                  max_message_size=1 << 30)
        asyncio.get_running_loop().create_task(self._pump())

    async def _pump(self) -> None:
        while True:
            msg = await self.upstream.read_message()
            if msg is None:
                self.close()
                return
            try:
                await self.write_message(msg, binary=isinstance(msg, bytes))
            except tornado.websocket.WebSocketClosedError:
                return

    def on_message(self, message: str | bytes) -> None:
        if self.upstream is not None:
            self.upstream.write_message(message, binary=isinstance(message, bytes))

    def on_close(self) -> None:
        if self.upstream is not None:
            self.upstream.close()


class ReplayPage:
    """The replay page with its controls, served on a free local port for a live viewer.

    Attributes:
        url: the page's address (``http://127.0.0.1:<port>/``).
    """

    def __init__(self, viewer: LiveViewer, guide: ReplayGuide, *,
                 title: str = "pivot-ompl replay") -> None:
        from pivot_ompl.viz.html import replay_page
        from pivot_ompl.viz.overlay import overlay_script

        web = viewer.url.split("//", 1)[1].split("/", 1)[0]  # host:port of meshcat's server
        page = replay_page(title=title, overlay=overlay_script(guide.to_json()),
                           loader=_LIVE_LOADER,
                           connect='viewer.connect("ws://" + location.host + "/ws");\n')
        self._loop = asyncio.new_event_loop()
        socks = tornado.netutil.bind_sockets(0, "127.0.0.1")
        self.url = f"http://127.0.0.1:{socks[0].getsockname()[1]}/"
        ready = threading.Event()

        def run() -> None:
            asyncio.set_event_loop(self._loop)
            app = tornado.web.Application([
                (r"/", _PageHandler, {"page": page}),
                (r"/ws", _RelayHandler, {"upstream": f"ws://{web}/"})])
            self._server = tornado.httpserver.HTTPServer(app, max_buffer_size=1 << 30)
            self._server.add_sockets(socks)
            ready.set()
            self._loop.run_forever()
            self._server.stop()
            self._loop.run_until_complete(self._loop.shutdown_asyncgens())
            self._loop.close()

        self._thread = threading.Thread(target=run, name="replay-page", daemon=True)
        self._thread.start()
        ready.wait(10)
        log.info("replay page at %s (relaying %s)", self.url, web)

    def close(self) -> None:
        """Stop serving the page (idempotent)."""
        if self._thread.is_alive():
            self._loop.call_soon_threadsafe(self._loop.stop)
            self._thread.join(10)

    def __enter__(self) -> ReplayPage:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class _Stop(Exception):
    """Raised by the SIGTERM handler to leave the serving loop."""


def serve(build: Callable[[meshcat.Visualizer], object], *, open_browser: bool = False,
          on_ready: Callable[[str], None] | None = None,
          stop: threading.Event | None = None, title: str = "pivot-ompl replay") -> int:
    """Start a live viewer, draw with ``build(vis)``, then wait until Ctrl-C / SIGTERM.

    When ``build`` returns a ``ReplayInfo`` with a ``guide``, the replay page with its
    controls (:class:`ReplayPage`) is served too and its URL is the one given to
    ``on_ready`` and opened; meshcat's own page stays available at the server's URL.

    Args:
        build: draws the scene into the visualizer it is given.
        open_browser: open the URL in the default browser.
        on_ready: called with the URL once the scene is sent (the CLI prints it).
        stop: optional event that ends the wait (for tests and embedding).
        title: the replay page's title.

    Returns:
        0 once the server has been stopped.
    """
    old = None
    if threading.current_thread() is threading.main_thread():
        def on_term(signum: int, frame: FrameType | None) -> None:
            raise _Stop()

        old = signal.signal(signal.SIGTERM, on_term)
    viewer = LiveViewer()
    page: ReplayPage | None = None
    try:
        info = build(viewer.vis)
        url = viewer.url
        guide = getattr(info, "guide", None)
        if isinstance(guide, ReplayGuide):
            page = ReplayPage(viewer, guide, title=title)
            url = page.url
        if on_ready is not None:
            on_ready(url)
        if open_browser:
            webbrowser.open(url, new=2)
        while stop is None or not stop.is_set():
            time.sleep(0.2)
            if viewer.vis.window.server_proc.poll() is not None:
                log.error("the meshcat server exited unexpectedly")
                return 1
    except (KeyboardInterrupt, _Stop):
        log.info("stopping the viewer")
    finally:
        if page is not None:
            page.close()
        viewer.close()
        if old is not None:
            signal.signal(signal.SIGTERM, old)
    return 0

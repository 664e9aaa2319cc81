"""Live meshcat viewer: a server process for as long as needed, then stopped cleanly.

``meshcat.Visualizer()`` starts meshcat's zmq/web server as a child process; its ports are
counted up from 6000 (zmq) and 7000 (web) until free ones bind, so a second viewer never
clashes with the first. :class:`LiveViewer` owns that process and always terminates it
(context exit, Ctrl-C, SIGTERM), leaving no stray server behind.
"""

from __future__ import annotations

import contextlib
import io
import logging
import signal
import threading
import time
import webbrowser
from collections.abc import Callable
from types import FrameType

import meshcat

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


class _Stop(Exception):
    """Raised by the SIGTERM handler to leave the serving loop."""


def serve(build: Callable[[meshcat.Visualizer], object], *, open_browser: bool = False,
          on_ready: Callable[[str], None] | None = None,
          stop: threading.Event | None = None) -> int:
    """Start a live viewer, draw with ``build(vis)``, then wait until Ctrl-C / SIGTERM.

    Args:
        build: draws the scene into the visualizer it is given.
        open_browser: open the URL in the default browser.
        on_ready: called with the URL once the scene is sent (the CLI prints it).
        stop: optional event that ends the wait (for tests and embedding).

    Returns:
        0 once the server has been stopped.
    """
    old = None
    if threading.current_thread() is threading.main_thread():
        def on_term(signum: int, frame: FrameType | None) -> None:
            raise _Stop()

        old = signal.signal(signal.SIGTERM, on_term)
    viewer = LiveViewer()
    try:
        build(viewer.vis)
        if on_ready is not None:
            on_ready(viewer.url)
        if open_browser:
            webbrowser.open(viewer.url, new=2)
        while stop is None or not stop.is_set():
            time.sleep(0.2)
            if viewer.vis.window.server_proc.poll() is not None:
                log.error("the meshcat server exited unexpectedly")
                return 1
    except (KeyboardInterrupt, _Stop):
        log.info("stopping the viewer")
    finally:
        viewer.close()
        if old is not None:
            signal.signal(signal.SIGTERM, old)
    return 0

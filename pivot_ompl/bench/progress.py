"""A text progress bar with an ETA, on stderr."""

from __future__ import annotations

import sys
import time
from typing import TextIO

from pivot_ompl.errors import printable


def _hms(seconds: float) -> str:
    s = int(round(max(0.0, seconds)))
    return f"{s // 3600:d}:{s // 60 % 60:02d}:{s % 60:02d}"


class Progress:
    """``bench [#####.....] 12/150  8% 0:01:10 elapsed, ETA 0:07:30  regrasp open #3``.

    The ETA is the elapsed time per finished job times the jobs left (so it accounts for the
    jobs running in parallel). On a terminal the line is redrawn in place; otherwise a line is
    written at most every ``period`` seconds and at the end.

    Args:
        total: number of jobs.
        stream: where to write (default: ``sys.stderr``).
        width: bar width in characters.
        period: seconds between lines when ``stream`` is not a terminal.
    """

    def __init__(self, total: int, *, stream: TextIO | None = None, width: int = 30,
                 period: float = 10.0, label: str = "bench") -> None:
        """Start the clock."""
        self.total = max(total, 1)
        self.stream = stream or sys.stderr
        self.width = width
        self.period = period
        self.label = label
        self.done = 0
        self.t0 = time.monotonic()
        self._last = -1e9
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def line(self, note: str = "") -> str:
        """Return the current progress line."""
        frac = self.done / self.total
        fill = int(round(frac * self.width))
        elapsed = time.monotonic() - self.t0
        eta = elapsed / self.done * (self.total - self.done) if self.done else float("nan")
        eta_s = _hms(eta) if self.done else "?:??:??"
        return (f"{self.label} [{'#' * fill}{'.' * (self.width - fill)}] {self.done}/{self.total}"
                f" {100 * frac:3.0f}% {_hms(elapsed)} elapsed, ETA {eta_s}  {note}").rstrip()

    def update(self, n: int = 1, note: str = "") -> None:
        """Count ``n`` finished jobs and redraw."""
        self.done += n
        now = time.monotonic()
        note = printable(note)  # a scene's name: no control character reaches the terminal
        if self.tty:  # its own control sequence, past an escaping wrapper (cli.terminal)
            getattr(self.stream, "unescaped", self.stream).write("\r\033[K" + self.line(note))
            self.stream.flush()
        elif now - self._last >= self.period or self.done >= self.total:
            self.stream.write(self.line(note) + "\n")
            self.stream.flush()
            self._last = now

    def close(self) -> None:
        """End the line."""
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()

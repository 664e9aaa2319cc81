"""What the command line writes to a terminal or a log: never a raw control character.

Names, keys and paths come from users' files; an ESC or BEL in one must not reach the
terminal, a newline must not forge a log line. While a verb runs, ``sys.stdout`` and
``sys.stderr`` are :class:`EscapingStream` wrappers (every control character but newline and
tab shown as its escape, :func:`~pivot_ompl.errors.printable`), and every log record's
message is escaped whole, newlines included (:class:`EscapingFormatter`).
"""

from __future__ import annotations

import io
import logging
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

from pivot_ompl.errors import printable


class EscapingStream(io.TextIOBase):
    """A text stream that writes to ``stream`` with control characters escaped.

    Newlines and tabs pass. ``unescaped`` is the wrapped stream, for the program's own
    control sequences (a progress bar's carriage return), never for a user's text.
    """

    def __init__(self, stream: TextIO) -> None:
        """Wrap ``stream``."""
        super().__init__()
        self.unescaped = stream

    def write(self, text: str) -> int:  # noqa: D102
        self.unescaped.write(printable(text, keep="\n\t"))
        return len(text)

    def flush(self) -> None:  # noqa: D102
        self.unescaped.flush()

    def isatty(self) -> bool:  # noqa: D102
        return bool(getattr(self.unescaped, "isatty", lambda: False)())

    def fileno(self) -> int:  # noqa: D102
        return self.unescaped.fileno()

    @property
    def encoding(self) -> str:  # type: ignore[override]  # noqa: D102
        return getattr(self.unescaped, "encoding", "utf-8") or "utf-8"

    def writable(self) -> bool:  # noqa: D102
        return True


def control_stream(stream: TextIO) -> TextIO:
    """The stream under an :class:`EscapingStream` (``stream`` itself otherwise).

    For the program's own carriage returns and erase sequences, never for a user's text.
    """
    return getattr(stream, "unescaped", stream)


class EscapingFormatter(logging.Formatter):
    """A log formatter whose records' messages are escaped whole (one record, one line)."""

    def formatMessage(self, record: logging.LogRecord) -> str:  # noqa: D102, N802
        record.message = printable(record.message)
        return super().formatMessage(record)


@contextmanager
def escaped_output() -> Iterator[None]:
    """``sys.stdout`` and ``sys.stderr`` escaped (:class:`EscapingStream`) inside the block."""
    out, err = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = EscapingStream(out), EscapingStream(err)
    try:
        yield
    finally:
        sys.stdout, sys.stderr = out, err


def configure_logging(level: int) -> None:
    """The root logger at ``level``, its messages escaped, on stderr (as ``basicConfig``)."""
    handler = logging.StreamHandler()
    handler.setFormatter(EscapingFormatter("%(levelname)s %(name)s: %(message)s"))
    logging.basicConfig(level=level, handlers=[handler])

"""Bounded, strict reading of input files: a path to a regular file, UTF-8 text, strict JSON.

See :mod:`pivot_ompl.fileio` for the limits every input is held to.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

from pivot_ompl.errors import InputError

#: Largest input file read (bytes): scenes and plans are kilobytes to a few megabytes.
MAX_FILE_BYTES = 64 * 1024 * 1024


def input_path(path: Any, *, error: type[InputError] = InputError,
               field: str = "path") -> Path:
    """``path`` as a :class:`~pathlib.Path` when it is a ``str`` or ``os.PathLike``.

    Raises:
        error: any other type (naming ``field`` and the type), or a path holding a NUL
            character (no file can be named so: the system refuses it before any lookup).
    """
    if not isinstance(path, str | os.PathLike) or isinstance(path, bytes):
        raise error(field, type(path).__name__, "must be a file path (str or os.PathLike)")
    p = Path(path)
    if "\0" in str(p):
        raise error(field, str(p), "is not a file path (it holds a NUL character)")
    return p


def regular_file(path: Any, *, error: type[InputError] = InputError,
                 field: str = "path") -> Path:
    """``path`` once checked to be an existing regular file (never opened).

    Raises:
        error: not a path, missing or unreadable, a directory, or another file that is not a
            regular one (a FIFO, a socket or a device: reading it could block forever).
    """
    p = input_path(path, error=error, field=field)
    try:
        mode = p.stat().st_mode
    except OSError as e:
        raise error(field, str(p), f"cannot be read ({e.strerror or e})") from None
    if stat.S_ISDIR(mode):
        raise error(field, str(p), "is a directory, not a file")
    if not stat.S_ISREG(mode):
        raise error(field, str(p), "is not a regular file")
    return p


def read_text(path: str | Path, *, error: type[InputError] = InputError,
              field: str = "path") -> str:
    """The UTF-8 text of ``path`` (at most :data:`MAX_FILE_BYTES`).

    Raises:
        error: not a path, unreadable, not a regular file (see :func:`regular_file`), too
            large, or not UTF-8 (naming ``field`` and the path).
    """
    p = regular_file(path, error=error, field=field)
    try:
        with p.open("rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except IsADirectoryError:
        raise error(field, str(p), "is a directory, not a file") from None
    except OSError as e:
        raise error(field, str(p), f"cannot be read ({e.strerror or e})") from None
    if len(data) > MAX_FILE_BYTES:
        raise error(field, str(p), f"is larger than {MAX_FILE_BYTES // 2**20} MB")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise error("<document>", str(p), f"is not UTF-8 text (byte {e.start})",
                    source=str(p)) from None


def _no_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    d: dict[str, Any] = {}
    for k, v in pairs:
        if k in d:
            raise ValueError(f"duplicate key {k!r:.60}")
        d[k] = v
    return d


def load_json(path: str | Path, *, error: type[InputError] = InputError) -> Any:
    """Parse a JSON file strictly (no duplicate key, no NaN/Infinity, bounded nesting).

    Raises:
        error: unreadable, not UTF-8, invalid JSON, a duplicate key, too deeply nested.
    """
    src = str(path)
    text = read_text(path, error=error)

    def constant(name: str) -> Any:
        raise ValueError(f"{name} is not a JSON number")

    try:
        return json.loads(text, object_pairs_hook=_no_duplicates, parse_constant=constant)
    except RecursionError:
        raise error("<document>", src, "is nested too deeply", source=src) from None
    except ValueError as e:  # JSONDecodeError, duplicate key, integer too long
        raise error("<document>", src, f"is not valid JSON ({short_error(e)})",
                    source=src) from None


def short_error(e: Exception, n: int = 160) -> str:
    """``e``'s message on one line, at most ``n`` characters."""
    text = " ".join(str(e).split())
    return text if len(text) <= n else text[:n - 3] + "..."

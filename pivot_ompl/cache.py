"""Caches: a bounded least-recently-used memo, and the safe reading of a disk cache's entry.

A disk cache's entry is data anyone with access to the folder may have put there: it is read
only as a small regular file owned by this user and writable by no one else
(:func:`read_entry_bytes`), never followed through a symbolic link, never blocking (a FIFO is
refused at once); a JSON entry must also name its format and the key asked for
(:func:`read_json_entry`).
"""

from __future__ import annotations

import json
import os
import stat
from collections import OrderedDict
from collections.abc import Callable, Hashable
from pathlib import Path
from typing import Any, Generic, TypeVar

from pivot_ompl.errors import InputError, PivotError

#: Largest entry a disk cache reads (bytes).
MAX_ENTRY_BYTES = 64 * 1024

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")


class BoundedCache(Generic[K, V]):
    """At most ``size`` entries; the least recently used one goes first.

    Args:
        size: largest number of entries (>= 1).
    """

    def __init__(self, size: int) -> None:
        """An empty cache."""
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise InputError("size", size, "must be an integer >= 1")
        self.size = size
        self._items: OrderedDict[K, V] = OrderedDict()

    def __len__(self) -> int:
        """Number of entries."""
        return len(self._items)

    def __contains__(self, key: object) -> bool:
        """Whether ``key`` is held (does not count as a use)."""
        return key in self._items

    def get(self, key: K) -> V | None:
        """The value of ``key`` (now the most recently used), or ``None``."""
        v = self._items.get(key)
        if v is not None:
            self._items.move_to_end(key)
        return v

    def put(self, key: K, value: V) -> V:
        """Store ``value`` under ``key``, evicting the least recently used beyond ``size``."""
        self._items[key] = value
        self._items.move_to_end(key)
        while len(self._items) > self.size:
            self._items.popitem(last=False)
        return value

    def get_or_compute(self, key: K, compute: Callable[[], V]) -> V:
        """The value of ``key``, computed and stored if absent."""
        v = self.get(key)
        return v if v is not None else self.put(key, compute())

    def discard(self, key: K) -> None:
        """Forget ``key`` (nothing when absent)."""
        self._items.pop(key, None)

    def clear(self) -> None:
        """Forget every entry."""
        self._items.clear()


class CacheEntryError(PivotError):
    """A disk cache's entry is not one to trust (it is discarded, never raised to a user).

    Attributes:
        path: the entry's file.
        reason: why it is refused.
    """

    def __init__(self, path: str | Path, reason: str) -> None:
        self.path = str(path)
        self.reason = reason
        super().__init__(f"{path}: {reason}")


def read_entry_bytes(path: str | Path, *, max_bytes: int = MAX_ENTRY_BYTES) -> bytes | None:
    """The bytes of a disk cache's entry, ``None`` when there is none.

    The file is opened without following a final symbolic link and without blocking
    (``O_NOFOLLOW | O_NONBLOCK``), then checked on the open descriptor (``fstat``): a regular
    file, owned by this user, writable by no one else, at most ``max_bytes``.

    Raises:
        CacheEntryError: something is there but is not such a file (a link, a FIFO, a
            folder, a device, another owner's, too large, unreadable).
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOFOLLOW", 0) | getattr(
        os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise CacheEntryError(path, f"cannot be opened ({e.strerror or e})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise CacheEntryError(path, "is not a regular file")
        if hasattr(os, "getuid") and st.st_uid != os.getuid():
            raise CacheEntryError(path, "is owned by another user")
        if st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            raise CacheEntryError(path, "is writable by other users")
        if st.st_size > max_bytes:
            raise CacheEntryError(path, f"is larger than {max_bytes} bytes")
        chunks, size = [], 0
        while size <= max_bytes:
            chunk = os.read(fd, max_bytes + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise CacheEntryError(path, f"cannot be read ({e.strerror or e})") from None
    finally:
        os.close(fd)
    if size > max_bytes:
        raise CacheEntryError(path, f"is larger than {max_bytes} bytes")
    return b"".join(chunks)


def read_json_entry(path: str | Path, *, entry_format: str, key: str,
                    max_bytes: int = MAX_ENTRY_BYTES) -> dict[str, Any] | None:
    """A disk cache's JSON entry answering ``key``, ``None`` when there is none.

    Read as :func:`read_entry_bytes` reads it; a JSON object whose ``format`` is
    ``entry_format`` and whose ``key`` is ``key`` (``NaN`` and ``Infinity`` refused).

    Raises:
        CacheEntryError: something is there but is not such an entry.
    """
    data = read_entry_bytes(path, max_bytes=max_bytes)
    if data is None:
        return None

    def constant(name: str) -> Any:
        raise ValueError(f"{name} is not a number")

    try:
        doc = json.loads(data.decode("utf-8"), parse_constant=constant)
    except (ValueError, RecursionError):
        raise CacheEntryError(path, "is not JSON") from None
    if not isinstance(doc, dict) or doc.get("format") != entry_format:
        raise CacheEntryError(path, f"is not a {entry_format} entry")
    if doc.get("key") != key:
        raise CacheEntryError(path, "answers another key (another scene or relaxation)")
    return doc

"""Output files: checked before any work, written all or nothing.

See :mod:`pivot_ompl.fileio` (writing).
"""

from __future__ import annotations

import errno
import os
import shutil
import uuid
from collections.abc import Iterable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from pivot_ompl.errors import InputError
from pivot_ompl.fileio.reading import input_path


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_output(path: str | Path, *, field: str, inputs: Iterable[str | Path] = (),
                 suffixes: Iterable[str] = ()) -> Path:
    """Validate an output path before any work; return it.

    Raises:
        InputError: ``path`` is not a path or is a directory, a name in it is longer than its
            file system allows (:data:`MAX_NAME` bytes where it cannot be asked) or the
            whole path longer than :data:`MAX_PATH` bytes, it is one of ``inputs``, has a
            suffix not in ``suffixes`` (when given), or its folder is a file.
    """
    p = input_path(path, field=field)
    _within_name_limits(p, field)
    if not str(path) or p.is_dir() or str(path).endswith(os.sep):
        raise InputError(field, str(path), "is a directory: give a file name")
    allowed = [s.lower() for s in suffixes]
    if allowed and p.suffix.lower() not in allowed:
        raise InputError(field, str(path), f"unsupported extension (use one of {allowed})")
    for src in inputs:
        if _same_file(p, Path(src)):
            raise InputError(field, str(path), f"is the input file {src}: refusing to "
                             "overwrite it")
    for parent in p.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(field, str(path), f"{parent} is not a directory")
            break
    return p


#: Longest file name an output may have (bytes) where the file system cannot be asked (the
#: usual limit of Linux file systems).
MAX_NAME = 255
#: Longest output path (bytes, the usual ``PATH_MAX`` of Linux).
MAX_PATH = 4095


def _name_max(p: Path) -> int:
    """The longest file name (bytes) of the file system of ``p``'s nearest existing folder."""
    for folder in (p.parent, *p.parents):
        try:  # a folder name too long for the system is not an existing folder either
            if folder.is_dir():
                return min(MAX_NAME, int(os.pathconf(folder, "PC_NAME_MAX")))
        except (OSError, ValueError):
            continue
    return MAX_NAME


def _within_name_limits(p: Path, field: str) -> None:
    """Refuse ``p`` when one of its names, or itself, is too long to be created.

    Checked before any work (the temporary names of :func:`atomic_outputs` are short).
    """
    text = str(p).encode(errors="surrogateescape")
    if len(os.path.abspath(p).encode(errors="surrogateescape")) > MAX_PATH:
        raise InputError(field, str(p), f"path longer than {MAX_PATH} bytes")
    limit = _name_max(p)
    for part in p.parts:
        if len(part.encode(errors="surrogateescape")) > limit:
            what = "file" if part == p.name else "folder"
            raise InputError(field, text.decode(errors="replace"),
                             f"{what} name longer than {limit} bytes: {part[:40]}...")
#: Longest file stem :func:`file_stem` makes (bytes; room for suffixes and temporary names
#: under the usual 255-byte limit of a file name).
MAX_STEM = 100


def file_stem(name: str) -> str:
    """A file name stem made from a name read from a file (a scene's ``name``): never a path.

    Letters, digits, ``.``, ``-`` and ``_`` are kept, every other character becomes ``_``;
    leading dots are dropped (no ``..``, no hidden file) and the stem is cut to
    :data:`MAX_STEM` characters; an empty result is ``"unnamed"``.
    """
    stem = "".join(c if (c.isascii() and c.isalnum()) or c in "._-" else "_" for c in name)
    stem = stem.lstrip(".")[:MAX_STEM]
    return stem or "unnamed"


def _temporary(p: Path) -> Path:
    """A short temporary name next to ``p`` with its suffix (never longer than a short name)."""
    return p.with_name(f".pivot-{uuid.uuid4().hex[:12]}.tmp{p.suffix[:32]}")


def _replace_all(moves: list[tuple[Path, Path]]) -> None:
    """``os.replace`` each ``(temporary, target)``: all, or none of the targets changed.

    A target that is a folder is refused before any move. Each target replaced is first kept
    as a hard link; when a later move fails, the targets already replaced get their previous
    content back (or are removed when they were new).
    """
    for _, p in moves:
        if p.is_dir():
            raise OSError(errno.EISDIR, "Is a directory", str(p))
    done: list[tuple[Path, Path | None]] = []
    backups: list[Path] = []
    try:
        for tmp, p in moves:
            backup: Path | None = _temporary(p)
            try:
                os.link(p, str(backup))
            except FileNotFoundError:
                backup = None  # a new file
            except OSError:  # no hard links here: a copy
                shutil.copy2(p, str(backup))
            if backup is not None:
                backups.append(backup)
            os.replace(tmp, p)
            done.append((p, backup))
    except BaseException:
        for p, backup in reversed(done):
            with suppress(OSError):
                if backup is None:
                    p.unlink()
                else:
                    os.replace(backup, p)
        raise
    finally:
        for backup in backups:
            with suppress(FileNotFoundError):
                backup.unlink()



@contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; move it onto ``path`` only on success.

    The temporary name keeps the suffix (writers that infer the format from it work). On an
    exception the temporary file is removed and ``path`` is untouched.
    """
    with atomic_outputs(path) as (tmp,):
        assert tmp is not None  # noqa: S101 - for mypy
        yield tmp


@contextmanager
def atomic_outputs(*paths: str | Path | None) -> Iterator[tuple[Path | None, ...]]:
    """Temporary paths next to each of ``paths``, moved into place together on success.

    All or nothing: when the block raises (an error, Ctrl-C), every temporary file is removed
    and no target is touched; targets are replaced only after every output has been written.
    ``None`` among ``paths`` (an output not asked for) yields ``None``. An ``OSError`` about a
    temporary file names its target instead (the user's file, not ``.pivot-*.tmp``).

    Raises:
        InputError: two of ``paths`` name one file.
    """
    targets = [None if p is None else Path(p) for p in paths]
    seen: set[str] = set()
    for p in targets:
        if p is None:
            continue
        key = os.path.abspath(p)
        if key in seen:
            raise InputError("output", str(p), "is named twice among one run's outputs")
        seen.add(key)
    for p in targets:
        if p is not None:
            p.parent.mkdir(parents=True, exist_ok=True)
    temps = tuple(None if p is None else _temporary(p) for p in targets)
    names = {str(t): str(p) for t, p in zip(temps, targets, strict=True) if t is not None}
    try:
        yield temps
        for tmp in temps:
            if tmp is not None and not tmp.exists():
                raise OSError(errno.ENOENT, "was not written", str(tmp))
        _replace_all([(t, p) for t, p in zip(temps, targets, strict=True)
                      if t is not None and p is not None])
    except OSError as e:
        if str(e.filename) in names or str(e.filename2) in names:
            raise OSError(e.errno, e.strerror or str(e),
                          names.get(str(e.filename), e.filename)) from None
        raise
    finally:
        for tmp in temps:
            if tmp is not None:
                with suppress(FileNotFoundError):
                    tmp.unlink()

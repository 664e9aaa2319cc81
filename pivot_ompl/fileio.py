"""The file boundary: bounded, strict reading of YAML/JSON inputs and atomic output writing.

Reading (scene YAML, ``pivot-plan/1`` JSON): at most :data:`MAX_FILE_BYTES`, UTF-8 only,
duplicate keys refused, YAML aliases expanded to at most :data:`MAX_NODES` nodes (a "billion
laughs" file is refused in milliseconds), nesting deeper than the parser's recursion refused,
integers too long for a float refused. Every failure is an :class:`~pivot_ompl.errors.InputError`
of the caller's kind naming the file.

Every input is first a path (``str`` or ``os.PathLike``) to a regular file
(:func:`regular_file`): a FIFO, a socket or a device is refused at once, never read (reading
could block forever).

Writing: :func:`atomic_outputs` yields a short temporary path next to each target; the targets
are replaced (``os.replace``) only when the ``with`` block succeeds, so a failed or interrupted
run never destroys an existing file and a run's outputs are written all or nothing. Files are
created with the process's umask (no mode of their own). :func:`check_output` refuses, before
any work, a target that is a directory, that is one of the run's input files, whose names are
too long for its file system, or whose folder is a file.
"""

from __future__ import annotations

import errno
import gc
import itertools
import json
import os
import shutil
import stat
import time
import uuid
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any

import yaml

from pivot_ompl.errors import InputError, Interrupted

#: Largest input file read (bytes): scenes and plans are kilobytes to a few megabytes.
MAX_FILE_BYTES = 64 * 1024 * 1024
#: Largest number of YAML nodes after alias expansion (a 64 MB file of plain data holds fewer;
#: the largest documented scene, 100 000 obstacles, about 1.6 M).
MAX_NODES = 8_000_000


def input_path(path: Any, *, error: type[InputError] = InputError,
               field: str = "path") -> Path:
    """``path`` as a :class:`~pathlib.Path` when it is a ``str`` or ``os.PathLike``.

    Raises:
        error: any other type (naming ``field`` and the type).
    """
    if not isinstance(path, str | os.PathLike) or isinstance(path, bytes):
        raise error(field, type(path).__name__, "must be a file path (str or os.PathLike)")
    return Path(path)


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


#: PyYAML's safe loader on libyaml's C parser where PyYAML has it (about ten times faster on
#: large scenes; the same documents, the same errors), else the pure-Python one.
_SafeBase = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _StrictLoader(_SafeBase):  # type: ignore[valid-type,misc]
    """PyYAML's safe loader that refuses duplicate mapping keys."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            try:
                dup = key in seen
                seen.add(key)
            except TypeError:  # an unhashable key: the base class reports it
                break
            if dup:
                raise yaml.constructor.ConstructorError(
                    None, None, f"duplicate key {key!r:.60}", key_node.start_mark)
        return super().construct_mapping(node, deep=deep)


#: Nodes composed, built or counted between two polls of a parse's ``should_stop``.
POLL_NODES = 1024


def _loader(text: str, should_stop: Callable[[], bool] | None) -> _StrictLoader:
    """A :class:`_StrictLoader` of ``text`` that polls ``should_stop``.

    libyaml composes the nodes in C and calls :meth:`resolve` once per node (there is no
    other way in), the constructor calls ``construct_mapping`` and ``construct_sequence`` once
    per mapping and list: all poll every :data:`POLL_NODES` calls, so a time limit stops a
    100 000-obstacle scene's parse, and a 10 000-point polygon's.
    """
    if should_stop is None:
        return _StrictLoader(text)
    calls = itertools.count(1)

    def poll() -> None:
        if next(calls) % POLL_NODES == 0 and should_stop():
            raise Interrupted("reading the scene")

    class _PollingLoader(_StrictLoader):
        def resolve(self, kind: Any, value: Any, implicit: Any) -> Any:
            poll()
            return super().resolve(kind, value, implicit)

        def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
            poll()
            return super().construct_mapping(node, deep=deep)

        def construct_sequence(self, node: yaml.SequenceNode, deep: bool = False) -> list:
            poll()
            return super().construct_sequence(node, deep=deep)

    return _PollingLoader(text)


def _expanded_size(node: yaml.Node, memo: dict[int, int],
                   should_stop: Callable[[], bool] | None = None) -> int:
    """Number of nodes of ``node`` once aliases are expanded (shared nodes counted each time)."""
    k = id(node)
    if k in memo:
        return memo[k]
    if should_stop is not None and len(memo) % POLL_NODES == 0 and should_stop():
        raise Interrupted("reading the scene")
    memo[k] = MAX_NODES + 1  # a cycle (recursive alias) counts as too large
    n = 1
    if isinstance(node, yaml.SequenceNode):
        for child in node.value:
            n += _expanded_size(child, memo, should_stop)
            if n > MAX_NODES:
                break
    elif isinstance(node, yaml.MappingNode):
        for kn, vn in node.value:
            n += _expanded_size(kn, memo, should_stop) + _expanded_size(vn, memo, should_stop)
            if n > MAX_NODES:
                break
    memo[k] = n
    return n


def load_yaml(path: str | Path, *, error: type[InputError] = InputError,
              should_stop: Callable[[], bool] | None = None) -> Any:
    """Parse a YAML file strictly (see the module docstring).

    Python's cyclic garbage collector is paused while the document is built (millions of
    objects, none of them garbage: with it a 100 000-obstacle scene took 24 s, without 9 s),
    and resumed only once a stopped parse has let go of them (with the stop's traceback
    still holding them, the first collection after took 1.7 s).

    Raises:
        error: unreadable, not UTF-8, invalid YAML, a duplicate key, too many or too deeply
            nested nodes.
        Interrupted: ``should_stop()`` became true (polled every :data:`POLL_NODES` nodes).
    """
    src = str(path)
    text = read_text(path, error=error)
    try:
        loader = _loader(text, should_stop)  # the reader refuses control characters here
    except yaml.YAMLError as e:
        raise error("<document>", src, f"is not valid YAML ({_short(e)})", source=src) from None
    collecting = gc.isenabled()
    gc.disable()
    try:
        return _parse(loader, src, error, should_stop)
    except Interrupted:
        pass  # raised again below, once its traceback no longer holds the nodes
    finally:
        _release(loader)
        if collecting:
            gc.enable()
    raise Interrupted("reading the scene")


def _release(loader: _StrictLoader) -> None:
    """Drop what ``loader`` holds of a parse, so that reference counting frees it at once.

    A construction stopped midway leaves PyYAML's pending generators on the loader, whose
    frames hold the loader again: a cycle only the garbage collector frees, by traversing
    every node of the document (0.05 s at 60 000 nodes, not polled).
    """
    loader.dispose()
    loader.state_generators = []
    loader.constructed_objects = {}
    loader.recursive_objects = {}


#: Time that freeing what a stopped parse built takes, as a share of the time it ran (a
#: 100 000-obstacle scene: 0.07 to 0.53 s after 1 to 8 s).
UNWIND_SHARE = 0.1


def parse_deadline(deadline: float) -> Callable[[], bool]:
    """The ``should_stop`` of a parse (:func:`load_yaml`) that must be over by ``deadline``.

    ``deadline`` is a ``time.monotonic()`` time; the stop is true once the time left is less
    than freeing what the parse built takes (:data:`UNWIND_SHARE` of the time since this call).
    """
    started = time.monotonic()

    def should_stop() -> bool:
        now = time.monotonic()
        return now + UNWIND_SHARE * (now - started) >= deadline

    return should_stop


def _parse(loader: _StrictLoader, src: str, error: type[InputError],
           should_stop: Callable[[], bool] | None) -> Any:
    """The document of :func:`load_yaml`'s ``loader``."""
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        if _expanded_size(node, {}, should_stop) > MAX_NODES:
            raise error("<document>", src, f"expands to more than {MAX_NODES} YAML nodes "
                        "(aliases expanded)", source=src)
        return loader.construct_document(node)
    except yaml.YAMLError as e:
        if "nesting depth" in str(e):  # libyaml's own depth limit
            raise error("<document>", src, "is nested too deeply", source=src) from None
        raise error("<document>", src, f"is not valid YAML ({_short(e)})", source=src) from None
    except RecursionError:
        raise error("<document>", src, "is nested too deeply", source=src) from None


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
        raise error("<document>", src, f"is not valid JSON ({_short(e)})", source=src) from None


def _short(e: Exception, n: int = 160) -> str:
    text = " ".join(str(e).split())
    return text if len(text) <= n else text[:n - 3] + "..."


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

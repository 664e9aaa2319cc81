"""The manifest of a sweep's folder: the files a sweep wrote, so that only those are replaced.

``bench-manifest.json`` lists every file the last sweep wrote into the folder, with its size
and SHA-256. ``bench --overwrite`` removes a file only when the previous manifest lists it
and the file is still what that sweep wrote (a regular file of that size and digest); any
other file is the user's and stays. A new output whose name is taken by a file no sweep wrote
(or one changed since) is refused before any run.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import stat
from collections.abc import Iterable
from pathlib import Path

from pivot_ompl.errors import InputError

log = logging.getLogger(__name__)

#: The manifest's file name in a sweep's folder.
MANIFEST = "bench-manifest.json"
#: Its ``format`` field.
MANIFEST_FORMAT = "pivot-bench-manifest/1"
#: Largest manifest read (bytes).
MAX_MANIFEST_BYTES = 4 * 1024 * 1024


def _digest(path: Path) -> str | None:
    """SHA-256 of a regular file (not followed through a link), ``None`` for anything else."""
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return None
        h = hashlib.sha256()
        with path.open("rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest()
    except OSError:
        return None


def manifest_of(folder: Path, names: Iterable[str]) -> dict:
    """The manifest of the files ``names`` in ``folder`` (as a sweep wrote them)."""
    files = {}
    for name in sorted(names):
        p = folder / name
        files[name] = {"size": p.stat().st_size, "sha256": _digest(p)}
    return {"format": MANIFEST_FORMAT, "files": files}


def write_manifest(folder: Path, names: Iterable[str]) -> Path:
    """Write the manifest of ``names`` (files in ``folder``) into ``folder``."""
    path = folder / MANIFEST
    path.write_text(json.dumps(manifest_of(folder, names), indent=1) + "\n")
    return path


def previous_outputs(folder: Path) -> dict[str, dict]:
    """The files the last sweep wrote into ``folder`` and that are still as it wrote them.

    The manifest itself is one of them. No manifest, or one that does not read: nothing (no
    file is a sweep's).
    """
    files = _read_manifest(folder)
    if files is None:
        return {}
    kept: dict[str, dict] = {MANIFEST: {}}
    for name, rec in files.items():
        if (not isinstance(name, str) or not isinstance(rec, dict) or name != Path(name).name
                or name in ("", ".", "..") or name == MANIFEST):
            continue
        p = folder / name
        try:
            size = os.lstat(p).st_size
        except OSError:
            continue
        if size == rec.get("size") and _digest(p) == rec.get("sha256"):
            kept[name] = rec
    return kept


def _read_manifest(folder: Path) -> dict | None:
    """The ``files`` of ``folder``'s manifest, ``None`` when it has none that reads."""
    path = folder / MANIFEST
    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return None
        if path.stat().st_size > MAX_MANIFEST_BYTES:
            return None
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or doc.get("format") != MANIFEST_FORMAT:
        return None
    files = doc.get("files")
    return files if isinstance(files, dict) else None


def check_names_free(folder: Path, names: Iterable[str]) -> None:
    """Refuse, before any run, new outputs whose names hold files no sweep wrote.

    Raises:
        InputError: such a file (the user's, or a sweep's output changed since).
    """
    ours = previous_outputs(folder)
    for name in names:
        p = folder / name
        if name not in ours and (p.exists() or p.is_symlink()):
            raise InputError("--out", str(p), "is not a file a previous sweep wrote (not in "
                             f"its {MANIFEST}, or changed since): --overwrite replaces only "
                             "those; move it away or give another folder")


def publish(staging: Path, folder: Path) -> None:
    """Replace the previous sweep's outputs in ``folder`` by the files in ``staging``.

    Only files the previous manifest lists, unchanged, are removed; the new manifest lists
    the new files.
    """
    old = previous_outputs(folder)
    new = sorted(p.name for p in staging.iterdir() if p.name != MANIFEST)
    write_manifest(staging, new)
    for name in old:
        if name not in new and name != MANIFEST:
            try:
                (folder / name).unlink()
            except OSError as e:
                log.warning("previous output %s not removed: %s", folder / name, e)
    for name in [*new, MANIFEST]:
        os.replace(staging / name, folder / name)

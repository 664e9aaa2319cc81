"""What the benchmark scripts share: scenes named on the command line, figures as JSON."""

from __future__ import annotations

import contextlib
import fcntl
import json
import math
import os
import statistics
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

#: this checkout: the package a benchmark's own process makes its scenes with
ROOT = Path(__file__).resolve().parents[1]


def _finite(x: Any) -> Any:
    """``x`` with NaN and infinities as ``None`` (JSON has neither)."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_finite(v) for v in x]
    return x


def write_json(res: dict[str, Any], out: str | Path) -> Path:
    """Write ``res`` to ``out`` (folders made as needed) and say so."""
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_finite(res), indent=1, default=float, allow_nan=False) + "\n")
    print(f"written {path}")
    return path


def scene_from_spec(spec: str):  # noqa: ANN201 (a Scene of whichever package version runs)
    """A scene file or shipped scene's name, or ``gen:FAMILY:SEED[:NAME=VALUE...]``.

    The generated form takes ``GeneratorParams`` fields (``gen:walls:1:walls=2``,
    ``gen:building:0:rooms=3``).
    """
    import dataclasses

    from pivot_ompl.generate import GeneratorParams, generate
    from pivot_ompl.scene import load_scene

    if not spec.startswith("gen:"):
        return load_scene(spec)
    _, family, seed, *pairs = spec.split(":")
    fields = {f.name for f in dataclasses.fields(GeneratorParams)}
    values: dict[str, Any] = {}
    for pair in pairs:
        key, value = pair.split("=", 1)
        if key not in fields:
            raise SystemExit(f"{spec}: no generator parameter {key!r}")
        values[key] = value if key == "layout" else (
            int(value) if key in ("walls", "rooms") else float(value))
    return generate(family, int(seed), params=GeneratorParams(**values)).scene


def this_checkout() -> None:
    """Put this checkout's package first on ``sys.path``; exit if another one is imported.

    A benchmark comparing versions runs each in its own process; its own process (the one
    that makes the scenes they share) must use this checkout's.
    """
    if sys.path[0] != str(ROOT):
        sys.path.insert(0, str(ROOT))
    import pivot_ompl

    where = Path(pivot_ompl.__file__).resolve().parents[1]
    if where != ROOT:
        raise SystemExit(f"pivot_ompl was imported from {where}, not from this checkout {ROOT}")


def written_scene(scene: Any, folder: Path, stem: str) -> Path:
    """``scene`` written by this checkout's package to ``folder/stem.yaml`` (exact floats).

    The file every version of a comparison loads: a generated scene depends on the version
    that makes it (its witness plan runs that version's checks) and a shipped one may differ
    between versions, so versions that each made their own could plan different layouts
    under one name.
    """
    this_checkout()
    from pivot_ompl.generate.sceneio import write_scene

    folder.mkdir(parents=True, exist_ok=True)
    return write_scene(scene, folder / f"{stem}.yaml")


def scene_file(spec: str, folder: Path, stem: str) -> str:
    """The scene of ``spec`` as one file for every version: an existing file as is (its
    absolute path), any other spec (:func:`scene_from_spec`) made once by this checkout
    (:func:`written_scene`)."""
    if Path(spec).is_file():
        return str(Path(spec).resolve())  # versions run in their own folders
    this_checkout()
    return str(written_scene(scene_from_spec(spec), folder, stem))


def cpu_timed(owner: Any, name: str, bucket: dict[str, float], key: str | None = None) -> None:
    """Wrap ``owner.name`` (if the version has it) to sum its CPU seconds into ``bucket[key]``.

    ``key`` defaults to ``name``; the entry is 0 from the start (the version has that stage),
    left out when the version has no ``owner.name`` (a caller may clear the bucket between
    runs).
    """
    fn = getattr(owner, name, None)
    if fn is None:
        return
    column = key or name
    bucket.setdefault(column, 0.0)

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t0 = time.process_time()
        try:
            return fn(*args, **kwargs)
        finally:
            bucket[column] = bucket.get(column, 0.0) + time.process_time() - t0

    setattr(owner, name, wrapper)


@contextlib.contextmanager
def machine_lock() -> Iterator[None]:
    """Hold ``$PIVOT_BENCH_LOCK`` (``flock``) when it is set: one timing run at a time."""
    path = os.environ.get("PIVOT_BENCH_LOCK")
    if not path:
        yield
        return
    with open(path, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def median_of(rows: list[dict[str, Any]], key: str) -> float | None:
    """The median of the rows' numbers under ``key`` (rows without one left out), or ``None``."""
    vals = [r[key] for r in rows if isinstance(r.get(key), int | float)]
    return statistics.median(vals) if vals else None


def fmt(x: float | None, spec: str) -> str:
    """``x`` formatted with ``spec``, ``-`` for ``None``."""
    return "-" if x is None else format(x, spec)


class TreeMemory:
    """Peak resident memory (MB) of a process and its descendants together (Linux).

    Sampled every ``period`` s in a thread from ``/proc``: a plan's prover process
    (:mod:`pivot_ompl.analysis.prover`) counts with the plan's own, at the same time, which
    ``ru_maxrss`` (the largest single process) does not. :meth:`stop` returns the peak.
    """

    def __init__(self, pid: int, period: float = 0.02) -> None:
        import threading

        self.pid, self.period, self.peak_mb = pid, period, 0.0
        self._done = threading.Event()
        self._page_mb = os.sysconf("SC_PAGE_SIZE") / 2**20
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()

    def _tree(self, pid: int) -> list[int]:
        out, todo = [], [pid]
        while todo:
            p = todo.pop()
            out.append(p)
            for task in Path(f"/proc/{p}/task").glob("*/children"):
                with contextlib.suppress(OSError):
                    todo.extend(int(c) for c in task.read_text().split())
        return out

    def _sample(self) -> None:
        while not self._done.is_set():
            total = 0.0
            for p in self._tree(self.pid):
                with contextlib.suppress(OSError, ValueError, IndexError):
                    total += int(Path(f"/proc/{p}/statm").read_text().split()[1]) * self._page_mb
            self.peak_mb = max(self.peak_mb, total)
            self._done.wait(self.period)

    def stop(self) -> float:
        """Stop sampling; the peak (MB)."""
        self._done.set()
        self._thread.join()
        return self.peak_mb


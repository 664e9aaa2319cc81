"""The SQLite database of ``ompl_benchmark_statistics`` (what Planner Arena reads).

:func:`build_database` does what ``ompl_benchmark_statistics -d DB LOG...`` does (a fresh
database, the logs read by ``ompl.tools.readBenchmarkLog``, then ``computeViews``), using the
module shipped in the ``ompl`` wheel (``ompl/_benchmark_statistics.py``); its progress prints go
to the logger. The console script ``ompl_benchmark_statistics`` gives the same database.
"""

from __future__ import annotations

import contextlib
import io
import logging
import sqlite3
from collections.abc import Sequence
from pathlib import Path

log = logging.getLogger(__name__)


def build_database(db: str | Path, logs: Sequence[str | Path], *, append: bool = False) -> Path:
    """Build (or with ``append`` extend) the SQLite database ``db`` from OMPL logs."""
    from ompl._benchmark_statistics import computeViews, readBenchmarkLog

    db = Path(db)
    db.parent.mkdir(parents=True, exist_ok=True)
    if not append and db.exists():
        db.unlink()
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        readBenchmarkLog(str(db), [str(p) for p in logs], False)
        computeViews(str(db), False)
    for line in out.getvalue().splitlines():
        log.debug("ompl_benchmark_statistics: %s", line)
    return db


def run_columns(db: str | Path) -> list[str]:
    """Return the column names of the ``runs`` table."""
    with contextlib.closing(sqlite3.connect(db)) as conn:
        return [row[1] for row in conn.execute("PRAGMA table_info(runs)")]

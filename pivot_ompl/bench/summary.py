"""The summary table of a sweep: success, time and solution quality per scene and planner."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.bench.job import JobResult
from pivot_ompl.bench.ompl_log import STATUS
from pivot_ompl.errors import printable


@dataclass(frozen=True)
class Row:
    """Figures of one (scene, planner) pair.

    Attributes:
        scene, planner: the pair.
        runs: number of runs.
        solved: runs with an exact solution.
        crashed: runs with status ``Crash``.
        median_time, p95_time: over all runs (a run that fails counts its time, about the
            limit) (s).
        mean_time: mean over all runs (s).
        pivots, regrasps, length: medians over solved runs (``nan`` when none); ``length`` is
            OMPL's ``solution length`` (distance of the compound space).
    """

    scene: str
    planner: str
    runs: int
    solved: int
    crashed: int
    median_time: float
    p95_time: float
    mean_time: float
    pivots: float
    regrasps: float
    length: float

    @property
    def success(self) -> float:
        """Return the fraction of runs with an exact solution."""
        return self.solved / self.runs if self.runs else 0.0


def _num(run: dict[str, str], name: str) -> float:
    v = run.get(name, "")
    try:
        return float(v)
    except ValueError:
        return math.nan


def exact(run: dict[str, str]) -> bool:
    """Tell whether a run found an exact solution."""
    return run.get("status ENUM") == str(STATUS["EXACT_SOLUTION"])


def _median(xs: list[float]) -> float:
    xs = [x for x in xs if not math.isnan(x)]
    return float(np.median(xs)) if xs else math.nan


def summarize(results: Iterable[JobResult]) -> list[Row]:
    """Return one row per (scene, planner), in first-seen order."""
    groups: dict[tuple[str, str], list[dict[str, str]]] = {}
    for r in results:
        groups.setdefault((r["scene"], r["planner"]), []).append(r["run"])
    rows = []
    for (scene, planner), runs in groups.items():
        times = [_num(r, "time REAL") for r in runs]
        ok = [r for r in runs if exact(r)]
        rows.append(Row(
            scene, planner, len(runs), len(ok),
            sum(r.get("status ENUM") == str(STATUS["CRASH"]) for r in runs),
            float(np.median(times)), float(np.percentile(times, 95)), float(np.mean(times)),
            _median([_num(r, "pivots INTEGER") for r in ok]),
            _median([_num(r, "regrasps INTEGER") for r in ok]),
            _median([_num(r, "solution length REAL") for r in ok])))
    return rows


def _f(x: float, fmt: str) -> str:
    return "-" if math.isnan(x) else format(x, fmt)


def format_table(rows: Iterable[Row]) -> str:
    """Format the rows as a plain-text table."""
    head = ("scene", "planner", "runs", "success", "crash", "t median", "t p95", "t mean",
            "pivots", "regrasps", "length")
    lines = [head]
    for r in rows:
        lines.append((printable(r.scene), printable(r.planner), str(r.runs),
                      f"{100 * r.success:.0f} %",
                      str(r.crashed), f"{r.median_time:.3f} s", f"{r.p95_time:.3f} s",
                      f"{r.mean_time:.3f} s", _f(r.pivots, ".0f"), _f(r.regrasps, ".0f"),
                      _f(r.length, ".2f")))
    widths = [max(len(line[i]) for line in lines) for i in range(len(head))]
    out = []
    for k, line in enumerate(lines):
        cells = [c.ljust(w) if i < 2 else c.rjust(w) for i, (c, w) in
                 enumerate(zip(line, widths, strict=True))]
        out.append("  ".join(cells).rstrip())
        if k == 0:
            out.append("  ".join("-" * w for w in widths))
    return "\n".join(out) + "\n"


def format_markdown(rows: Iterable[Row]) -> str:
    """Format the rows as a Markdown table."""
    out = ["| scene | planner | runs | success | crash | median time (s) | p95 time (s) "
           "| mean time (s) | pivots | regrasps | length |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {printable(r.scene)} | {printable(r.planner)} | {r.runs} | "
                   f"{100 * r.success:.0f} % | "
                   f"{r.crashed} | {r.median_time:.3f} | {r.p95_time:.3f} | "
                   f"{r.mean_time:.3f} | {_f(r.pivots, '.0f')} | {_f(r.regrasps, '.0f')} | "
                   f"{_f(r.length, '.2f')} |")
    return "\n".join(out) + "\n"

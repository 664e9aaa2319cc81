"""The generality benchmark: planners on generated scenes (with witnesses) and shipped ones.

:func:`generate_suite` writes ``count`` scenes of each family (seeds ``seed0 ..``) with their
witness plans; :func:`family_rows` turns a sweep's runs into success and times per family
and planner (a generated scene's family is the generator's; a shipped scene is its own family).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pivot_ompl.bench.summary import exact
from pivot_ompl.generate import generate, write_generated


@dataclass(frozen=True)
class FamilyRow:
    """Figures of one planner on one family of scenes.

    Attributes:
        family: family name (or a shipped scene's name).
        planner: planner label.
        runs: runs counted.
        success: fraction of runs with an exact solution.
        median_time: median solve time over all runs (unsolved count as the limit; s).
        p95_time: 95th percentile of the same (s).
    """

    family: str
    planner: str
    runs: int
    success: float
    median_time: float
    p95_time: float


def generate_suite(families: Sequence[str], *, count: int, out: str | Path,
                   seed0: int = 0) -> dict[Path, str]:
    """Write ``count`` scenes (and witnesses) per family into ``out``; scene path -> family."""
    paths: dict[Path, str] = {}
    for fam in families:
        for seed in range(seed0, seed0 + count):
            scene_path, _ = write_generated(generate(fam, seed), out)
            paths[scene_path] = fam
    return paths


def family_rows(results: Sequence[Mapping], families: Mapping[str, str], *,
                time_limit: float) -> list[FamilyRow]:
    """Success and times per (family, planner); ``families`` maps scene name -> family."""
    groups: dict[tuple[str, str], list[tuple[bool, float]]] = {}
    for r in results:
        run = r["run"]
        ok = exact(run)
        t = float(run.get("time REAL", "nan")) if ok else time_limit
        key = (families.get(r["scene"], r["scene"]), r["planner"])
        groups.setdefault(key, []).append((ok, t if math.isfinite(t) else time_limit))
    rows = []
    for (fam, planner), xs in groups.items():
        times = sorted(t for _, t in xs)
        p95 = float(np.percentile(times, 95, method="inverted_cdf"))  # nearest rank
        rows.append(FamilyRow(fam, planner, len(xs), sum(ok for ok, _ in xs) / len(xs),
                              statistics.median(times), p95))
    return sorted(rows, key=lambda row: (row.family, row.planner))


def format_rows(rows: Sequence[FamilyRow]) -> str:
    """A plain-text table of :func:`family_rows`."""
    lines = [f"{'family':<16} {'planner':<12} {'runs':>5} {'success':>8} {'median s':>9} "
             f"{'p95 s':>7}"]
    for r in rows:
        lines.append(f"{r.family:<16} {r.planner:<12} {r.runs:5d} {100 * r.success:7.0f}% "
                     f"{r.median_time:9.2f} {r.p95_time:7.2f}")
    return "\n".join(lines) + "\n"

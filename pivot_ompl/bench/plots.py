"""Plots of a sweep (PNG): solve-time distributions and success against the time limit."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pivot_ompl.bench.job import JobResult
from pivot_ompl.bench.summary import exact
from pivot_ompl.errors import printable

#: Matplotlib settings of every figure: texts are plain (a ``$`` is a dollar sign).
PLAIN_TEXT: dict[Any, Any] = {"text.parse_math": False}


def _by_planner(results: Iterable[JobResult], scene: str) -> dict[str, list[dict[str, str]]]:
    out: dict[str, list[dict[str, str]]] = {}
    for r in results:
        if r["scene"] == scene:
            out.setdefault(r["planner"], []).append(r["run"])
    return out


def _time(run: dict[str, str]) -> float:
    try:
        return float(run.get("time REAL", "nan"))
    except ValueError:
        return float("nan")


def plot_times(results: Sequence[JobResult], scene: str, time_limit: float,
               path: str | Path) -> Path:
    """Box plot of the solve time per planner; solved runs as dots, failures as crosses."""
    import matplotlib

    matplotlib.use("Agg")
    with matplotlib.rc_context(PLAIN_TEXT):  # names drawn as they are, never as mathtext
        return _plot_times(results, scene, time_limit, path)


def _plot_times(results: Sequence[JobResult], scene: str, time_limit: float,
                path: str | Path) -> Path:
    import matplotlib.pyplot as plt

    groups = _by_planner(results, scene)
    names = list(groups)
    fig, ax = plt.subplots(figsize=(1.6 + 1.4 * len(names), 4.0))
    data = [[_time(r) for r in groups[n]] for n in names]
    ax.boxplot(data, showfliers=False)
    ax.set_xticks(range(1, len(names) + 1), names)
    rng = np.random.default_rng(0)  # fixed jitter: the figure is reproducible
    for i, n in enumerate(names, start=1):
        for run in groups[n]:
            x = i + rng.uniform(-0.15, 0.15)
            ok = exact(run)
            ax.plot(x, _time(run), "o" if ok else "x", ms=4, alpha=0.7,
                    color="tab:green" if ok else "tab:red")
    ax.axhline(time_limit, ls="--", color="grey", lw=1, label=f"time limit {time_limit:g} s")
    ax.set_ylabel("solve time (s)")
    ax.set_title(f"{printable(scene)}: solve time (o solved, x not solved)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_success(results: Sequence[JobResult], scene: str, time_limit: float,
                 path: str | Path) -> Path:
    """Fraction of runs solved within ``t``, for ``t`` up to the time limit, per planner."""
    import matplotlib

    matplotlib.use("Agg")
    with matplotlib.rc_context(PLAIN_TEXT):  # names drawn as they are, never as mathtext
        return _plot_success(results, scene, time_limit, path)


def _plot_success(results: Sequence[JobResult], scene: str, time_limit: float,
                  path: str | Path) -> Path:
    import matplotlib.pyplot as plt

    groups = _by_planner(results, scene)
    t = np.linspace(0.0, time_limit, 400)
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for name, runs in groups.items():
        solved = np.array(sorted(_time(r) for r in runs if exact(r)))
        frac = np.searchsorted(solved, t, side="right") / max(len(runs), 1)
        ax.step(t, 100 * frac, where="post", label=f"{name} ({len(runs)} runs)")
    ax.set_xlim(0, time_limit)
    ax.set_ylim(-2, 102)
    ax.set_xlabel("time limit (s)")
    ax.set_ylabel("runs solved (%)")
    ax.set_title(f"{printable(scene)}: success against the time limit")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

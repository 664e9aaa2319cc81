"""The rotation shortening's CPU seconds, before/after side by side, and its rotations compared.

``pivot_ompl.checking.rotation_shortcut.shorten`` runs on every transfer phase a plan
converts. For each scene and seed, one fresh worker process per version (``--before DIR``, a
package tree put on ``PYTHONPATH``, then this checkout; the order reversed every other seed,
ABBA, as the second of two back-to-back processes runs slower on a small machine), with an
empty cache folder, plans the scene and records every call of the shortening: its CPU
seconds inside the plan (the sweep checks included) and its arguments. The worker then calls
the shortening again, unstopped, on the recorded phases ``--repeat`` times (the checks'
answers now known: mostly the search over the windows' replacements) and takes the median
pass (a replay that shortens differently is counted: a phase the plan's stop cut short). Prints
per scene and version: phases, rotations before and after the shortening, the plan's CPU
seconds in the shortening, the median replay pass, and whether every version's shortened
rotations are the same floats (a digest of their ``repr``).

    python benchmarks/shortening.py --before ../base [--scenes t_junction,fig10]
        [--seeds 3] [--time 15] [--repeat 5] [--out results/shortening.json]

Run it under ``flock /tmp/pivot-bench.lock`` (or set ``PIVOT_BENCH_LOCK``).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE.parent))

from common import machine_lock, write_json  # noqa: E402


def worker(scene_name: str, seed: int, limit: float, repeat: int) -> None:
    """Plan ``scene_name`` once, record the shortening's calls, replay them; one JSON line."""
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.base import path_conversion
    from pivot_ompl.scene import load_scene

    ou.setLogLevel(ou.LOG_WARN)
    real = path_conversion.shorten
    calls: list[tuple[tuple, dict, Any]] = []
    spent = [0.0]

    def recorded(*args: Any, **kwargs: Any) -> Any:
        t0 = time.process_time()
        out = real(*args, **kwargs)
        spent[0] += time.process_time() - t0
        calls.append((args, kwargs, out))
        return out

    path_conversion.shorten = recorded
    res = plan(load_scene(scene_name), time_limit=limit, seed=seed)
    passes, differ = [], 0
    for _ in range(repeat):  # unstopped: the plan's deadline has passed
        t0 = time.process_time()
        for args, kwargs, out in calls:
            differ += real(*args, **(kwargs | {"should_stop": None})) != out
        passes.append(time.process_time() - t0)
    digest = hashlib.sha256(repr([out for _, _, out in calls]).encode()).hexdigest()[:12]
    row = {"seed": seed, "solved": bool(res.solved), "phases": len(calls),
           "rotations": sum(len(args[2]) for args, _, _ in calls),
           "shortened": sum(len(out) for _, _, out in calls), "plan_cpu": spent[0],
           "replay_cpu": statistics.median(passes) if passes else 0.0, "digest": digest,
           "replays_differing": differ}
    print("ROW " + json.dumps(row), flush=True)


def run(path: Path, scene: str, seed: int, limit: float, repeat: int) -> dict[str, Any]:
    """The row of one fresh worker with the package at ``path`` and an empty cache folder."""
    with tempfile.TemporaryDirectory(prefix="shortening_cache_") as cache:
        env = dict(os.environ, PYTHONPATH=str(path), XDG_CACHE_HOME=cache)
        out = subprocess.run([sys.executable, str(HERE), "--worker", scene, "--seed",
                              str(seed), "--time", str(limit), "--repeat", str(repeat)],
                             env=env, cwd=str(path), text=True, capture_output=True,
                             check=False)
    rows = [json.loads(line[4:]) for line in out.stdout.splitlines() if line.startswith("ROW ")]
    if out.returncode != 0 or len(rows) != 1:
        raise SystemExit(f"{scene} seed {seed} with {path}: worker failed\n{out.stderr[-2000:]}")
    return rows[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to time before this checkout (repeatable)")
    ap.add_argument("--scenes", default="t_junction,fig10")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--time", type=float, default=15.0, help="plan's time limit (s)")
    ap.add_argument("--repeat", type=int, default=5, help="replay passes per plan")
    ap.add_argument("--out", default=None, help="JSON of every row")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--seed", type=int, default=0, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.worker, a.seed, a.time, a.repeat)
        return
    versions = [*a.before, ROOT]
    table: dict[str, dict[str, list[dict[str, Any]]]] = {}
    with machine_lock():
        for scene in a.scenes.split(","):
            by_version = table.setdefault(scene, {str(v): [] for v in versions})
            for seed in range(a.seeds):
                for v in versions if seed % 2 == 0 else versions[::-1]:
                    by_version[str(v)].append(run(v, scene, seed, a.time, a.repeat))
    print(f"{'scene':<12} {'version':<40} {'phases':>6} {'rots':>6} {'short':>6} "
          f"{'plan cpu s':>10} {'replay s':>9}  same")
    for scene, by in table.items():
        digests = {tuple(r["digest"] for r in rows) for rows in by.values()}
        for v, rows in by.items():
            def med(key: str, rows: list[dict[str, Any]] = rows) -> float:
                return statistics.median(r[key] for r in rows)
            print(f"{scene:<12} {v[-40:]:<40} {med('phases'):>6.0f} {med('rotations'):>6.0f} "
                  f"{med('shortened'):>6.0f} {med('plan_cpu'):>10.4f} {med('replay_cpu'):>9.4f}"
                  f"  {'yes' if len(digests) == 1 else 'NO'}")
    if a.out:
        write_json({"args": vars(a) | {"before": [str(p) for p in a.before]}, "rows": table},
                   a.out)


if __name__ == "__main__":
    main()

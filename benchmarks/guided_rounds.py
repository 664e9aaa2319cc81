"""The guided regrasp bound's rounds: CPU seconds and traces, side by side with other versions.

For each scene and each version (``--before DIR``, a package tree put on ``PYTHONPATH``, e.g.
an exported commit; then this checkout), runs
:func:`pivot_ompl.analysis.guided_refine.guided_lower_bound` on the scene's coarse cover (built
before the clock starts, as inside ``plan``) in a fresh interpreter, ``--runs`` times in ABBA
order, each run holding ``$PIVOT_BENCH_LOCK`` when set and with a fresh ``XDG_CACHE_HOME``.
Prints per version the bound, the trace (per round: regrasps, window cells, path nodes), the
median CPU seconds of the call, the ratio to the first version, and the peak resident memory
(MB, of the whole process); ``same`` says whether every run's trace equals the first
version's (the rounds' windows drive the next round: a faster version must keep them).

``--places X,Y;X,Y`` and ``--target N`` are passed on as a plan's regrasp places and count.

Usage::

    PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock python benchmarks/guided_rounds.py \\
        --before /path/to/base --scenes corpus:willow_garage_2010 \\
        --target 2 --places "35.48,34.46;47.08,41.00" --runs 2
    python benchmarks/guided_rounds.py --scenes fig10,door --runs 1
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE.parent))

from common import fmt, median_of  # noqa: E402
from held_proof import scene_path  # noqa: E402


def worker(scene_file: str, target: int | None, places: str) -> None:
    """One guided bound in this interpreter: prints one JSON row."""
    from pivot_ompl.analysis.guided_refine import guided_lower_bound
    from pivot_ompl.analysis.raster_bound import CELL
    from pivot_ompl.analysis.raster_cover import raster_cover
    from pivot_ompl.scene.files import load_scene

    scene = load_scene(scene_file)
    cover = raster_cover(scene, cell=CELL)
    where = tuple(tuple(float(v) for v in p.split(",")) for p in places.split(";") if p)
    trace: list[Any] = []
    t0 = time.process_time()
    got = guided_lower_bound(scene, cover=cover, target=target, trace=trace,
                             places=where)  # type: ignore[arg-type]
    cpu = time.process_time() - t0
    print(json.dumps({
        "bound": None if got is None else got.regrasps,
        "trace": [[r.regrasps, r.window, r.path] for r in trace],
        "cpu": cpu,
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))


def run(version: Path, scene: str, target: int | None, places: str) -> dict[str, Any]:
    """One guided bound in a fresh interpreter with ``version`` first on the path."""
    from common import machine_lock

    cache = tempfile.mkdtemp()
    env = dict(os.environ, PYTHONPATH=str(version), XDG_CACHE_HOME=cache)
    cmd = [sys.executable, str(HERE), "--worker", scene, "--places", places,
           *([] if target is None else ["--target", str(target)])]
    try:
        with machine_lock():
            out = subprocess.run(cmd, env=env, cwd=version, capture_output=True, text=True,
                                 check=False)
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode != 0 or not lines:
        return {"error": f"error {out.returncode}: {out.stderr.strip()[-300:]}"}
    return dict(json.loads(lines[-1]))


def main() -> None:
    """Print one row per scene and version."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to time before this checkout (repeatable)")
    ap.add_argument("--scenes", default="corpus:willow_garage_2010",
                    help="comma-separated scene files, shipped names or corpus:NAME")
    ap.add_argument("--runs", type=int, default=2, help="bounds per scene and version")
    ap.add_argument("--target", type=int, default=None, help="a plan's regrasps")
    ap.add_argument("--places", default="", help="a plan's regrasp places: X,Y;X,Y (m)")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.worker, a.target, a.places)
        return
    versions = [*(v.resolve() for v in a.before), ROOT]
    folder = Path(tempfile.mkdtemp(prefix="guided_rounds_"))
    try:
        print(f"{'scene':22} {'version':28} {'bound':>5} {'cpu s':>7} {'ratio':>6} "
              f"{'peak MB':>8} same  trace")
        for k, spec in enumerate(filter(None, a.scenes.split(","))):
            scene = scene_path(spec, folder, str(k))
            rows: dict[Path, list[dict[str, Any]]] = {v: [] for v in versions}
            for i in range(a.runs):
                for v in versions if i % 2 == 0 else versions[::-1]:
                    rows[v].append(run(v, scene, a.target, a.places))
            first = rows[versions[0]][0].get("trace")
            base_cpu = None
            for v in versions:
                r = rows[v]
                errors = [x["error"] for x in r if "error" in x]
                if errors:
                    print(f"{spec:22} {v.name[:28]:28} {errors[0]}")
                    continue
                cpu = median_of(r, "cpu")
                base_cpu = cpu if base_cpu is None else base_cpu
                ratio = cpu / base_cpu if cpu is not None and base_cpu else None
                same = all(x["trace"] == first for x in r)
                print(f"{spec:22} {v.name[:28]:28} {str(r[0]['bound']):>5} "
                      f"{fmt(cpu, '7.2f')} {fmt(ratio, '6.2f')} "
                      f"{fmt(median_of(r, 'peak_mb'), '8.0f')} {'yes ' if same else 'NO  '} "
                      f"{r[0]['trace']}", flush=True)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()

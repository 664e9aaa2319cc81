"""Side by side: the regrasp planner of this tree against a previous tree, same seeds.

Each run is a fresh process (``python benchmarks/versus.py --worker ...``) importing the
package from ``--baseline`` (a source tree of the previous version, e.g. ``git archive
<merge-base> | tar -x -C /tmp/base``) or from this tree; the two alternate run by run, so
both see the same machine load. Scenes: the given ones plus copies of fig10 rotated and
mirrored (``pivot_ompl.generate``). Prints success, median / p95 wall time and median CPU
time per scene and version, and the ratio of medians. Run under
``flock /tmp/pivot-bench.lock``.

    python benchmarks/versus.py --baseline /tmp/base [--seeds 10] [--time 30]
        [--scenes fig10] [--rotations 37,143] [--mirrors 20] [--planner regrasp]
        [--out results/versus]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
TREE = HERE.parent


def worker(scene: str, planner: str, seed: int, limit: float) -> None:
    from pivot_ompl.api import plan
    from pivot_ompl.scene import load_scene
    from pivot_ompl.validity.plan_check import check_plan

    sc = load_scene(scene)
    c0 = time.process_time()
    r = plan(sc, planner=planner, time_limit=limit, seed=seed)
    cpu = time.process_time() - c0
    ok = r.solved and check_plan(r.plan, sc).ok
    print(json.dumps({"solved": ok, "status": r.status, "time": r.timings["solve"], "cpu": cpu,
                      "regrasps": r.regrasps, "pivots": r.pivots}))


def run(tree: Path, scene: str, planner: str, seed: int, limit: float) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    p = subprocess.run([sys.executable, str(HERE / "versus.py"), "--worker", scene, planner,
                        str(seed), str(limit)], env=env, capture_output=True, text=True,
                       timeout=limit * 3 + 120)
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    if p.returncode != 0 or not lines:
        return {"solved": False, "status": "CRASH", "time": limit, "cpu": math.nan,
                "regrasps": math.nan, "pivots": math.nan}
    return json.loads(lines[-1])


def p95(xs: list[float]) -> float:
    """The 95th percentile by nearest rank (one of the runs' own times)."""
    return float(np.percentile(xs, 95, method="inverted_cdf"))


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        worker(sys.argv[2], sys.argv[3], int(sys.argv[4]), float(sys.argv[5]))
        return
    sys.path.insert(0, str(TREE))
    from common import write_json

    from pivot_ompl.generate import mirror_scene, rotate_scene, write_scene
    from pivot_ompl.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, type=Path)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--scenes", default="fig10")
    ap.add_argument("--rotations", default="37,143", help="degrees, copies of fig10")
    ap.add_argument("--mirrors", default="20", help="axis angles (degrees), copies of fig10")
    ap.add_argument("--planner", default="regrasp")
    ap.add_argument("--out", default="results/versus")
    args = ap.parse_args()
    out = Path(args.out)
    scenes = [s for s in args.scenes.split(",") if s]
    fig10 = load_scene("fig10")
    for a in [float(x) for x in args.rotations.split(",") if x]:
        path = out / f"fig10_rot{a:g}.yaml"
        write_scene(rotate_scene(fig10, math.radians(a), name=path.stem), path)
        scenes.append(str(path))
    for a in [float(x) for x in args.mirrors.split(",") if x]:
        path = out / f"fig10_mirror{a:g}.yaml"
        write_scene(mirror_scene(fig10, math.radians(a), name=path.stem), path)
        scenes.append(str(path))
    versions = {"previous": args.baseline.resolve(), "this": TREE}
    runs: dict[tuple[str, str], list[dict]] = {}
    for scene in scenes:
        for seed in range(args.seeds):
            for name, tree in versions.items():
                r = run(tree, scene, args.planner, seed, args.time)
                runs.setdefault((scene, name), []).append(r)
                print(f"{Path(scene).stem:<18} seed {seed:3d} {name:<9} {r['status']:<15} "
                      f"{r['time']:6.2f} s cpu {r['cpu']:6.2f} s regrasps {r['regrasps']}",
                      flush=True)
    rows = []
    lines = [f"{'scene':<18} {'version':<9} {'success':>8} {'median s':>9} {'p95 s':>7} "
             f"{'cpu med s':>9} {'regrasps':>8}"]
    for (scene, name), rs in runs.items():
        times = [r["time"] if r["solved"] else args.time for r in rs]
        cpus = [r["cpu"] for r in rs if r["solved"]]
        row = {"scene": Path(scene).stem, "version": name, "runs": len(rs),
               "success": sum(r["solved"] for r in rs) / len(rs),
               "median_time": statistics.median(times), "p95_time": p95(times),
               "median_cpu": statistics.median(cpus) if cpus else math.nan,
               "median_regrasps": statistics.median([r["regrasps"] for r in rs if r["solved"]])
               if cpus else math.nan}
        rows.append(row)
        lines.append(f"{row['scene']:<18} {name:<9} {100 * row['success']:7.0f}% "
                     f"{row['median_time']:9.2f} {row['p95_time']:7.2f} "
                     f"{row['median_cpu']:9.2f} {row['median_regrasps']:8.1f}")
    text = "\n".join(lines)
    print(f"\n{args.planner}, {args.seeds} seeds, {args.time:g} s limit\n{text}")
    out.mkdir(parents=True, exist_ok=True)
    (out / "versus_table.txt").write_text(text + "\n")
    write_json({"seeds": args.seeds, "time_limit": args.time, "rows": rows}, out / "versus.json")


if __name__ == "__main__":
    main()

"""Large open floors: ``plan --time T`` wall time and peak memory by floor size.

Writes one hall per size: a square floor of S x S m with ``--boxes`` obstacle boxes
(0.5-2 m a side, any yaw) scattered by a seeded generator clear of the start (near one corner)
and the goal (near the opposite one), so no regrasp is needed. Then, for each hall, runs
``pivot-ompl plan HALL --time T`` in a fresh process under ``/usr/bin/time`` and prints the
floor size, status, wall seconds, peak resident memory (the plan's process and its prover
process together: ``common.TreeMemory``) and the plan's regrasps.

    python benchmarks/halls.py [--sizes 50,100,200] [--boxes 60] [--time 10] [--seed 0]
        [--folder results/halls] [--python OTHER_VENV/bin/python]

Run it under ``flock /tmp/pivot-bench.lock`` (one planning process at a time).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import TreeMemory  # noqa: E402

#: Clear radius (m) round the start and the goal.
CLEAR = 4.0


def hall(size: float, boxes: int, seed: int) -> dict:
    """The scene document of an S x S m hall with ``boxes`` scattered obstacle boxes."""
    rng = np.random.default_rng(seed)
    start, goal = (3.0, 3.0, 0.0), (size - 3.0, size - 3.0, 0.0)
    obstacles = []
    while len(obstacles) < boxes:
        x, y = rng.uniform(1.0, size - 1.0, 2)
        if min(math.dist((x, y), start[:2]), math.dist((x, y), goal[:2])) < CLEAR:
            continue
        obstacles.append({"type": "box", "center": [round(float(x), 3), round(float(y), 3)],
                          "size": [round(float(v), 3) for v in rng.uniform(0.5, 2.0, 2)],
                          "yaw": round(float(rng.uniform(-math.pi, math.pi)), 4),
                          "height": 1.5})
    return {"name": f"hall_{size:g}m", "bounds": [0.0, 0.0, float(size), float(size)],
            "object": {"size": [0.8, 0.6, 1.3]}, "start": list(start), "goal": list(goal),
            "obstacles": obstacles}


def run(scene: Path, limit: float, seed: int, python: str = sys.executable) -> dict:
    """``pivot-ompl plan`` in a fresh process under ``/usr/bin/time``: the figures."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "plan.json"
        cmd = ["/usr/bin/time", "-f", "TIME %e s %M KB", python, "-m", "pivot_ompl",
               "plan", str(scene), "--time", str(limit), "--seed", str(seed), "--out",
               str(out)]
        # run from elsewhere: ``-m`` would import the package of the working folder first
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, cwd=tmp)
        memory = TreeMemory(proc.pid)  # the plan and its prover together
        stdout, stderr = proc.communicate()
        together = memory.stop()
        m = re.search(r"TIME ([\d.]+) s (\d+) KB", stderr)
        regrasps = None
        if out.exists():
            regrasps = sum(1 for ph in json.loads(out.read_text())["phases"]
                           if ph.get("type") == "transit")
        status = (stdout.split(":")[0] if stdout else "?").strip()
        return {"status": status, "seconds": float(m.group(1)) if m else math.nan,
                "peak_mb": max(int(m.group(2)) / 1024 if m else math.nan, together),
                "regrasps": regrasps}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="50,100,200")
    ap.add_argument("--boxes", type=int, default=60)
    ap.add_argument("--time", type=float, default=10.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--folder", default="results/halls")
    ap.add_argument("--python", default=sys.executable,
                    help="the Python whose pivot_ompl to run (e.g. another checkout's venv)")
    args = ap.parse_args(argv)
    folder = Path(args.folder)
    folder.mkdir(parents=True, exist_ok=True)
    print("| floor | status | wall s | peak MB | regrasps |\n|---|---|---|---|---|")
    for size in (float(s) for s in args.sizes.split(",")):
        path = folder / f"hall_{size:g}m.yaml"
        path.write_text(yaml.safe_dump(hall(size, args.boxes, args.seed), sort_keys=False))
        r = run(path.resolve(), args.time, args.seed, args.python)
        print(f"| {size:g} x {size:g} m | {r['status']} | {r['seconds']:.1f} | "
              f"{r['peak_mb']:.0f} | {r['regrasps']} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Benchmark of the RS-to-pivot conversion (issue: steering).

1000 seeded random start/goal pairs 0.1-6 m apart (paper box, grasp 0: l = 0.3 m, turning
radius 2 m, alpha_max = pi/8). Prints median and p95 time per conversion and rotations per
metre of Reeds-Shepp path, and writes them as JSON. Targets on the CI machine kind:
median <= 0.5 ms per conversion, <= 15 rotations per metre.

    python benchmarks/steering.py [--pairs 1000] [--seed 0] [--out results/steering.json]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from common import write_json

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="results/steering.json")
    args = ap.parse_args()
    model = BoxGraspModel((0.8, 0.6, 1.3))
    st = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    ell = model.edge_half_length(0)
    rng = np.random.default_rng(args.seed)
    pairs = []
    for _ in range(args.pairs):
        d, th = rng.uniform(0.1, 6.0), rng.uniform(-math.pi, math.pi)
        a = (0.0, 0.0, rng.uniform(-math.pi, math.pi))
        pairs.append((a, (d * math.cos(th), d * math.sin(th), rng.uniform(-math.pi, math.pi))))
    for a, b in pairs[:50]:  # warm-up
        st.convert(a, b, half_length=ell)
    times, rots, length = [], 0, 0.0
    for a, b in pairs:
        t0 = time.perf_counter()
        seq = st.convert(a, b, half_length=ell)
        times.append(time.perf_counter() - t0)
        rots += len(seq.rotations)
        length += seq.rs_length
    t = np.array(times) * 1e3
    res = {"pairs": args.pairs, "seed": args.seed, "median_ms": float(np.median(t)),
           "p95_ms": float(np.percentile(t, 95)), "rotations_per_m": rots / length,
           "targets": {"median_ms": 0.5, "rotations_per_m": 15.0}}
    print(f"RS-to-pivot conversion over {args.pairs} pairs 0.1-6 m apart")
    print(f"  median {res['median_ms']:.3f} ms   p95 {res['p95_ms']:.3f} ms   "
          "(target median <= 0.5 ms)")
    print(f"  {res['rotations_per_m']:.2f} rotations per metre of RS path   (target <= 15)")
    write_json(res, args.out)


if __name__ == "__main__":
    main()

"""Benchmark of the RS-to-pivot conversion (issue: steering).

1000 seeded random start/goal pairs 0.1-6 m apart (paper box, grasp 0: l = 0.3 m, turning
radius 2 m, alpha_max = pi/8). Prints median and p95 time per conversion and rotations per
metre of Reeds-Shepp path; rotations per metre of 8 m straight pushes for l = 0.2 and 0.4 m
beside the ideal alternating rate ``1 / (2 l sin(alpha/2))``; and, for 300 tiny moves
(1e-5..1e-3 m), the largest distance of the car to the Reeds-Shepp path over the path's
length (small-time property). Writes them as JSON. Targets on the CI machine kind:
median <= 0.5 ms per conversion, <= 15 rotations per metre, straight pushes within 5 % of
the ideal rate.

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
    push = {}
    for half in (0.2, 0.4):
        n = 0
        for h in (0.0, 0.7, -2.0):
            b = (8.0 * math.cos(h), 8.0 * math.sin(h), h)
            n += len(st.convert((0.0, 0.0, h), b, half_length=half).rotations)
        push[half] = (n / 24.0, 1.0 / (2 * half * math.sin(st.alpha_max / 2)))
    worst = 0.0
    for _ in range(300):
        mag, th = 10 ** rng.uniform(-5, -3), rng.uniform(-math.pi, math.pi)
        a = (1.0, -2.0, 0.4)
        b = (1.0 + mag * math.cos(th), -2.0 + mag * math.sin(th), 0.4 + rng.uniform(-1, 1) * mag)
        seq = st.convert(a, b, half_length=ell)
        pts = np.array([p[:2] for p in st.paths.sample(a, b, [i / 399 for i in range(400)])])
        dev = max((float(np.min(np.hypot(pts[:, 0] - r.car[0], pts[:, 1] - r.car[1])))
                   for r in seq.rotations), default=0.0)
        worst = max(worst, dev / seq.rs_length)
    res = {"pairs": args.pairs, "seed": args.seed, "median_ms": float(np.median(t)),
           "p95_ms": float(np.percentile(t, 95)), "rotations_per_m": rots / length,
           "straight_push_per_m": {str(k): v[0] for k, v in push.items()},
           "ideal_per_m": {str(k): v[1] for k, v in push.items()},
           "tiny_move_max_deviation_over_rs_length": worst,
           "targets": {"median_ms": 0.5, "rotations_per_m": 15.0}}
    print(f"RS-to-pivot conversion over {args.pairs} pairs 0.1-6 m apart")
    print(f"  median {res['median_ms']:.3f} ms   p95 {res['p95_ms']:.3f} ms   "
          "(target median <= 0.5 ms)")
    print(f"  {res['rotations_per_m']:.2f} rotations per metre of RS path   (target <= 15)")
    for k, (got, ideal) in push.items():
        print(f"  straight 8 m push, l = {k} m: {got:.2f} rotations per metre "
              f"(ideal {ideal:.2f}, {100 * (got / ideal - 1):+.1f} %)")
    print(f"  tiny moves 1e-5..1e-3 m: car at most {worst:.3g} RS lengths from the RS path")
    write_json(res, args.out)


if __name__ == "__main__":
    main()

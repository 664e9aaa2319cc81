"""Benchmark of state and motion checks on scenes/fig10.yaml (issue: space and validators).

Median over seeded random states (state checks/s) and random short motions, same grasp
(motion checks/s, cache off), and the fraction of motion-check time spent inside coal.

    python benchmarks/validation.py [--n 2000] [--seed 0] [--out results/validation.json]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from common import write_json
from ompl import util as ou

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import load_scene
from pivot_ompl.validity.collision import CollisionWorld


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="fig10")
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="results/validation.json")
    args = ap.parse_args()
    ou.setLogLevel(ou.LogLevel.LOG_ERROR)
    scene = load_scene(args.scene)
    ck = PivotChecker(scene)
    rng = np.random.default_rng(args.seed)
    b = scene.bounds

    def rand_pose():
        return (rng.uniform(b[0], b[2]), rng.uniform(b[1], b[3]), rng.uniform(-math.pi, math.pi))

    states = [(rand_pose(), int(rng.integers(4))) for _ in range(args.n)]
    t0 = time.perf_counter()
    for q, g in states:
        ck.state_valid(q, g)
    state_rate = args.n / (time.perf_counter() - t0)
    # motions between valid states 0.5-2 m apart
    motions = []
    while len(motions) < args.n // 4:
        q, g = rand_pose(), int(rng.integers(4))
        if not ck.state_valid(q, g):
            continue
        d, th = rng.uniform(0.5, 2.0), rng.uniform(-math.pi, math.pi)
        q2 = (q[0] + d * math.cos(th), q[1] + d * math.sin(th), q[2] + rng.normal(0, 0.5))
        if ck.state_valid(q2, g):
            motions.append((q, q2, g))
    # time coal by wrapping the world's query
    coal_time = [0.0]
    orig = CollisionWorld._distance

    def timed(self, *args):  # the query's own arguments, whatever they are
        t = time.perf_counter()
        try:
            return orig(self, *args)
        finally:
            coal_time[0] += time.perf_counter() - t

    CollisionWorld._distance = timed
    per, valid = [], 0
    t0 = time.perf_counter()
    for q, q2, g in motions:
        t = time.perf_counter()
        m = ck.model  # uncached: the transfer check itself
        valid += ck.transfers.check(m.car_pose(q, g), m.car_pose(q2, g), g, with_robot=True,
                                    should_stop=None).valid
        per.append(time.perf_counter() - t)
    total = time.perf_counter() - t0
    CollisionWorld._distance = orig
    res = {"scene": scene.name, "state_checks_per_s": state_rate,
           "motion_checks_per_s": len(motions) / total,
           "motion_check_median_ms": float(np.median(per) * 1e3),
           "motion_valid_fraction": valid / len(motions),
           "coal_fraction": coal_time[0] / total}
    print(f"{scene.name}: {state_rate:,.0f} state checks/s; "
          f"{res['motion_checks_per_s']:.0f} motion checks/s "
          f"(median {res['motion_check_median_ms']:.2f} ms, "
          f"{100 * res['motion_valid_fraction']:.0f} % valid); "
          f"{100 * res['coal_fraction']:.0f} % of motion-check time in coal queries")
    write_json(res, args.out)


if __name__ == "__main__":
    main()

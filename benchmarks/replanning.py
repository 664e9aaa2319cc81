"""Replanning in a warm session against a fresh plan, side by side in one process.

Along the plan of each scene (``--scenes``: fig10, slot, a generated walls scene), at
``--points`` points of its execution (pivot steps spread over its transfers): the box drifted
(5 cm and 5 deg, then 15 cm and 15 deg), an obstacle dropped on the route ahead (a 0.3 m
block 1 m further along), an obstacle removed (the scene's last). For each event: the replan
of a :class:`pivot_ompl.session.PlanningSession` that planned the scene (its roadmaps and
checked motions kept) and that of a fresh session on the same changed scene, one after the
other (both start with the grasp the robot holds): success, seconds, regrasps and pivots of
both. Prints one row per event kind and scene (medians) and the ratio of the medians.

    python benchmarks/replanning.py [--scenes fig10,slot,gen:walls:1] [--points 10] [--time 30]
        [--out results/replanning.json]

Run timing figures under ``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()


def _points(plan: Any, n: int) -> list[tuple[tuple[float, float, float], int]]:
    from pivot_ompl.planfile import TransferPhase

    steps = [(st.object, ph.grasp) for ph in plan.phases if isinstance(ph, TransferPhase)
             for st in ph.steps]
    if not steps:
        return []
    return [steps[int(k * (len(steps) - 1) / max(1, n - 1))] for k in range(n)]


def _events(q: tuple[float, float, float]) -> dict[str, dict[str, Any]]:
    x, y, t = q
    c, s = math.cos(t), math.sin(t)
    return {
        "drift 5cm/5deg": {"box": (x + 0.05 * c, y + 0.05 * s, t + math.radians(5))},
        "drift 15cm/15deg": {"box": (x + 0.15 * c, y + 0.15 * s, t + math.radians(15))},
        "obstacle dropped": {"box": q, "add_obstacles": [{
            "type": "box", "center": [x + 1.0 * c, y + 1.0 * s], "size": [0.3, 0.3],
            "yaw": 0.0, "height": 1.0}]},
        "obstacle removed": {"box": q, "remove": True},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default="fig10,slot,gen:walls:1")
    ap.add_argument("--points", type=int, default=10)
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--out", default="results/replanning.json")
    args = ap.parse_args()
    sys.path[:0] = [str(HERE.parent)]
    from common import scene_from_spec, write_json
    from ompl import util as ou

    from pivot_ompl.errors import PlanningError
    from pivot_ompl.session import PlanningSession

    ou.setLogLevel(ou.LOG_ERROR)
    rows: list[dict[str, Any]] = []
    for name in args.scenes.split(","):
        base = scene_from_spec(name)
        first = PlanningSession(base, seed=0).plan(time_limit=args.time)
        if not first.solved:
            print(f"{name}: no first plan")
            continue
        for q, grasp in _points(first.plan, args.points):
            for kind, ev in _events(q).items():
                session = PlanningSession(base, seed=0)
                session.plan(time_limit=args.time)  # the session that executes the plan
                kw: dict[str, Any] = {"box": ev["box"], "grasp": grasp,
                                      "add_obstacles": ev.get("add_obstacles", ())}
                if ev.get("remove"):
                    kw["remove_obstacles"] = [len(base.obstacles) - 1]
                row: dict[str, Any] = {"scene": name, "event": kind}
                try:
                    t0 = time.perf_counter()
                    warm = session.replan(time_limit=args.time, **kw)
                    row.update(warm_s=time.perf_counter() - t0, warm_ok=warm.solved,
                               warm_regrasps=warm.regrasps, warm_pivots=warm.pivots)
                    t0 = time.perf_counter()
                    cold = PlanningSession(session.scene, seed=0).replan(
                        box=ev["box"], grasp=grasp, time_limit=args.time)
                    row.update(fresh_s=time.perf_counter() - t0, fresh_ok=cold.solved,
                               fresh_regrasps=cold.regrasps, fresh_pivots=cold.pivots)
                except PlanningError as e:  # the observed pose collides
                    row.update(error=str(e)[:80])
                rows.append(row)
                print(f"{name:10s} {kind:18s} " + (
                    f"warm {row['warm_s']:.2f} s ({row['warm_ok']}) fresh {row['fresh_s']:.2f} s"
                    f" ({row['fresh_ok']})" if "error" not in row else row["error"]), flush=True)
    print()
    table = {}
    keys = sorted({(r["scene"], r["event"]) for r in rows})
    for sc, ev in keys:
        rs = [r for r in rows if r["scene"] == sc and r["event"] == ev and "error" not in r]
        if not rs:
            continue
        w = statistics.median(r["warm_s"] for r in rs)
        f = statistics.median(r["fresh_s"] for r in rs)
        t = {"runs": len(rs), "warm_ok": sum(r["warm_ok"] for r in rs),
             "fresh_ok": sum(r["fresh_ok"] for r in rs), "warm_median_s": w,
             "fresh_median_s": f, "ratio": w / f if f > 0 else math.nan,
             "warm_regrasps": statistics.median(r["warm_regrasps"] for r in rs),
             "fresh_regrasps": statistics.median(r["fresh_regrasps"] for r in rs)}
        table[f"{sc}/{ev}"] = t
        print(f"{sc:10s} {ev:18s} runs {len(rs):2d}  warm {w:5.2f} s ({t['warm_ok']} ok)  "
              f"fresh {f:5.2f} s ({t['fresh_ok']} ok)  ratio {t['ratio']:.2f}  regrasps "
              f"{t['warm_regrasps']:.0f} vs {t['fresh_regrasps']:.0f}")
    write_json({"time_limit": args.time, "rows": rows, "table": table}, args.out)


if __name__ == "__main__":
    main()

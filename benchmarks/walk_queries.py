"""Walk micro-benchmark: the transit queries a regrasp planner run asks, replayed.

``--record`` runs the regrasp planner on a scene and on rotated / mirrored copies of it
(``pivot_ompl.generate.rotate_scene`` / ``mirror_scene``), seeds ``0 .. runs-1``, and writes
every ``WalkPlanner.plan_between`` query (start, goal, box pose) of each run, with its answer
(valid, length, cost, expansions), to a JSON file. The default mode replays them: one fresh
``PivotChecker`` per (scene copy, seed), its queries in their order (so the per-run caches
fill as in the planner run), and prints total and median CPU time (``process_time``),
expansions, walk length totals, and each answer's validity against the recorded one (a
change of validity is listed: a walk found where none was, or lost).

    python benchmarks/walk_queries.py --record [--scene fig10] [--runs 10]
        [--copies rot37,mir20] [--queries results/walk_queries.json]
    python benchmarks/walk_queries.py [--queries results/walk_queries.json] [--repeat 1]
        [--out results/walk_bench.json] [--set field_after=1000 ...]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from pathlib import Path

from common import write_json

import pivot_ompl
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import mirror_scene, rotate_scene
from pivot_ompl.scene import Scene, load_scene
from pivot_ompl.transit import planner as walking


def scene_copy(name: str, copy: str) -> Scene:
    """Scene ``name`` as is (``copy`` ``""``), rotated (``rot<deg>``) or mirrored (``mir<deg>``)."""
    scene = load_scene(name)
    if not copy:
        return scene
    deg = math.radians(float(copy[3:]))
    return rotate_scene(scene, deg) if copy.startswith("rot") else mirror_scene(scene, deg)


def record(name: str, runs: int, copies: list[str], out: Path) -> None:
    """Plan each copy and seed, recording the walk queries."""
    groups: list[dict] = []
    current: list[dict] = []
    orig = walking.WalkPlanner.plan_between

    def spy(self: walking.WalkPlanner, start, goal, obj, **kw):  # noqa: ANN001, ANN202
        e0 = self.expansions
        r = orig(self, start, goal, obj, **kw)
        current.append({"start": list(start), "goal": list(goal), "obj": list(obj),
                        "valid": r.valid, "length": r.length, "cost": r.cost,
                        "expansions": self.expansions - e0})
        return r

    walking.WalkPlanner.plan_between = spy  # type: ignore[method-assign]
    try:
        for copy in ["", *copies]:
            scene = scene_copy(name, copy)
            for seed in range(runs):
                current = []
                res = pivot_ompl.plan(scene, planner="regrasp", time_limit=30.0, seed=seed)
                print(f"{name}{copy and ' ' + copy} seed {seed}: {res.status}, "
                      f"{len(current)} walk queries", flush=True)
                groups.append({"scene": name, "copy": copy, "seed": seed, "queries": current})
    finally:
        walking.WalkPlanner.plan_between = orig  # type: ignore[method-assign]
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"groups": groups}, default=float))
    print(f"written {out}")


def replay(path: Path, settings: dict[str, float] | None = None) -> dict:
    """Replay the recorded queries once; figures and validity changes.

    ``settings``: walk planner attributes to set (e.g. ``{"inflation": 2.0}``).
    """
    groups = json.loads(path.read_text())["groups"]
    scenes: dict[tuple[str, str], Scene] = {}
    times, changed = [], []
    expansions, length_old, length_new, n_valid = 0, 0.0, 0.0, 0
    cost_old, cost_new = 0.0, 0.0
    group_cpu = []
    per_copy: dict[str, list[float]] = {}
    for g in groups:
        key = (g["scene"], g["copy"])
        if key not in scenes:
            scenes[key] = scene_copy(*key)
        ck = PivotChecker(scenes[key])
        w = ck.walker
        for k, v in (settings or {}).items():
            setattr(w, k, type(getattr(w, k))(v))
        t_group = 0.0
        for i, q in enumerate(g["queries"]):
            t0 = time.process_time()
            r = w.plan_between(tuple(q["start"]), tuple(q["goal"]), tuple(q["obj"]))
            dt = time.process_time() - t0
            times.append(dt)
            t_group += dt
            if r.valid != q["valid"]:
                changed.append({"scene": key, "seed": g["seed"], "query": i,
                                "was": q["valid"], "now": r.valid})
            elif r.valid:
                n_valid += 1
                length_old += q["length"]
                length_new += r.length
                cost_old += q["cost"]
                cost_new += r.cost
        expansions += w.expansions
        group_cpu.append(t_group)
        per_copy.setdefault(g["copy"] or g["scene"], []).append(t_group)
    return {"queries": len(times), "cpu_total_s": sum(times),
            "cpu_median_ms": 1e3 * statistics.median(times),
            "cpu_max_ms": 1e3 * max(times), "run_cpu_median_s": statistics.median(group_cpu),
            "run_cpu_median_s_per_copy": {k: statistics.median(v) for k, v in per_copy.items()},
            "expansions": expansions, "valid_both": n_valid,
            "length_recorded_m": length_old, "length_now_m": length_new,
            "cost_recorded_m": cost_old, "cost_now_m": cost_new,
            "validity_changed": changed}


def main() -> None:
    """Command line (see the module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--record", action="store_true")
    ap.add_argument("--scene", default="fig10")
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--copies", default="rot37,mir20")
    ap.add_argument("--queries", default="results/walk_queries.json")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--out", default="results/walk_bench.json")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a walk planner attribute for the replay, e.g. inflation=2")
    a = ap.parse_args()
    if a.record:
        record(a.scene, a.runs, [c for c in a.copies.split(",") if c], Path(a.queries))
        return
    settings = {k: float(v) for k, v in (kv.split("=", 1) for kv in a.set)}
    results = []
    for k in range(a.repeat):
        res = replay(Path(a.queries), settings)
        results.append(res)
        print(f"replay {k}: {res['queries']} queries, CPU total {res['cpu_total_s']:.3f} s, "
              f"median {res['cpu_median_ms']:.1f} ms, max {res['cpu_max_ms']:.0f} ms, "
              f"per run median {res['run_cpu_median_s']:.3f} s, "
              f"expansions {res['expansions']}, walk length {res['length_now_m']:.2f} m "
              f"(recorded {res['length_recorded_m']:.2f} m over {res['valid_both']} walks), "
              f"cost {res['cost_now_m']:.2f} m (recorded {res['cost_recorded_m']:.2f} m), "
              f"validity changed: {len(res['validity_changed'])}", flush=True)
        print("  per run median CPU (s):", {k: round(v, 3) for k, v in
                                             res["run_cpu_median_s_per_copy"].items()})
        for c in res["validity_changed"]:
            print("  changed:", c)
    write_json({"replays": results,
                "cpu_total_median_s": statistics.median(r["cpu_total_s"] for r in results)},
               a.out)


if __name__ == "__main__":
    main()

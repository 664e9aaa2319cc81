"""Rooms in a row joined for the robot by a corridor 1-3 cm wider than its walking body.

The ``building`` family's ``corridor`` layout (``pivot_ompl.generate``): every wall between
rooms a box-only slot, the robot's way round a corridor ``--width`` wide (default 0.87-0.89
m; the walking body is 0.86 x 0.60 m) behind doors ``--door`` wide (default 1.0 m), turned
by a random angle unless ``--no-rotate``. For each rooms count and seed: plan with
``pivot_ompl.api.plan`` (seed = the scene's seed, ``--time`` limit, the regrasp bound within
it) and check the plan. Prints one row per run, then per rooms count: solved over seeds,
median seconds (``plan``'s whole call), median seconds per room, median regrasps and the
lower bound. Each row also gives the call's CPU seconds and its ``solve`` and ``bound``
timings (the search, and the quality block's lower bounds), so a change is placed in the
phase it moved. ``--cpu``: the medians are of CPU seconds (less disturbed by a loaded
machine). Target (issue 41): 8, 16 and 32 rooms solved, the 32 rooms' median at most 8 x
the 4 rooms', and at most 10 s.

    python benchmarks/corridors.py [--rooms 4,8,16,32] [--seeds 3] [--time 60]
        [--width 0.87,0.89] [--door 1.0,1.0] [--no-rotate] [--save DIR | --scenes DIR]
        [--cpu] [--out results/corridors.json]

``--save DIR`` writes the scenes; ``--scenes DIR`` plans those instead of generating them
(so another version of the package plans the same floors). Run timing figures under
``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()


def _ints(text: str) -> list[int]:
    return [int(v) for v in text.split(",") if v]


def _pair(text: str) -> tuple[float, float]:
    lo, hi = (float(v) for v in text.split(","))
    return lo, hi


def _scenes(args: argparse.Namespace) -> list[tuple[int, int, Any]]:
    """``(rooms, seed, scene)`` for every run."""
    from pivot_ompl.scene import load_scene

    out = []
    for n in _ints(args.rooms):
        for seed in range(args.seeds):
            name = f"corridor{n}_{seed}.yaml"
            if args.scenes:
                out.append((n, seed, load_scene(str(Path(args.scenes) / name))))
                continue
            from pivot_ompl.generate import GeneratorParams, generate
            from pivot_ompl.generate.sceneio import write_scene

            gen = generate("building", seed, params=GeneratorParams(
                rooms=n, layout="corridor", rotate=not args.no_rotate,
                side_corridor=_pair(args.width), side_door=_pair(args.door)))
            if args.save:
                write_scene(gen.scene, Path(args.save) / name)
            out.append((n, seed, gen.scene))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rooms", default="4,8,16,32")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--time", type=float, default=60.0)
    ap.add_argument("--width", default="0.87,0.89", help="corridor widths MIN,MAX (m)")
    ap.add_argument("--door", default="1.0,1.0", help="door widths MIN,MAX (m)")
    ap.add_argument("--no-rotate", action="store_true", help="keep the layout's axes")
    ap.add_argument("--save", default=None, help="write the scenes to this folder")
    ap.add_argument("--scenes", default=None, help="plan the scenes of this folder")
    ap.add_argument("--cpu", action="store_true", help="medians of CPU seconds")
    ap.add_argument("--out", default="results/corridors.json")
    args = ap.parse_args()
    sys.path[:0] = [str(HERE.parent)]
    from common import machine_lock, write_json
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.validity.plan_check import check_plan

    ou.setLogLevel(ou.LOG_WARN)
    rows = []
    print(f"{'rooms':>5} {'seed':>4} {'solved':>6} {'check':>5} {'seconds':>8} {'s/room':>7} "
          f"{'cpu':>7} {'solve':>7} {'bound s':>7} {'regr':>4} {'bound':>5}")
    measure = "cpu" if args.cpu else "seconds"
    for n, seed, scene in _scenes(args):
        with machine_lock():
            t0, c0 = time.perf_counter(), time.process_time()
            res = plan(scene, time_limit=args.time, seed=seed)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        ok = res.solved and check_plan(res.plan, scene).ok
        q = res.plan.extra.get("quality", {}) if res.solved else {}
        row = {"rooms": n, "seed": seed, "solved": res.solved, "checked": ok, "seconds": wall,
               "cpu": cpu, "solve": res.timings.get("solve"),
               "bound_seconds": res.timings.get("bound"), "regrasps": q.get("regrasps"),
               "bound": q.get("regrasps_lower_bound")}
        rows.append(row)
        print(f"{n:5d} {seed:4d} {str(res.solved):>6} {str(ok):>5} {wall:8.2f} {wall / n:7.3f} "
              f"{cpu:7.2f} {row['solve'] or 0.0:7.2f} {row['bound_seconds'] or 0.0:7.2f} "
              f"{str(row['regrasps']):>4} {str(row['bound']):>5}", flush=True)
    print()
    table: dict[str, Any] = {}
    for n in _ints(args.rooms):
        rs = [r for r in rows if r["rooms"] == n]
        ok = [r for r in rs if r["checked"]]
        med = statistics.median(r[measure] if r["checked"] else args.time for r in rs)
        regr = [r["regrasps"] for r in ok]
        table[str(n)] = {"runs": len(rs), "solved": len(ok), "median_s": med, "measure": measure,
                         "per_room_s": med / n,
                         "regrasps": statistics.median(regr) if regr else None,
                         "bounds": [r["bound"] for r in ok]}
        print(f"{n:3d} rooms: solved {len(ok)}/{len(rs)}, median {med:.2f} s ({measure}), "
              f"{med / n:.3f} s a room, regrasps {table[str(n)]['regrasps']} "
              f"(bounds {table[str(n)]['bounds']})")
    first, last = _ints(args.rooms)[0], _ints(args.rooms)[-1]
    if str(first) in table and str(last) in table and table[str(first)]["median_s"] > 0:
        ratio = table[str(last)]["median_s"] / table[str(first)]["median_s"]
        print(f"{last} rooms / {first} rooms median: {ratio:.2f} x (rooms {last / first:g} x)")
    write_json({"time_limit": args.time, "rows": rows, "table": table}, args.out)


if __name__ == "__main__":
    main()

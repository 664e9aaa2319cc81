"""How planning time grows with tight passages and with the size of the floor.

Generated scenes, one planning process (this one), one run at a time:

* ``building``: N rooms in a row (``--rooms 1,2,4,8,16``), box-only slots and robot-only doors
  or wide doors between them (``pivot_ompl.generate`` family ``building``);
* ``slots``: two walls whose slots leave C a side (``--clearances 0.10,0.06,0.04,0.03``;
  the generator's ``walls`` family with ``walls=2, slot_clearance=C``);
* ``doors``: ``--door-rooms`` rooms in a row (default 6), every wall a door robot and box pass
  together, W wide and off the wall's middle (``--doors 0.95,1.1,1.3``; ``building`` with
  ``wide_doors=(W, W)``): doors narrower than the disk the held assembly sweeps turning.

For each scene and seed: solved or not within ``--time``, solve seconds, regrasps and the
proven lower bound (``--no-bound``: not computed), and the floor's area. Prints one row per
run, then success, median and 95th percentile per class; ``--plot`` draws solve time against
rooms, against slot clearance and against door width (median line, p95 dashed, unsolved runs
at the limit).
Targets (issue: scaling): time close to linear in the rooms; slots of 2-6 cm a side solved.

    python benchmarks/scaling.py [--rooms 1,2,4,8] [--clearances 0.1,0.06,0.04]
        [--doors 0.95,1.1,1.3] [--door-rooms 6] [--seeds 2] [--time 180] [--no-bound]
        [--out results/scaling.json]
        [--plot results/scaling.png]

Run timing figures under ``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()


def _scenes(args: argparse.Namespace) -> list[tuple[str, str, Any]]:
    from pivot_ompl.generate import GeneratorParams, generate

    out = []
    for n in [int(v) for v in args.rooms.split(",") if v]:
        for seed in range(args.seeds):
            gen = generate("building", seed, params=GeneratorParams(rooms=n))
            out.append(("building", f"rooms={n}", gen.scene))
    for w in [float(v) for v in args.doors.split(",") if v]:
        for seed in range(args.seeds):
            gen = generate("building", seed, params=GeneratorParams(rooms=args.door_rooms,
                                                                    wide_doors=(w, w)))
            out.append(("doors", f"width={w:g}", gen.scene))
    for c in [float(v) for v in args.clearances.split(",") if v]:
        for seed in range(args.seeds):
            try:
                gen = generate("walls", seed, params=GeneratorParams(walls=2, slot_clearance=c))
            except Exception as e:  # noqa: BLE001 - a layout the generator cannot make
                print(f"slots clearance={c} seed {seed}: not generated ({e})")
                continue
            out.append(("slots", f"clearance={c:g}", gen.scene))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rooms", default="1,2,4,8")
    ap.add_argument("--clearances", default="0.1,0.06,0.04,0.03")
    ap.add_argument("--doors", default="", help="door widths (m) of the doors class")
    ap.add_argument("--door-rooms", type=int, default=6)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--time", type=float, default=180.0)
    ap.add_argument("--no-bound", action="store_true", help="skip the lower bounds")
    ap.add_argument("--out", default="results/scaling.json")
    ap.add_argument("--plot", default=None, help="write the figure here (PNG)")
    args = ap.parse_args()
    sys.path[:0] = [str(HERE.parent)]
    from common import write_json
    from ompl import util as ou

    from pivot_ompl.analysis.bound_cache import lower_bound
    from pivot_ompl.api import plan

    ou.setLogLevel(ou.LOG_WARN)
    rows = []
    print(f"{'class':9s} {'param':16s} {'scene':24s} {'area m2':>8} {'solved':>6} {'solve s':>8} "
          f"{'regr':>4} {'bound':>5} {'bound s':>7}")
    for cls, param, scene in _scenes(args):
        t0 = time.perf_counter()
        b_regrasps = None if args.no_bound else lower_bound(scene, use_cache=False).regrasps
        bound_s = time.perf_counter() - t0
        res = plan(scene, time_limit=args.time, seed=0, bound=False)
        x0, y0, x1, y1 = scene.bounds
        row = {"class": cls, "param": param, "scene": scene.name, "area": (x1 - x0) * (y1 - y0),
               "solved": res.solved, "solve": res.timings["solve"],
               "regrasps": res.regrasps if res.solved else None, "bound": b_regrasps,
               "bound_s": bound_s}
        rows.append(row)
        print(f"{cls:9s} {param:16s} {scene.name:24s} {row['area']:8.0f} "
              f"{str(res.solved):>6} {row['solve']:8.2f} {str(row['regrasps']):>4} "
              f"{str(b_regrasps):>5} {bound_s:7.2f}", flush=True)
    print()
    groups: dict[tuple[str, str], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["class"], r["param"]), []).append(r)
    table = {}
    for (cls, param), rs in groups.items():
        ok = [r for r in rs if r["solved"]]
        times = [r["solve"] if r["solved"] else args.time for r in rs]
        med, p95 = statistics.median(times), _percentile(times, 95.0)
        table[f"{cls}/{param}"] = {"runs": len(rs), "solved": len(ok), "solve_median": med,
                                   "solve_p95": p95,
                                   "at_bound": sum(r["regrasps"] == r["bound"] for r in ok)}
        print(f"{cls:9s} {param:16s} solved {len(ok)}/{len(rs)}, median solve {med:.2f} s, "
              f"p95 {p95:.2f} s, at the bound {table[f'{cls}/{param}']['at_bound']}/{len(ok)}")
    write_json({"time_limit": args.time, "rows": rows, "table": table}, args.out)
    if args.plot:
        _plot(table, args.plot, args.time)


def _percentile(values: list[float], q: float) -> float:
    """The ``q``-th percentile (linear interpolation between the closest ranks)."""
    v = sorted(values)
    k = (len(v) - 1) * q / 100.0
    lo = int(k)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (k - lo)


def _plot(table: dict[str, dict[str, Any]], path: str, limit: float) -> None:
    """Solve time against rooms, slot clearance and door width: median and p95 per class."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for ax, cls, label in ((axes[0], "building", "rooms in a row"),
                           (axes[1], "slots", "slot clearance a side (m)"),
                           (axes[2], "doors", "door width (m), every wall")):
        pts = sorted((float(k.split("=")[1]), v) for k, v in table.items()
                     if k.startswith(cls + "/"))
        if not pts:
            ax.set_visible(False)
            continue
        xs = [x for x, _ in pts]
        ax.plot(xs, [v["solve_median"] for _, v in pts], "o-", label="median")
        ax.plot(xs, [v["solve_p95"] for _, v in pts], "s--", label="p95")
        for x, v in pts:
            ax.annotate(f"{v['solved']}/{v['runs']}", (x, v["solve_p95"]), fontsize=7,
                        textcoords="offset points", xytext=(0, 4), ha="center")
        ax.axhline(limit, color="grey", lw=0.8, ls=":", label="time limit")
        ax.set_xlabel(label)
        ax.set_ylabel("solve time (s)")
        if cls == "building":
            ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.legend(fontsize=8)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()

"""Plan on real building maps: the corpus of ROS map_server maps, N seeds each.

Every map of :data:`CORPUS` (public maps: AWS RoboMaker worlds, TurtleBot3, Nav2, the Willow
Garage office, a home-robotics lab; provenance and licence in each map's ``PROVENANCE.md``)
is imported with ``pivot_ompl.import_map`` at its start and goal, then planned by
``pivot-ompl plan`` in a fresh process per seed (``--time``, default 60 s). Per map the
Markdown table gives: the floor area and its boxes, runs solved, the median wall time of a
run (the whole ``plan`` command: import of the scene, bound, search, conversion), the
regrasps against the proven bound the plan carries (``regrasps_lower_bound``; "-" when the
bound was not proven within ``plan``'s share of the limit), the median route ratio (route
length over the proven shortest route) and the peak memory of a run (the plan's process and
its prover process together, sampled from ``/proc``: ``common.TreeMemory``; at least the
``ru_maxrss`` of ``os.wait4``).

Usage::

    python benchmarks/buildings.py                      # 20 seeds, --time 60
    python benchmarks/buildings.py --seeds 3 --maps aws_small_house,nav2_depot
    python benchmarks/buildings.py --table results/buildings/buildings.json
    python benchmarks/buildings.py --seeds 2 --turn 0.5 --mirror   # rigid copies of the maps

``--turn RAD`` plans on each map's scene turned by ``RAD`` about its bounds' centre
(``pivot_ompl.generate.rotate_scene``: the old bounds become walls round the turned floor);
``--mirror`` on its mirror image across the horizontal line through that centre
(``mirror_scene``), before any turn. A rigid copy has the same plans as the map itself, so
its table should match the map's.

Set ``PIVOT_BENCH_LOCK`` to a file (``/tmp/pivot-bench.lock``) to hold it (``flock``) during
each planning run, so that two measuring scripts never share the cores. Outputs go to
``--out`` (default ``results/buildings``): the scenes, the plans, ``buildings.json`` and
``buildings.md``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import TreeMemory, machine_lock  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HALF_PI = 0.5 * math.pi


@dataclass(frozen=True)
class CorpusMap:
    """A map of the corpus and the task planned on it.

    Attributes:
        name: the scene's name.
        map: the map's YAML file, relative to the repository.
        kind: what the map shows.
        start, goal: the box's poses in the map frame (m, rad).
        clean: ``MapCleaning`` fields (m², m), none by default.
        note: what is known of the task's feasibility beyond the bound plans carry (printed
            under the table).
        feasible: a plan exists (``False``: proven that none does, the note says how).
    """

    name: str
    map: str
    kind: str
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    clean: dict[str, float] = field(default_factory=dict)
    note: str = ""
    feasible: bool = True


CORPUS = (
    CorpusMap("aws_small_house", "scenes/maps/aws_small_house/map.yaml",
              "house (simulated, SLAM map)", (-6.0, -3.0, 0.0), (7.0, -1.0, HALF_PI)),
    CorpusMap("aws_bookstore", "scenes/maps/aws_bookstore/map.yaml",
              "bookstore (simulated, SLAM map)", (-2.3, 5.4, 0.0), (2.6, -3.1, HALF_PI)),
    CorpusMap("aws_small_warehouse", "scenes/maps/aws_small_warehouse/map.yaml",
              "small warehouse (simulated, SLAM map)", (-4.5, -7.8, HALF_PI), (0.6, 6.4, 0.0)),
    CorpusMap("turtlebot3_world", "benchmarks/maps/turtlebot3_world/map.yaml",
              "TurtleBot3 arena (simulated, SLAM map)", (0.0, -1.9, 0.0), (0.0, 1.9, 0.0),
              note="no plan exists: the held poses' relaxation "
              "(pivot_ompl.analysis.pose_proof, about 1.4 s of CPU) separates start and "
              "goal; `plan` runs it in its prover beside the search from the start "
              "(pivot_ompl.analysis.prover; every way passes a gap narrower than the held "
              "assembly: no gate), --time 60: INFEASIBLE in 3.9 s on a quiet 2-core machine "
              "(one process, --no-parallel: from 4 % of --time, 4.9-5.1 s)",
              feasible=False),
    CorpusMap("nav2_depot", "benchmarks/maps/nav2_depot/depot.yaml",
              "depot (simulated, SLAM map)", (-4.0, 0.0, 0.0), (20.0, 0.0, 0.0)),
    CorpusMap("nav2_warehouse", "benchmarks/maps/nav2_warehouse/warehouse.yaml",
              "warehouse (simulated, SLAM map)", (-12.0, -20.0, HALF_PI), (0.0, 22.0, 0.0)),
    CorpusMap("aws_hospital", "benchmarks/maps/aws_hospital/hospital.yaml",
              "hospital (simulated, floor plan of its walls)", (-29.0, 5.05, 0.0),
              (8.0, 0.05, HALF_PI)),
    CorpusMap("willow_garage_2010",
              "benchmarks/maps/willow_garage_2010/willow-2010-02-18-0.10.yaml",
              "office (real robot's SLAM map)", (17.4, 16.4, 0.0), (49.0, 40.4, HALF_PI),
              {"specks": 0.02},
              note="start and goal lie in different components of the held assembly's "
              "lattice (pushes and turns in place) at every grasp: every plan regrasps; the "
              "coarse raster bound gives 0 (doors a few cm narrower than the held assembly, "
              "below its raster's cell); the first plan on a cold bound cache refines it to "
              "2 (the guided bound, about 10 s of CPU, in the plan's prover beside the "
              "search; `--no-prove`: not) and later plans read it"),
    CorpusMap("brsu_c069", "benchmarks/maps/brsu_c069/map.yaml",
              "home-robotics lab (real robot's SLAM map)", (3.7, 6.2, 0.0), (3.2, 0.9, 0.0),
              {"specks": 0.02},
              note="no plan exists: the rooms' only joint is the inner door, 0.85 m "
              "between its jambs (x 2.55-3.40, y 3.55-3.95), the held assembly needs 0.88 m, "
              "and the robot alone cannot walk past the box resting in the door (0.45 m "
              "beside it at most); the held poses' relaxation, its regrasps walked round the "
              "box, proves it and names the door (56 bins, 2.3 s of CPU: `pivot-ompl bound "
              "--held-poses`); `plan` runs it in its prover beside the search from the "
              "start: INFEASIBLE in 9.9-10.4 s at --time 60, 10.8 s at --time 30 (one "
              "process, --no-parallel: where half its estimate, 19 s, fits between 4 and "
              "25 % of --time: 11.7-11.9 s at --time 60, TIMEOUT at --time 30)",
              feasible=False),
    CorpusMap("brsu_c069_room", "benchmarks/maps/brsu_c069/map.yaml",
              "home-robotics lab (real robot's SLAM map)", (4.2, 3.0, 0.0),
              (1.5, -2.8, HALF_PI), {"specks": 0.02},
              note="both poses in the lower room, round its furniture: every plan "
              "regrasps once, as the bound proves it must (the plans' regrasp, forced, names "
              "the passage at about (1.14, 0.31))"),
)


def import_corpus_map(m: CorpusMap, out: Path, *, turn: float = 0.0,
                     mirror: bool = False) -> dict[str, Any]:
    """Import ``m`` as ``out/<name>.yaml``; its size and boxes (those of the map's floor).

    ``mirror``: the scene mirrored across the horizontal line through its bounds' centre;
    ``turn``: then turned by that angle (rad) about that centre (the file named after it).
    """
    from pivot_ompl import MapCleaning, import_map
    from pivot_ompl.generate import mirror_scene, rotate_scene
    from pivot_ompl.generate.sceneio import write_scene

    result = import_map(ROOT / m.map, start=m.start, goal=m.goal, name=m.name,
                        cleaning=MapCleaning(**m.clean))
    scene, name = result.scene, m.name
    if mirror:
        name = f"{name}_mirror"
        scene = mirror_scene(scene, 0.0, name=name)
    if turn:
        name = f"{name}_turn{turn:g}"
        scene = rotate_scene(scene, turn, name=name)
    path = write_scene(scene, out / f"{name}.yaml", comment=result.header)
    b = result.scene.bounds
    return {"scene": str(path), "width": b[2] - b[0], "depth": b[3] - b[1],
            "boxes": len(result.scene.obstacles), "resolution": result.map.resolution}


def plan_once(scene: str, seed: int, limit: float, out: Path, *,
              prove: bool = False, fresh: bool = False,
              parallel: bool | None = None) -> dict[str, Any]:
    """One ``pivot-ompl plan`` in a fresh process: exit code, wall and CPU time, peak memory, plan.

    ``parallel``: ``plan --parallel`` / ``--no-parallel`` (``None``: ``plan``'s default).
    ``prove``: ``plan --prove`` (the guided bound refined inside the plan whatever its
    estimate; by default ``plan`` refines it where the estimate fits the limit).
    ``fresh``: the plan's own empty cache folder (``XDG_CACHE_HOME``; no bound cached by
    an earlier plan).
    """
    plan_path = out / f"{Path(scene).stem}.seed{seed}.json"
    plan_path.unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "pivot_ompl.cli", "plan", scene, "--time", str(limit),
           "--seed", str(seed), "--out", str(plan_path)] + (["--prove"] if prove else []) \
        + ([] if parallel is None else ["--parallel" if parallel else "--no-parallel"])
    env = dict(os.environ)
    with machine_lock(), tempfile.TemporaryDirectory() as cache:
        if fresh:
            env["XDG_CACHE_HOME"] = cache
        t0 = time.perf_counter()
        with tempfile.TemporaryFile("w+") as stdout:  # a file: wait4 reaps the process
            proc = subprocess.Popen(cmd, stdout=stdout, stderr=subprocess.PIPE, text=True,
                                    env=env)
            memory = TreeMemory(proc.pid)
            assert proc.stderr is not None
            err = proc.stderr.read()
            _, status, usage = os.wait4(proc.pid, 0)
            together = memory.stop()
            stdout.seek(0)
            out_text = stdout.read()
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
    run: dict[str, Any] = {"seed": seed, "code": proc.returncode, "wall": wall,
                           "cpu": usage.ru_utime + usage.ru_stime,
                           "peak_mb": max(usage.ru_maxrss / 1024.0, together),
                           "outcome": outcome(proc.returncode, out_text),
                           "message": err.replace("\r", "\n").strip().splitlines()[-1:]}
    if proc.returncode == 0 and plan_path.exists():
        doc = json.loads(plan_path.read_text())
        q = doc.get("quality", {})
        run.update(solved=doc.get("status") == "exact", regrasps=q.get("regrasps"),
                   bound=q.get("regrasps_lower_bound"), route_ratio=q.get("route_ratio"),
                   solve=doc.get("timings", {}).get("solve"))
    else:
        run["solved"] = False
    return run


def outcome(code: int, stdout: str) -> str:
    """What a run ended in: ``solved``, ``infeasible`` (proven, exit 1), ``timeout`` (exit 1
    without a reason) or ``error`` (any other exit), read from ``plan``'s exit code and the
    status word that starts its first line."""
    first = stdout.strip().split(":", 1)[0] if stdout.strip() else ""
    if code == 0:
        return "solved"
    if code == 1:
        return "infeasible" if first == "INFEASIBLE" else "timeout"
    return "error"


def _others(runs: list[dict[str, Any]]) -> str:
    """The unsolved runs by outcome with their median wall time, ``-`` if none."""
    parts = []
    for kind in ("infeasible", "timeout", "error"):
        walls = [r["wall"] for r in runs if r.get("outcome") == kind]
        if walls:
            parts.append(f"{len(walls)} {kind} ({_fmt(_median(walls))} s)")
    return ", ".join(parts) or "-"


def _median(xs: list[float]) -> float | None:
    return statistics.median(xs) if xs else None


def _fmt(x: float | None, spec: str = ".1f") -> str:
    return "-" if x is None else format(x, spec)


def summary_row(m: CorpusMap, info: dict[str, Any], runs: list[dict[str, Any]]) -> str:
    """One Markdown row of the table."""
    ok = [r for r in runs if r["solved"]]
    grasps = [r["regrasps"] for r in ok if r.get("regrasps") is not None]
    bounds = [r for r in ok if r.get("bound") is not None]
    at_bound = sum(r["regrasps"] == r["bound"] for r in bounds)
    bound_text = (f"{at_bound}/{len(bounds)} at bound {min(r['bound'] for r in bounds)}"
                  if bounds else f"- (0/{len(ok)} carry one)")
    ratios = [r["route_ratio"] for r in ok if r.get("route_ratio") is not None]
    return (f"| {m.name} | {m.kind} | {info['width']:.1f} x {info['depth']:.1f} "
            f"({info['resolution']:g}) | {info['boxes']} | {len(ok)}/{len(runs)} | "
            f"{_fmt(_median([r['wall'] for r in ok]))} | "
            f"{_fmt(_median([r['solve'] for r in ok if r.get('solve') is not None]))} | "
            f"{_fmt(_median([float(g) for g in grasps]), '.0f')} | {bound_text} | "
            f"{_fmt(_median(ratios), '.2f')} | "
            f"{max(r['peak_mb'] for r in runs):.0f} | {_others(runs)} |")


HEADER = ("| map | kind | floor m (m/px) | boxes | solved | median time s | median solve s "
          "| median regrasps | regrasps = bound | median route ratio | peak memory MB "
          "| not solved (median time) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|")


def table(record: dict[str, Any], command: str) -> str:
    """The Markdown table of a run's record (``buildings.json``'s ``maps``)."""
    by_name = {m.name: m for m in CORPUS}
    rows = [summary_row(by_name[name], info, info["runs"]) for name, info in record.items()
            if name in by_name]
    notes = "".join(f"\n- {name}: {by_name[name].note}" for name in record
                    if name in by_name and by_name[name].note)
    return (f"{HEADER}\n" + "\n".join(rows) + f"\n\n`{command}`; {os.cpu_count()} cores; "
            "time: the whole `pivot-ompl plan` process (start-up, the bound's share, search, "
            "writing); solve: the search alone.\n" + (f"\nKnown of the tasks:{notes}\n"
                                                      if notes else ""))


def main() -> None:
    """Run the corpus and print the table."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=20, help="seeds 0..N-1 per map (default 20)")
    p.add_argument("--time", type=float, default=60.0, help="plan's --time (s; default 60)")
    p.add_argument("--maps", help="comma-separated names (default: the whole corpus)")
    p.add_argument("--out", default=str(ROOT / "results" / "buildings"), help="output folder")
    p.add_argument("--prove", action="store_true",
                   help="plan with --prove (the bound refined inside the plan whatever its "
                        "estimate; by default plan refines it where the estimate fits)")
    p.add_argument("--no-parallel", action="store_true",
                   help="plan with --no-parallel (the proofs in the plan's own process)")
    p.add_argument("--fresh", action="store_true",
                   help="each plan with its own empty cache folder (a first plan: no bound "
                        "cached by an earlier seed)")
    p.add_argument("--turn", type=float, default=0.0, metavar="RAD",
                   help="plan on each scene turned by RAD (rad) about its bounds' centre")
    p.add_argument("--mirror", action="store_true",
                   help="plan on each scene mirrored across its centre's horizontal line "
                        "(before --turn)")
    p.add_argument("--table", metavar="JSON", help="only print the table of a run's "
                   "buildings.json")
    args = p.parse_args()
    if args.table:
        doc = json.loads(Path(args.table).read_text())
        print(table(doc["maps"], f"python benchmarks/buildings.py --seeds {doc['seeds']} "
                    f"--time {doc['time']:g}"))
        return
    names = {m.name for m in CORPUS}
    chosen = CORPUS if not args.maps else tuple(m for m in CORPUS
                                                 if m.name in args.maps.split(","))
    unknown = set(args.maps.split(",")) - names if args.maps else set()
    if unknown:
        raise SystemExit(f"--maps: unknown {sorted(unknown)} (known: {sorted(names)})")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    record = {}
    for m in chosen:
        info = import_corpus_map(m, out, turn=args.turn, mirror=args.mirror)
        runs = []
        for seed in range(args.seeds):
            run = plan_once(info["scene"], seed, args.time, out, prove=args.prove,
                            parallel=False if args.no_parallel else None,
                            fresh=args.fresh)
            runs.append(run)
            print(f"{m.name} seed {seed}: {run['outcome']} (code {run['code']}), "
                  f"{run['wall']:.1f} s ({run['cpu']:.1f} s CPU), "
                  f"{run.get('regrasps')} regrasps (bound {run.get('bound')}), "
                  f"{run['peak_mb']:.0f} MB", file=sys.stderr, flush=True)
        record[m.name] = {"map": m.map, "start": m.start, "goal": m.goal, "clean": m.clean,
                          **info, "runs": runs}
    command = (f"python benchmarks/buildings.py --seeds {args.seeds} --time {args.time:g}"
               + (f" --maps {args.maps}" if args.maps else "")
               + (" --prove" if args.prove else "") + (" --fresh" if args.fresh else "")
               + (" --no-parallel" if args.no_parallel else "")
               + (f" --turn {args.turn:g}" if args.turn else "")
               + (" --mirror" if args.mirror else ""))
    text = table(record, command)
    (out / "buildings.md").write_text(text)
    (out / "buildings.json").write_text(json.dumps(
        {"seeds": args.seeds, "time": args.time, "maps": record}, indent=1) + "\n")
    print(text)


if __name__ == "__main__":
    main()

"""Solve time before/after on the shipped scenes: CPU seconds of ``plan`` side by side.

For each scene and each version (``--before DIR``, a package tree put on ``PYTHONPATH``, e.g.
an export of an older commit, repeatable; then this checkout), a fresh interpreter plans the
scene once as a warm-up (imports, caches, the scene's lower bounds) and then over seeds
``0 .. N-1``, timing each ``plan(scene, time_limit=T, seed=s)`` with ``time.process_time``
(CPU seconds of the process, so other load on the machine counts less than in wall time).
Scenes and versions take turns (one process at a time). Prints per scene and version the
median CPU seconds, the ratio to the first version, the median plan cost (s, the cost model's
``plan_cost``), pivots and regrasps (so a faster plan that is worse shows), and the medians of
the seconds spent in the re-routing (``refine``) and in ``follow_route`` where the version
has them; ``first s``: the CPU seconds of the warm-up plan, the first of its process (what
one plan of the command line costs beyond the imports; the lower bounds may come from the
disk cache). Target (issue 42): every shipped scene <= 1.2x the first version.

With ``--first``, every plan is the first of a fresh interpreter instead: for each seed
``0 .. N-1`` and each version in turn (the order reversed every other seed: ABBA, since on
a small machine the second of two back-to-back processes ran slower), a new process with a
new, empty cache folder (``XDG_CACHE_HOME``: nothing served from an earlier run) imports the
API and plans once.
Prints per scene and version the medians of that plan's CPU seconds (``cpu s``, lazy imports
inside ``plan`` included) and its ratio to the first version, the CPU seconds of the regrasp
search with its improvement (``search``: the core of ``solve``) and their ratio, the CPU
seconds of the late proof inside that search (``proof``: the relaxation the search asks
while it has no path, from a share of the time limit on the clock, so that a quieter machine
reaches it sooner and pays it more often; ``-`` for a version without it), the plan's
``solve`` and lower bounds' (``bound``) wall seconds, the whole process's CPU seconds
(``proc s``: the interpreter, the imports and the plan; what one ``pivot-ompl plan`` costs),
cost, pivots and regrasps.

Each worker process holds ``$PIVOT_BENCH_LOCK`` (``flock``) while it runs, when that is set:
one timing process on the machine at a time, the lock free between them (set it, or run the
whole script under ``flock`` of the same file, not both: the script would wait for itself).

    PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock python benchmarks/solve_time.py \
        --before /tmp/base [--seeds 5] [--time 15] [--first]
        [--scenes fig10,slot,door,...] [--out results/solve_time.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE.parent))

from common import cpu_timed, fmt, machine_lock, median_of  # noqa: E402

#: the shipped scenes (``scenes/``) and public layouts (``benchmarks/layouts``) timed
SCENES = ("fig10", "slot", "door", "t_junction", "open", "open_fig7", "corridor",
          "cluttered_room", "hall", "bugtrap")


def worker(scene_name: str, seeds: int, limit: float) -> None:
    """Plan ``scene_name`` (warm-up, then seeds 0..seeds-1); one JSON line per seed."""
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.scene import load_scene

    ou.setLogLevel(ou.LOG_WARN)
    layout = HERE.parent / "layouts" / f"{scene_name}.yaml"
    scene = load_scene(layout if layout.is_file() else scene_name)
    bucket: dict[str, float] = {}
    try:
        from pivot_ompl.planners import improve
        cpu_timed(improve, "refine", bucket)
        cpu_timed(improve, "follow_route", bucket)
    except ImportError:  # an older version without the stage
        pass
    t0 = time.process_time()
    plan(scene, time_limit=limit, seed=0)  # warm-up: the first plan of the process
    print("FIRST " + json.dumps({"cpu": time.process_time() - t0}), flush=True)
    for seed in range(seeds):
        bucket.clear()
        t0 = time.process_time()
        res = plan(scene, time_limit=limit, seed=seed)
        cpu = time.process_time() - t0
        row: dict[str, Any] = {"seed": seed, "cpu": cpu, "solved": bool(res.solved),
                               "refine": bucket.get("refine"),
                               "follow": bucket.get("follow_route")}
        if res.solved:
            q = (res.plan.extra.get("quality") or {})
            row.update(pivots=res.plan.pivots, regrasps=res.plan.regrasps, cost=q.get("cost"))
        print("ROW " + json.dumps(row), flush=True)


def first_worker(scene_name: str, seed: int, limit: float) -> None:
    """Plan ``scene_name`` once with ``seed``, the first plan of this process; one JSON line."""
    from ompl import util as ou

    from pivot_ompl.api import plan
    from pivot_ompl.scene import load_scene

    ou.setLogLevel(ou.LOG_WARN)
    layout = HERE.parent / "layouts" / f"{scene_name}.yaml"
    bucket: dict[str, float] = {}
    try:  # the regrasp search with its improvement, in CPU seconds (every version has it)
        from pivot_ompl.planners.regrasp_search import RegraspSearch
        cpu_timed(RegraspSearch, "run", bucket)
    except ImportError:
        pass
    try:  # the late proof, polled by the search while it has no path (newer versions)
        from pivot_ompl.analysis.late_proof import LateProof
        cpu_timed(LateProof, "__call__", bucket, "proof")
    except ImportError:
        pass
    t0 = time.process_time()
    scene = load_scene(layout if layout.is_file() else scene_name)
    res = plan(scene, time_limit=limit, seed=seed)
    cpu = time.process_time() - t0
    row: dict[str, Any] = {"seed": seed, "cpu": cpu, "solved": bool(res.solved),
                           "search": bucket.get("run"), "proof": bucket.get("proof"),
                           "solve": res.timings.get("solve"),
                           "bound": res.timings.get("bound"), "proc": time.process_time()}
    if res.solved:
        q = (res.plan.extra.get("quality") or {})
        row.update(pivots=res.plan.pivots, regrasps=res.plan.regrasps, cost=q.get("cost"))
    print("ROW " + json.dumps(row), flush=True)


def run_first(path: Path, scene: str, seed: int, limit: float) -> dict[str, Any]:
    """The row of one fresh worker, with an empty cache folder, planning ``scene`` once."""
    with tempfile.TemporaryDirectory(prefix="solve_time_cache_") as cache, machine_lock():
        env = dict(os.environ, PYTHONPATH=str(path), XDG_CACHE_HOME=cache)
        out = subprocess.run([sys.executable, str(HERE), "--first-worker", scene, "--seed",
                              str(seed), "--time", str(limit)], env=env, cwd=str(path),
                             text=True, capture_output=True, check=False)
    rows = [json.loads(line[4:]) for line in out.stdout.splitlines() if line.startswith("ROW ")]
    if out.returncode != 0 or len(rows) != 1:
        raise SystemExit(f"{scene} seed {seed} with {path}: worker failed\n{out.stderr[-2000:]}")
    return rows[0]


def run(path: Path, scene: str, seeds: int, limit: float) -> list[dict[str, Any]]:
    """Rows of one fresh worker with the package at ``path`` (the first row's ``first``: the
    warm-up plan's CPU seconds)."""
    env = dict(os.environ, PYTHONPATH=str(path))
    with machine_lock():
        out = subprocess.run([sys.executable, str(HERE), "--worker", scene, "--seeds",
                              str(seeds), "--time", str(limit)], env=env, cwd=str(path),
                             text=True, capture_output=True, check=False)
    rows = [json.loads(line[4:]) for line in out.stdout.splitlines() if line.startswith("ROW ")]
    first = [json.loads(line[6:]) for line in out.stdout.splitlines() if line.startswith("FIRST ")]
    if out.returncode != 0 or len(rows) != seeds or not first:
        raise SystemExit(f"{scene} with {path}: worker failed\n{out.stderr[-2000:]}")
    rows[0]["first"] = first[0]["cpu"]
    return rows


def _ratio(x: float | None, first: float | None) -> float | None:
    return x / first if x is not None and first else None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to time before this checkout (repeatable)")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--time", type=float, default=15.0, help="plan's time limit (s)")
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--out", default=None, help="JSON of every row")
    ap.add_argument("--first", action="store_true",
                    help="time the first plan of a fresh process per seed (empty cache)")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--first-worker", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--seed", type=int, default=0, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.worker, a.seeds, a.time)
        return
    if a.first_worker:
        first_worker(a.first_worker, a.seed, a.time)
        return
    versions = [*a.before, ROOT]
    table: dict[str, dict[str, list[dict[str, Any]]]] = {}
    if a.first:
        _first_table(versions, a, table)
    else:
        _warm_table(versions, a, table)
    if a.out:
        out = Path(a.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = out.with_suffix(".tmp")
        tmp.write_text(json.dumps(table, indent=1) + "\n")
        tmp.replace(out)
        print(f"written {out}")


def _first_table(versions: list[Path], a: argparse.Namespace,
                 table: dict[str, dict[str, list[dict[str, Any]]]]) -> None:
    """First plans of fresh processes, versions taking turns per seed (``--first``)."""
    print(f"{'scene':15} {'version':28} {'cpu s':>7} {'ratio':>6} {'search':>7} {'ratio':>6} "
          f"{'proof':>6} {'solve':>7} {'bound':>7} {'proc s':>7} {'cost':>8} {'piv':>5} {'rg':>3}")
    for scene in filter(None, a.scenes.split(",")):
        rows: dict[str, list[dict[str, Any]]] = {str(v): [] for v in versions}
        for seed in range(a.seeds):  # the order reversed every other seed: on a small
            for v in versions if seed % 2 == 0 else versions[::-1]:  # machine the second of
                rows[str(v)].append(run_first(v, scene, seed, a.time))  # two runs is slower
        table[scene] = rows
        base: dict[str, float | None] = {}
        for v in versions:
            r = rows[str(v)]
            cpu, search = median_of(r, "cpu"), median_of(r, "search")
            base.setdefault("cpu", cpu)
            base.setdefault("search", search)
            print(f"{scene:15} {str(v)[-28:]:28} {fmt(cpu, '7.3f')} "
                  f"{fmt(_ratio(cpu, base['cpu']), '6.2f')} {fmt(search, '7.3f')} "
                  f"{fmt(_ratio(search, base['search']), '6.2f')} "
                  f"{fmt(median_of(r, 'proof'), '6.3f')} {fmt(median_of(r, 'solve'), '7.3f')} "
                  f"{fmt(median_of(r, 'bound'), '7.3f')} "
                  f"{fmt(median_of(r, 'proc'), '7.3f')} {fmt(median_of(r, 'cost'), '8.1f')} "
                  f"{fmt(median_of(r, 'pivots'), '5.0f')} {fmt(median_of(r, 'regrasps'), '3.0f')}",
                  flush=True)


def _warm_table(versions: list[Path], a: argparse.Namespace,
                table: dict[str, dict[str, list[dict[str, Any]]]]) -> None:
    """A warm-up plan, then seeds, in one process per scene and version."""
    print(f"{'scene':15} {'version':28} {'cpu s':>7} {'ratio':>6} {'cost':>8} {'piv':>5} "
          f"{'rg':>3} {'reroute':>7} {'follow':>7} {'first s':>7}")
    for scene in filter(None, a.scenes.split(",")):
        table[scene] = {}
        first: float | None = None
        for v in versions:
            rows = run(v, scene, a.seeds, a.time)
            table[scene][str(v)] = rows
            cpu = median_of(rows, "cpu")
            first = cpu if first is None else first
            ratio = cpu / first if cpu is not None and first else None
            m = {k: median_of(rows, k) for k in ("cost", "pivots", "regrasps", "refine", "follow")}
            print(f"{scene:15} {str(v)[-28:]:28} {fmt(cpu, '7.3f')} {fmt(ratio, '6.2f')} "
                  f"{fmt(m['cost'], '8.1f')} {fmt(m['pivots'], '5.0f')} "
                  f"{fmt(m['regrasps'], '3.0f')} {fmt(m['refine'], '7.3f')} "
                  f"{fmt(m['follow'], '7.3f')} {fmt(rows[0].get('first'), '7.3f')}",
                  flush=True)


if __name__ == "__main__":
    main()

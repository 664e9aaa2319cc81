"""The held poses' proof (``prove_no_plan``) side by side: answer, bins and CPU seconds.

For each scene and each version (``--before DIR``, a package tree put on ``PYTHONPATH``, e.g.
an export of an older commit, repeatable; then this checkout), a fresh interpreter loads the
scene and runs :func:`pivot_ompl.analysis.pose_proof.prove_no_plan` once, ``--runs`` times;
the versions take turns, the order reversed every other run (ABBA: on a small machine the
second of two back-to-back processes ran slower), each run holding ``$PIVOT_BENCH_LOCK``
when it is set. Prints per scene and version the answer (``apart``: proven, ``joined``: the
finest bins join start and goal, ``-``: nothing), the last round's bins, the rounds, the
bins whose regions were computed, and the medians of the proof's CPU seconds (``cpu s``),
of those spent in the bins' regions (``regions``), in GEOS unions (``unions``, all of the
proof's), in the chain search (``chain``) and in the regrasp walks (``walks``); ``ratio`` is
``cpu s`` over the first version's. ``--both`` times what the late proof's held try runs:
the gate, then the proof where the gate did not join (``joined``: the gate joined). ``--gate``
times the proof's gate instead,
:func:`pivot_ompl.analysis.pose_inner.joined_at_every_yaw` (answer ``joined``: held poses
valid at every yaw join start and goal, ``no``: they do not, ``-``: stopped or out of
searches; its 32 bins, no rounds).

A scene is a scene file, a shipped scene's name or a generated scene's spec
(``common.scene_from_spec``: ``gen:FAMILY:SEED[:NAME=VALUE...]``), or ``corpus:NAME``, a map of
``buildings.py``'s corpus. Every version reads the same file: a name, a spec or a corpus map is
made once, by this checkout, into a temporary folder (``common.scene_file``; a generated
scene depends on the checks of the version that makes it).

    PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock python benchmarks/held_proof.py \\
        --before /path/to/base --scenes corpus:brsu_c069,corpus:turtlebot3_world [--runs 2]
        [--gate] [--out results/held_proof.json]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE.parent))

from common import cpu_timed, fmt, median_of  # noqa: E402

#: what each run's figures are summed from: (column, module, function)
STAGES = (("regions", "pivot_ompl.analysis.pose_bins", "BinRegions.regions"),
          ("unions", "pivot_ompl.analysis.pose_bins", "shapely.union_all"),
          ("chain", "pivot_ompl.analysis.pose_proof", "walked_chain"),  # before pose_graph
          ("chain", "pivot_ompl.analysis.pose_graph", "walked_chain"),
          ("chain", "pivot_ompl.analysis.pose_inner", "walked_chain"),  # the gate's
          ("walks", "pivot_ompl.analysis.pose_proof", "HeldParts.may_regrasp"))


def worker(scene_spec: str, gate: bool = False, both: bool = False) -> None:
    """One proof (its gate, or both) of one scene in this process; prints its figures as JSON."""
    import importlib

    sys.path.insert(0, str(HERE.parent))
    from common import scene_from_spec

    bucket: dict[str, float] = {}
    for column, module, attr in STAGES:
        try:
            owner: Any = importlib.import_module(module)
        except ModuleNotFoundError:  # a version without that module
            continue
        *path, name = attr.split(".")
        for part in path:
            owner = getattr(owner, part, None)
        if owner is not None:
            cpu_timed(owner, name, bucket, column)
    proof = importlib.import_module("pivot_ompl.analysis.pose_proof")
    kept: list[Any] = []  # the proof's regions, for the bins computed (not a twin's)
    regions = getattr(proof, "BinRegions", None)
    if regions is not None:
        init = regions.__init__

        def counted(self: Any, *args: Any, **kwargs: Any) -> None:
            init(self, *args, **kwargs)
            kept.append(self)

        regions.__init__ = counted
    scene = scene_from_spec(scene_spec)
    t0 = time.process_time()
    if gate:
        inner = importlib.import_module("pivot_ompl.analysis.pose_inner")
        joined = inner.joined_at_every_yaw(scene)
        cpu = time.process_time() - t0
        row: dict[str, Any] = {"answer": {True: "joined", False: "no", None: "-"}[joined],
                               "bins": proof.FIRST_BINS}
    elif both:  # the late proof's held try: the gate, then the proof where it did not join
        inner = importlib.import_module("pivot_ompl.analysis.pose_inner")
        shared: dict[str, Any] = {}
        try:  # a version whose gate and proof read one floor
            floor = importlib.import_module("pivot_ompl.analysis.pose_floor")
            shared["floor"] = floor.HeldFloor(scene, proof.MOTION_CLEARANCE, None)
        except ModuleNotFoundError:
            pass
        joined = inner.joined_at_every_yaw(scene, **shared)
        res = None if joined else proof.prove_no_plan(scene, **shared)
        cpu = time.process_time() - t0
        row = {"answer": "joined" if res is None else
               {True: "apart", False: "joined", None: "-"}[res.apart],
               "bins": proof.FIRST_BINS if res is None else res.bins,
               "rounds": 0 if res is None else res.rounds}
    else:
        res = proof.prove_no_plan(scene)
        cpu = time.process_time() - t0
        row = {"answer": {True: "apart", False: "joined", None: "-"}[res.apart],
               "bins": res.bins, "rounds": res.rounds,
               "finest_deg": res.finest * 180.0 / 3.141592653589793}
    row.update(cpu=cpu, **bucket, computed=sum(getattr(b, "computed", 0) for b in kept))
    print(json.dumps(row))


def run(version: Path, scene: str, gate: bool = False, both: bool = False) -> dict[str, Any]:
    """One proof (its gate, or both) in a fresh interpreter with ``version`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(version), XDG_CACHE_HOME=tempfile.mkdtemp())
    cmd = [sys.executable, str(HERE), "--worker", scene, *(["--gate"] if gate else []),
           *(["--both"] if both else [])]
    sys.path.insert(0, str(HERE.parent))
    from common import machine_lock

    with machine_lock():
        out = subprocess.run(cmd, env=env, cwd=version, capture_output=True, text=True,
                             check=False)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode != 0 or not lines:
        return {"answer": f"error {out.returncode}: {out.stderr.strip()[-200:]}"}
    return dict(json.loads(lines[-1]))


def scene_path(spec: str, folder: Path, stem: str) -> str:
    """The one scene file of ``spec`` every version reads, made by this checkout.

    ``corpus:NAME`` imported into ``folder`` (its scene file); any other spec as
    :func:`common.scene_file` gives it (a file as is, else ``folder/stem.yaml``).
    """
    sys.path.insert(0, str(HERE.parent))
    from common import scene_file, this_checkout

    this_checkout()
    if not spec.startswith("corpus:"):
        return scene_file(spec, folder, stem)
    from buildings import CORPUS, import_corpus_map

    name = spec.split(":", 1)[1]
    m = next((m for m in CORPUS if m.name == name), None)
    if m is None:
        raise SystemExit(f"{spec}: no such map in buildings.py's corpus")
    return str(import_corpus_map(m, folder)["scene"])


def _print_rows(spec: str, versions: list[Path], rows: dict[str, list[dict[str, Any]]]
                ) -> None:
    """One line per version of ``spec``: the medians of its runs, ``ratio`` the first's."""
    first: float | None = None
    for v in versions:
        r = rows[str(v)]
        cpu = median_of(r, "cpu")
        first = cpu if first is None else first
        ratio = cpu / first if cpu is not None and first else None
        print(f"{spec[-22:]:22} {str(v)[-28:]:28} {r[0]['answer'][:7]:>7} "
              f"{fmt(median_of(r, 'bins'), '5.0f')} {fmt(median_of(r, 'rounds'), '6.0f')} "
              f"{fmt(median_of(r, 'computed'), '8.0f')} {fmt(cpu, '7.2f')} "
              f"{fmt(ratio, '6.2f')} {fmt(median_of(r, 'regions'), '7.2f')} "
              f"{fmt(median_of(r, 'unions'), '7.2f')} {fmt(median_of(r, 'chain'), '6.2f')} "
              f"{fmt(median_of(r, 'walks'), '6.2f')}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to time before this checkout (repeatable)")
    ap.add_argument("--scenes", default="corpus:brsu_c069,corpus:turtlebot3_world")
    ap.add_argument("--runs", type=int, default=1, help="proofs per scene and version")
    ap.add_argument("--gate", action="store_true",
                    help="time the gate (pose_inner.joined_at_every_yaw), not the proof")
    ap.add_argument("--both", action="store_true",
                    help="time the late proof's held try: the gate, then the proof where the "
                         "gate did not join (on one floor where the version shares it)")
    ap.add_argument("--out", default=None, help="JSON of every run")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.worker, a.gate, a.both)
        return
    versions = [*(v.resolve() for v in a.before), ROOT]
    table: dict[str, dict[str, list[dict[str, Any]]]] = {}
    folder = Path(tempfile.mkdtemp(prefix="held_proof_"))
    try:
        print(f"{'scene':22} {'version':28} {'answer':>7} {'bins':>5} {'rounds':>6} "
              f"{'computed':>8} {'cpu s':>7} {'ratio':>6} {'regions':>7} {'unions':>7} "
              f"{'chain':>6} {'walks':>6}")
        for k, spec in enumerate(filter(None, a.scenes.split(","))):
            scene = scene_path(spec, folder, str(k))
            rows: dict[str, list[dict[str, Any]]] = {str(v): [] for v in versions}
            for i in range(a.runs):
                for v in versions if i % 2 == 0 else versions[::-1]:
                    rows[str(v)].append(run(v, scene, a.gate, a.both))
            table[spec] = rows
            _print_rows(spec, versions, rows)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if a.out:
        sys.path.insert(0, str(HERE.parent))
        from common import write_json

        write_json(table, a.out)


if __name__ == "__main__":
    main()

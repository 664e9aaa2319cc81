"""Generality benchmark: our planners and OMPL's on generated scenes and the shipped ones.

Generates ``--per-family`` scenes of each family (``walls``, ``corridor``, ``clutter``; each
with a witness plan, so each is known solvable), adds the shipped scenes, runs
``pivot-ompl bench``'s sweep over them (one planning process at a time: ``--workers 1``) and
prints success and median / p95 time per family and planner. Run timing figures under
``flock /tmp/pivot-bench.lock``.

    python benchmarks/generality.py [--per-family 34] [--time 30] [--runs 1]
                                    [--planners regrasp,rrtconnect] [--out results/generality]
                                    [--overwrite]
"""

from __future__ import annotations

import argparse
from dataclasses import asdict

from common import write_json

from pivot_ompl.bench.executors import LocalExecutor
from pivot_ompl.bench.generality import family_rows, format_rows, generate_suite
from pivot_ompl.bench.sweep import check_out_folder, run_sweep
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.scene import load_scene

SHIPPED = ("fig10", "slot", "corridor", "cluttered_room")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-family", type=int, default=34)
    ap.add_argument("--families", default="walls,corridor,clutter")
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--planners", default="regrasp,rrtconnect")
    ap.add_argument("--shipped", default=",".join(SHIPPED))
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--out", default="results/generality")
    ap.add_argument("--overwrite", action="store_true",
                    help="replace a previous run's outputs in --out")
    args = ap.parse_args()
    out = check_out_folder(args.out, overwrite=args.overwrite)  # before the scenes go in
    suite = generate_suite(args.families.split(","), count=args.per_family, out=out / "scenes")
    scenes = [*suite, *(shipped_scenes()[n] for n in args.shipped.split(",") if n)]
    families = {load_scene(p).name: fam for p, fam in suite.items()}
    for p in scenes[len(suite):]:  # a shipped scene is its own row (fig10, corridor...)
        families[load_scene(p).name] = f"shipped {load_scene(p).name}"
    sweep = run_sweep(scenes, args.planners.split(","), runs=args.runs, time_limit=args.time,
                      out=out, executor=LocalExecutor(args.workers), plots=False,
                      overwrite=True)  # the folder was checked, and holds the scenes now
    rows = family_rows(sweep.results, families, time_limit=args.time)
    text = format_rows(rows)
    print(f"\n{len(suite)} generated + {len(scenes) - len(suite)} shipped scenes, "
          f"{args.runs} run(s) each, {args.time:g} s limit\n{text}")
    (out / "generality_table.txt").write_text(text)
    write_json({"per_family": args.per_family, "time_limit": args.time, "runs": args.runs,
                "rows": [asdict(r) for r in rows]}, out / "generality.json")


if __name__ == "__main__":
    main()

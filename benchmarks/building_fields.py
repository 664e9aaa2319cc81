"""The whole-building fields of a plan on a real map, versions side by side: CPU seconds.

A plan on a building map builds two fields over the whole floor: the walking floor's open
positions, tile by tile (``FloorTiles``: each obstacle piece's uncertified Minkowski sums with
the walking body at 32 yaws, a wall box's at the 16 yaws opposite others reflected,
rasterised; a regrasp walk that goes round the building floods them all), and the held
assembly's field (``AssemblyField``: 32 yaws x 2 grasp parities of uncertified sums,
rasterised). For each version (``--before DIR``, a package tree put on
``PYTHONPATH``, repeatable; then this checkout) a fresh interpreter builds both from the
scene, ``--repeat`` times, versions alternating; the table gives the best CPU seconds
(``time.process_time``: other load on the machine counts less than in wall time) and a
SHA-256 of every raster, so that a faster version shows it computes the same cells.

    python benchmarks/building_fields.py --scene results/buildings/willow_garage_2010.yaml \
        --before /tmp/base [--repeat 3] [--out results/building_fields.json]

The scene: any scene file or shipped scene (``benchmarks/buildings.py`` writes the corpus'
scenes to its ``--out`` folder).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

from common import write_json

ROOT = Path(__file__).resolve().parents[1]

#: What a worker runs: both fields from the scene, timed, and a digest of their rasters.
WORKER = """
import hashlib, json, sys, time
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import load_scene
from pivot_ompl.transit.floor_window import FloorTiles
from pivot_ompl.validity.assembly_field import FIELD_YAWS, AssemblyField
checker = PivotChecker(load_scene(sys.argv[1]), share=False)
grid = checker.walker.field.grid
digest = hashlib.sha256()
t0 = time.process_time()
tiles = FloorTiles(grid)
digest.update(tiles.window(slice(0, grid.nx), slice(0, grid.ny)).tobytes())
t1 = time.process_time()
field = AssemblyField(checker.model, checker.world, 0.1)
for parity in (0, 1):
    for k in range(len(FIELD_YAWS)):
        digest.update(field.fits(parity, k).tobytes())
t2 = time.process_time()
print(json.dumps({"walk_tiles": t1 - t0, "assembly_field": t2 - t1, "tiles": tiles.tiles_built,
                  "pieces": len(grid.pieces), "digest": digest.hexdigest()}))
"""


def run(tree: Path, scene: str) -> dict:
    """One fresh interpreter on ``tree``: both fields' CPU seconds and the rasters' digest."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, "-c", WORKER, scene], env=env, cwd=tree,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    """Time the versions and print the table."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help="scene file or shipped scene's name")
    ap.add_argument("--before", action="append", default=[], type=Path,
                    help="a package tree to time before this checkout (repeatable)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per version (best kept)")
    ap.add_argument("--out", default=None, help="JSON of every run")
    args = ap.parse_args()
    scene = str(Path(args.scene).resolve()) if Path(args.scene).exists() else args.scene
    trees = [*args.before, ROOT]
    runs: dict[str, list[dict]] = {str(t): [] for t in trees}
    for _ in range(args.repeat):
        for tree in trees:
            runs[str(tree)].append(run(tree, scene))
    print("| version | walk tiles CPU s | assembly field CPU s | tiles | rasters' SHA-256 |\n"
          "|---|---|---|---|---|")
    for tree in trees:
        rs = runs[str(tree)]
        print(f"| {tree} | {min(r['walk_tiles'] for r in rs):.2f} | "
              f"{min(r['assembly_field'] for r in rs):.2f} | {rs[0]['tiles']} | "
              f"{rs[0]['digest'][:16]}{'' if len({r['digest'] for r in rs}) == 1 else ' (!)'} |")
    print(f"\n`python benchmarks/building_fields.py --scene {args.scene} "
          + "".join(f"--before {t} " for t in args.before) + f"--repeat {args.repeat}`; "
          f"best of {args.repeat} runs a version, CPU seconds, {os.cpu_count()} cores")
    if args.out:
        write_json({"scene": scene, "runs": runs}, args.out)


if __name__ == "__main__":
    main()

"""The raster regrasp bound refined round its necks, by window, on the buildings corpus.

For each map (imported as ``benchmarks/buildings.py`` does) and each window kind, prints the
coarse raster bound (10 cm cells, bins of 5 cm rotation erosion) and the refined one
(:func:`pivot_ompl.analysis.refined_bound.refined_lower_bound`: 5 cm cells and bins of 1 cm
rotation erosion inside the window), the window's coarse cells and the refinement's seconds.
Window kinds: ``necks`` (:func:`~pivot_ompl.analysis.raster_refine.neck_window`, the
default), ``turns`` (:func:`~pivot_ompl.analysis.raster_refine.turn_neck_window`), ``all``
(every cell: the whole fine relaxation, slow), ``guided``
(:func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound`: windows round the narrow
places the relaxation's best path passes, round after round; "cells refined" is its last
window, and the rounds' counts and seconds follow the bound). ``--target N`` stops the
guided rounds at N regrasps, as inside ``plan`` for a plan of N regrasps.

Usage::

    flock /tmp/pivot-bench.lock python benchmarks/refined_bound.py --maps willow_garage_2010
    python benchmarks/refined_bound.py --maps turtlebot3_world --windows necks,all
    python benchmarks/refined_bound.py --maps willow_garage_2010 --windows guided --target 2
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from buildings import CORPUS, import_corpus_map  # noqa: E402


def main() -> None:
    """Print one Markdown row per map and window kind."""
    from pivot_ompl.analysis.guided_refine import GuidedRound, guided_lower_bound
    from pivot_ompl.analysis.raster_bound import raster_graph, raster_lower_bound
    from pivot_ompl.analysis.raster_cover import raster_cover
    from pivot_ompl.analysis.raster_refine import neck_window, turn_neck_window
    from pivot_ompl.analysis.refined_bound import refined_lower_bound
    from pivot_ompl.analysis.wall_frame import relaxed_scene
    from pivot_ompl.scene import load_scene

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--maps", default="willow_garage_2010", help="comma-separated corpus names")
    p.add_argument("--windows", default="necks,turns", help="comma-separated window kinds")
    p.add_argument("--target", type=int, default=None,
                   help="stop the guided rounds at this many regrasps")
    p.add_argument("--scenes", default="",
                   help="comma-separated scene files or shipped names, besides the maps")
    args = p.parse_args()
    kinds = {"necks": neck_window, "turns": turn_neck_window,
             "all": lambda c: np.ones(c.raster.shape, dtype=bool)}
    print("| map | coarse bound | coarse s | window | cells refined | refined bound | "
          "refinement s |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        names = [n for n in args.maps.split(",") if n] + [s for s in args.scenes.split(",") if s]
        for name in names:
            m = next((m for m in CORPUS if m.name == name), None)
            scene = relaxed_scene(load_scene(name if m is None else
                                             import_corpus_map(m, Path(tmp))["scene"]))
            name = Path(name).stem
            t0 = time.perf_counter()
            cover = raster_cover(scene, cell=0.1)
            assert cover is not None
            graphs = [raster_graph(scene, cover)]  # handed on to the guided rounds, as in plan
            coarse = raster_lower_bound(scene, cover=cover, graph=graphs[0])
            coarse_s = time.perf_counter() - t0
            for kind in args.windows.split(","):
                if kind == "guided":
                    trace: list[GuidedRound] = []
                    t0 = time.perf_counter()
                    got = guided_lower_bound(scene, cover=cover, target=args.target,
                                             trace=trace,
                                             coarse=graphs.pop() if graphs else None)
                    seconds = time.perf_counter() - t0
                    counts = ", ".join(str(r.regrasps) for r in trace)
                    times = ", ".join(f"{r.seconds:.2f}" for r in trace)
                    print(f"| {name} | {coarse.regrasps} | {coarse_s:.2f} | guided "
                          f"({len(trace)} rounds: {counts}; s: {times}) | {trace[-1].window} | "
                          f"{'-' if got is None else got.regrasps} | {seconds:.2f} |",
                          flush=True)
                    continue
                window = kinds[kind](cover)
                t0 = time.perf_counter()
                refined = refined_lower_bound(scene, cover, window=window)
                seconds = time.perf_counter() - t0
                said = "-" if refined is None else (
                    "no plan" if refined.solvable is False else refined.regrasps)
                print(f"| {name} | {coarse.regrasps} | {coarse_s:.2f} | {kind} | "
                      f"{int(window.sum())} | {said} | {seconds:.2f} |", flush=True)


if __name__ == "__main__":
    main()

"""Walking floor field micro-benchmark: the static field and the box footprints, old vs new.

For fig10 and its copies (``scene_copy``: ``rot37``, ``mir20`` by default), times
``FloorField.static_open`` (the obstacles' part, once per planning run) and
``FloorGrid.meets_box`` (the resting box's part, per lattice-field query) with the numpy
route (``minkowski.meeting_edges`` + ``rasters.grid_union``) and with the shapely route it replaced
(:func:`reference_fits`, :func:`reference_meets_box`: shapely convex hulls of vertex
differences, each rasterised by ``rasters.grid_inside``), side by side: CPU time
(``process_time``), best of ``--repeat`` fresh fields (old and new alternated), and whether
the booleans are equal.

    python benchmarks/walk_field.py [--scene fig10] [--copies rot37,mir20] [--repeat 5]
        [--out results/walk_field.json]
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import numpy as np
import shapely
from common import write_json
from walk_queries import scene_copy

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import Pose, rectangle_corners
from pivot_ompl.transit.field import OPEN_YAWS, FloorField
from pivot_ompl.transit.floor_grid import FloorGrid
from pivot_ompl.transit.lattice import HEADING_YAWS
from pivot_ompl.validity.footprints import meeting_hulls
from pivot_ompl.validity.rasters import grid_inside


def reference_fits(f: FloorGrid, yaw: float) -> np.ndarray:
    """``FloorGrid.fits_index`` of ``yaw`` by the shapely route (the code before the
    numpy one)."""
    c, s = math.cos(yaw), math.sin(yaw)
    rot = np.array([[c, -s], [s, c]])
    corners = f.outline @ rot.T
    b = f.world.bounds
    xs, ys = f.grid_x[:, 0], f.grid_y[0, :]
    ok = ((xs + corners[:, 0].min() > b[0]) & (xs + corners[:, 0].max() < b[2]))[:, None] \
        & ((ys + corners[:, 1].min() > b[1]) & (ys + corners[:, 1].max() < b[3]))[None, :]
    for hull in meeting_hulls(f.pieces, f.grown_outline @ rot.T):
        cols, rows, inside = grid_inside(hull, xs, ys)
        ok[cols, rows] &= ~inside
    return ok


def reference_meets_box(f: FloorGrid, obj: Pose) -> list[np.ndarray]:
    """``FloorGrid.meets_box`` by the shapely route (the code before the numpy one)."""
    box = shapely.Polygon(rectangle_corners(obj, f.model.object_size[0], f.model.object_size[1]))
    if f.box_margin > 0:
        box = box.buffer(f.box_margin, quad_segs=4)
    pts = np.asarray(box.exterior.coords)[:-1]
    diffs = []
    for yaw in HEADING_YAWS:
        c, s = math.cos(yaw), math.sin(yaw)
        body = f.outline @ np.array([[c, -s], [s, c]]).T
        diffs.append((pts[:, None, :] - body[None, :, :]).reshape(-1, 2))
    hulls = shapely.convex_hull(shapely.multipoints(
        np.concatenate(diffs), indices=np.repeat(np.arange(len(diffs)), len(diffs[0]))))
    xs, ys = f.grid_x[:, 0], f.grid_y[0, :]
    out = []
    for hull in hulls:
        meets = np.zeros((f.nx, f.ny), dtype=bool)
        cols, rows, inside = grid_inside(hull, xs, ys)
        meets[cols, rows] = inside
        out.append(meets)
    return out


def fresh_field(template: FloorField, old: bool) -> FloorField:
    """A new field of ``template``'s scene, on the shapely route if ``old``."""
    g = template.grid
    f = FloorField(g.model, g.world, g.resolution, g.box_margin)
    if old:
        f.grid.fits_range = lambda k0, k1, *_: [  # type: ignore[method-assign]
            reference_fits(f.grid, OPEN_YAWS[k]) for k in range(k0, k1)]
        f.grid.meets_box = lambda obj: reference_meets_box(  # type: ignore[method-assign]
            f.grid, obj)
    return f


def best_of(repeat: int, runs: dict[str, Callable[[], object]]) -> dict[str, tuple[float, object]]:
    """Per run, least CPU time (s) of ``repeat`` (the runs alternated), and its last result."""
    best = {name: (math.inf, None) for name in runs}
    for _ in range(repeat):
        for name, run in runs.items():
            t = time.process_time()
            out = run()
            best[name] = (min(best[name][0], time.process_time() - t), out)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="fig10")
    ap.add_argument("--copies", default="rot37,mir20")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default="results/walk_field.json")
    a = ap.parse_args()
    rows = []
    for copy in ["", *a.copies.split(",")]:
        scene = scene_copy(a.scene, copy)
        template = PivotChecker(scene).walker.field
        objs = [scene.start, scene.goal]
        row: dict[str, object] = {"copy": copy or "orig",
                                  "grid": [template.grid.nx, template.grid.ny]}
        static = best_of(a.repeat, {
            route: (lambda t=template, old=route == "old": fresh_field(t, old).static_open())
            for route in ("old", "new")})
        fields = {route: fresh_field(template, route == "old") for route in ("old", "new")}
        box = best_of(a.repeat, {
            route: (lambda f=f, objs=objs: [f.grid.meets_box(o) for o in objs])
            for route, f in fields.items()})
        results = {}
        for route in ("old", "new"):
            row[f"static_open_{route}_ms"] = 1e3 * static[route][0]
            row[f"meets_box_{route}_ms"] = 1e3 * box[route][0] / len(objs)
            results[route] = (static[route][1], box[route][1])
        (ok_old, m_old), (ok_new, m_new) = results["old"], results["new"]
        row["equal"] = bool(np.array_equal(ok_old, ok_new)) and all(
            np.array_equal(x, y) for a_, b_ in zip(m_old, m_new, strict=True)
            for x, y in zip(a_, b_, strict=True))
        row["static_speedup"] = row["static_open_old_ms"] / row["static_open_new_ms"]
        row["meets_box_speedup"] = row["meets_box_old_ms"] / row["meets_box_new_ms"]
        print(f"{row['copy']:>6} grid {template.grid.nx}x{template.grid.ny}: static_open "
              f"{row['static_open_old_ms']:.1f} -> {row['static_open_new_ms']:.1f} ms "
              f"(x{row['static_speedup']:.2f}), meets_box {row['meets_box_old_ms']:.2f} -> "
              f"{row['meets_box_new_ms']:.2f} ms (x{row['meets_box_speedup']:.2f}), "
              f"equal: {row['equal']}")
        rows.append(row)
    write_json({"scene": a.scene, "repeat": a.repeat, "rows": rows}, a.out)


if __name__ == "__main__":
    main()

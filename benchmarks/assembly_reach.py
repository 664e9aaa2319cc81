"""Where the held assembly can go from a region: a fine flood fill over poses, both parities.

A diagnosis for a scene the regrasp planner does not solve: is the start's region closed to the
assembly (box and robot holding it), or is the planner's sampling too sparse? States are a car
pose on a grid (``--step`` m, ``--headings`` headings) at one grasp parity (grasps 0 and 2 have
the same car-relative shape, so have 1 and 3). Moves from a state: a push or pull of about 1.5
grid steps along the heading, a spin of one heading (its half-way heading checked too), an arc
of the scene's turning radius turning one heading forward or backward, either side (its
middle checked), and a regrasp to the other parity at the same box pose (valid at both). A
state is kept where :meth:`PivotChecker.state_valid` holds. Seeds: every valid state whose car
lies in ``--seeds`` at either parity (a superset of what the planner reaches there).

Not a proof either way: poses between grid points and checks between the tested poses are
left out; a reached state is a strong hint, an unreached region a strong hint of none.

Usage::

    python benchmarks/assembly_reach.py SCENE.yaml --seeds -0.8,-2.5,0.8,-1.6 \\
        --region -2.6,-2.5,0,0.3 --target -2.6,-0.9,-1.3,0.3
"""

from __future__ import annotations

import argparse
import collections
import math
import time
from collections.abc import Iterator

from pivot_ompl.base.problem import make_problem
from pivot_ompl.planners.objects.roadmap import half_turn
from pivot_ompl.scene.files import load_scene
from pivot_ompl.se2 import Pose

State = tuple[int, int, int, int]  # (parity, ix, iy, heading)


def _box(text: str) -> tuple[float, float, float, float]:
    x0, y0, x1, y1 = (float(v) for v in text.split(","))
    return x0, y0, x1, y1


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--seeds", type=_box, required=True, help="x0,y0,x1,y1 of the seed cars")
    ap.add_argument("--region", type=_box, required=True, help="x0,y0,x1,y1 searched")
    ap.add_argument("--target", type=_box, required=True, help="x0,y0,x1,y1 to reach")
    ap.add_argument("--step", type=float, default=0.02)
    ap.add_argument("--headings", type=int, default=64)
    a = ap.parse_args()
    scene = load_scene(a.scene)
    ck = make_problem(scene).checker
    m, radius = ck.model, scene.turning_radius
    x0, y0, x1, y1 = a.region
    dx, nh = a.step, a.headings
    dh = 2 * math.pi / nh
    nx, ny = int((x1 - x0) / dx) + 1, int((y1 - y0) / dx) + 1
    valid: dict[State, bool] = {}

    def car(s: State) -> Pose:
        return (x0 + s[1] * dx, y0 + s[2] * dx, s[3] * dh)

    def snap(p: int, c: Pose) -> State:
        return (p, round((c[0] - x0) / dx), round((c[1] - y0) / dx), round(c[2] / dh) % nh)

    def ok(p: int, c: Pose) -> bool:
        return ck.state_valid(m.object_from_car(c, p), p)

    def free(s: State) -> bool:
        v = valid.get(s)
        if v is None:
            v = valid[s] = 0 <= s[1] < nx and 0 <= s[2] < ny and ok(s[0], car(s))
        return v

    def moves(s: State) -> Iterator[State]:
        p, (cx, cy, yaw) = s[0], car(s)
        obj = m.object_from_car((cx, cy, yaw), p)
        for o in (obj, half_turn(obj)):  # regrasps (grasp 1 - p or 3 - p)
            yield snap(1 - p, m.car_pose(o, 1 - p))
        for sgn in (1, -1):  # push, pull
            yield snap(p, (cx + sgn * 1.5 * dx * math.cos(yaw),
                           cy + sgn * 1.5 * dx * math.sin(yaw), yaw))
        for turn in (1, -1):  # spins
            if ok(p, (cx, cy, yaw + 0.5 * turn * dh)):
                yield (p, s[1], s[2], (s[3] + turn) % nh)
        for fwd in (1, -1):  # arcs, forward and backward, left and right
            for side in (1, -1):
                ox, oy = cx - side * radius * math.sin(yaw), cy + side * radius * math.cos(yaw)
                ends = []
                for f in (0.5, 1.0):
                    t = f * fwd * side * dh
                    ends.append((ox + (cx - ox) * math.cos(t) - (cy - oy) * math.sin(t),
                                 oy + (cx - ox) * math.sin(t) + (cy - oy) * math.cos(t),
                                 yaw + t))
                if ok(p, ends[0]):
                    yield snap(p, ends[1])

    t0 = time.perf_counter()
    sx0, sy0, sx1, sy1 = a.seeds
    seeds = [(p, ix, iy, h) for ix in range(nx) for iy in range(ny)
             if sx0 <= x0 + ix * dx <= sx1 and sy0 <= y0 + iy * dx <= sy1
             for h in range(nh) for p in (0, 1)]
    seeds = [s for s in seeds if free(s)]
    seen = set(seeds)
    queue = collections.deque(seeds)
    while queue:
        for t in moves(queue.popleft()):
            if t not in seen and free(t):
                seen.add(t)
                queue.append(t)
    tx0, ty0, tx1, ty1 = a.target
    hit = [s for s in seen if tx0 <= car(s)[0] <= tx1 and ty0 <= car(s)[1] <= ty1]
    xs, ys = [car(s)[0] for s in seen], [car(s)[1] for s in seen]
    print(f"{len(seeds)} seed states, {len(seen)} reached ({len(valid)} checked) in "
          f"{time.perf_counter() - t0:.1f} s; cars reached over x {min(xs):.2f}..{max(xs):.2f}, "
          f"y {min(ys):.2f}..{max(ys):.2f}; in the target: {len(hit)}")


if __name__ == "__main__":
    main()

"""``pivot-ompl bound SCENE``: the fewest regrasps any plan of a scene needs, proven.

Prints the lower bounds on regrasps and on the box's route
(:mod:`pivot_ompl.analysis.regrasp_bound`, :mod:`pivot_ompl.analysis.route_bound`; the route
the larger of the relaxation's and the disk route with the gaps no held pose fits closed,
:func:`pivot_ompl.analysis.plan_bounds.route_bound`, as a plan's ``shortest_route``), computed
once per scene geometry and cached (``--no-cache`` computes afresh and keeps nothing): the
raster relaxation first, the exact polygons when they are estimated to take at most 2.5
seconds (``--exhaustive``: always; :mod:`pivot_ompl.analysis.bound_levels`), and with
``--guided`` the raster refined where its best path passes narrow places
(:mod:`pivot_ompl.analysis.guided_refine`; later plans read it from the cache), and with
``--held-poses``, where the relaxation joins start and goal, the held poses' proof that no
plan exists (:func:`pivot_ompl.analysis.late_proof.held_pose_proof`: the yaw refined where
the held assembly may pass, the robot walking round the box at every regrasp; minutes on
thousands of boxes, not cached). Exit
status: 0 a bound, 1 none (stopped by ``--time``, or the relaxation proves that no plan
exists), 2 bad input.
"""

from __future__ import annotations

import argparse
import math
import time

from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.bound_levels import REFINE_SECONDS
from pivot_ompl.analysis.late_proof import held_pose_proof
from pivot_ompl.analysis.plan_bounds import route_bound
from pivot_ompl.cli.args import time_limit
from pivot_ompl.errors import printable
from pivot_ompl.scene import load_scene


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``bound`` verb."""
    p = sub.add_parser("bound", help="prove the fewest regrasps any plan of a scene needs")
    p.add_argument("scene", help="scene file (YAML) or shipped scene's name, e.g. fig10")
    p.add_argument("--time", type=time_limit("--time"), default=60.0,
                   help="time limit of a computation (s; default 60)")
    p.add_argument("--no-cache", action="store_true",
                   help="compute afresh (neither read nor write the cache)")
    p.add_argument("--exhaustive", action="store_true",
                   help="also run the exact polygon relaxation on a large floor (minutes on "
                        "thousands of boxes; by default only where estimated <= 2.5 s)")
    p.add_argument("--guided", action="store_true",
                   help="where the polygons do not run, refine the raster where its best path "
                        "passes narrow places (seconds on thousands of boxes)")
    p.add_argument("--held-poses", action="store_true",
                   help="where the relaxation joins start and goal, also try to prove that no "
                        "plan exists from the held assembly's poses, refined in yaw (minutes on "
                        "thousands of boxes)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Compute (or read) and print the bounds."""
    scene = load_scene(args.scene)
    t0 = time.perf_counter()
    end = time.monotonic() + args.time
    b = lower_bound(scene, use_cache=not args.no_cache,
                    refine_seconds=math.inf if args.exhaustive else REFINE_SECONDS,
                    should_stop=lambda: time.monotonic() > end,
                    guided_seconds=math.inf if args.guided else 0.0)
    took = time.perf_counter() - t0
    how = ("polygons" if b.exhaustive else "raster, held poses" if b.held
           else "raster, guided" if b.guided else "raster")
    where = f"{how}, {b.bins} yaw bins, {b.pieces} pieces; {took:.2f} s"
    if b.solvable is None:
        print(f"{printable(scene.name)}: unknown (stopped after {args.time:g} s; {where})")
        return 1
    if b.solvable is False:
        print(f"{printable(scene.name)}: no plan exists (proven: the relaxation joins no path; "
              f"{where})")
        return 1
    if args.held_poses:
        t1 = time.perf_counter()
        proof = held_pose_proof(scene, should_stop=lambda: time.monotonic() > end)
        if proof is not None:
            print(f"{printable(scene.name)}: {proof.reason} (proven: held poses; "
                  f"{time.perf_counter() - t1:.2f} s)")
            return 1
    n = b.regrasps
    held = route_bound(scene, should_stop=lambda: time.monotonic() > end,
                       use_cache=not args.no_cache)  # the gaps no held pose fits closed
    known = [r for r in (b.shortest_route, held) if r is not None]
    route = "" if not known else f", a box route of at least {max(known):.2f} m"
    print(f"{printable(scene.name)}: at least {n} regrasp{'' if n == 1 else 's'}{route} "
          f"(proven; {where})")
    return 0

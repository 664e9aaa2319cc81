"""``pivot-ompl generate --family F --seed N --out DIR``: a scene and its witness plan.

Writes ``DIR/<name>.yaml`` and ``DIR/<name>.witness.json`` (a ``pivot-plan/1`` plan that
passes ``pivot-ompl check``) for each seed, all or nothing: every scene is generated before any
file is written. Exit status: 0 written, 2 bad input.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

from pivot_ompl.cli.args import positive, time_limit
from pivot_ompl.errors import InputError, Interrupted, counted
from pivot_ompl.generate import FAMILIES, GeneratorParams, generate, write_all_generated
from pivot_ompl.generate.params import BUILDING_LAYOUTS

#: Most scenes one run generates (each is kept in memory until all are written).
MAX_COUNT = 10_000
#: Seconds between two alarms of :func:`time_limited` once its limit has passed.
REPEAT = 0.05


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``generate`` verb."""
    p = sub.add_parser("generate", help="generate a scene with a witness plan")
    p.add_argument("--family", required=True, choices=sorted(FAMILIES))
    p.add_argument("--seed", type=int, default=0, help="seed (>= 0)")
    p.add_argument("--count", type=positive("--count"), default=1,
                   help=f"scenes of seeds seed, seed+1, ... (default 1, at most {MAX_COUNT})")
    p.add_argument("--time", type=time_limit("--time"), default=math.inf,
                   help="time limit (s) of the whole generation: past it nothing is written "
                        "and the exit status is 1 (default: inf, no limit)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--door-width", type=positive("--door-width"), nargs=2,
                   metavar=("MIN", "MAX"), help="range of robot door widths (m), walls")
    p.add_argument("--no-rotate", action="store_true",
                   help="keep the layout's axes (walls, corridor, building)")
    p.add_argument("--walls", type=positive("--walls"), metavar="K",
                   help="number of walls, each with a box-only slot (walls; default 1-3)")
    p.add_argument("--slot-clearance", type=positive("--slot-clearance"), metavar="C",
                   help="gap (m) each side of the box in every slot (walls, building)")
    p.add_argument("--rooms", type=positive("--rooms"), metavar="N",
                   help="number of rooms (building; default 4)")
    p.add_argument("--layout", choices=BUILDING_LAYOUTS, default="row",
                   help="rooms in a row or a grid, or in a row with every wall a box-only "
                        "slot and the robot's way round a corridor (building; default row)")
    p.add_argument("--wide-doors", type=positive("--wide-doors"), nargs=2,
                   metavar=("MIN", "MAX"),
                   help="every wall along a row a door robot and box pass together, of a "
                        "width in MIN-MAX (m), off the wall's middle (building)")
    p.add_argument("--side-corridor", type=positive("--side-corridor"), nargs=2,
                   metavar=("MIN", "MAX"),
                   help="width (m) of the robot's corridor (building --layout corridor; "
                        "default 0.87 0.89: 1-3 cm wider than the walking body)")
    p.add_argument("--side-door", type=positive("--side-door"), nargs=2,
                   metavar=("MIN", "MAX"),
                   help="width (m) of the doors into that corridor (default 1.0 1.0)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Generate and write the scenes."""
    if args.seed < 0:
        raise InputError("--seed", args.seed, "must be >= 0")
    if int(args.count) != args.count:
        raise InputError("--count", args.count, "must be a whole number")
    if args.count > MAX_COUNT:
        raise InputError("--count", args.count, f"at most {MAX_COUNT} scenes in one run")
    for name in ("walls", "rooms"):
        value = getattr(args, name)
        if value is not None and int(value) != value:
            raise InputError(f"--{name}", value, "must be a whole number")
    params = GeneratorParams(rotate=not args.no_rotate,
                             walls=None if args.walls is None else int(args.walls),
                             slot_clearance=args.slot_clearance,
                             rooms=4 if args.rooms is None else int(args.rooms),
                             layout=args.layout)
    if args.door_width:
        params = dataclasses.replace(params, door_width=_range(args.door_width, "--door-width"))
    if args.wide_doors:
        params = dataclasses.replace(params, wide_doors=_range(args.wide_doors, "--wide-doors"))
    if args.side_corridor:
        params = dataclasses.replace(params, side_corridor=_range(args.side_corridor,
                                                                  "--side-corridor"))
    if args.side_door:
        params = dataclasses.replace(params, side_door=_range(args.side_door, "--side-door"))
    check_out_dir(args.out)
    with time_limited(args.time, "generating the scenes"):
        gens = [generate(args.family, seed, params=params)
                for seed in range(args.seed, args.seed + int(args.count))]
    for gen, (scene_path, plan_path) in zip(gens, write_all_generated(gens, args.out),
                                            strict=True):
        print(f"{scene_path} ({counted(len(gen.scene.obstacles), 'obstacle')}), witness "
              f"{plan_path} ({counted(gen.witness.pivots, 'pivot')}, "
              f"{counted(gen.witness.regrasps, 'regrasp')})")
    return 0


def _range(value: list[float], flag: str) -> tuple[float, float]:
    """``MIN MAX`` of a range flag as a tuple (:class:`InputError` unless MIN <= MAX)."""
    lo, hi = value
    if lo > hi:
        raise InputError(flag, list(value), "must be MIN <= MAX")
    return lo, hi


def check_out_dir(path: str) -> None:
    """Refuse, before the work, an ``--out`` folder that cannot hold the files.

    Raises:
        InputError: ``path`` is a file, a name in it too long, or a folder in it a file.
    """
    from pathlib import Path

    from pivot_ompl.fileio import check_output

    check_output(Path(path) / "x.yaml", field="--out")  # names first: exists() could fail
    if Path(path).exists() and not Path(path).is_dir():
        raise InputError("--out", path, "is a file: give a folder")


@contextmanager
def time_limited(seconds: float, what: str) -> Iterator[None]:
    """Raise :class:`~pivot_ompl.errors.Interrupted` in the block once ``seconds`` have passed.

    A real-time alarm (``SIGALRM``) interrupts the work wherever it is, so no loop of it has
    to poll; it rings again every :data:`REPEAT` s until the interruption gets out of the work
    (a library's callback may swallow one). Without an alarm (not the main thread, not POSIX)
    or with an infinite limit, nothing.
    """
    if not math.isfinite(seconds) or not hasattr(signal, "setitimer") or \
            threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: FrameType | None) -> None:
        raise Interrupted(what)

    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, seconds, REPEAT)  # again until it gets through
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)

"""``pivot-ompl import-map MAP.yaml --out SCENE.yaml --start X Y YAW --goal X Y YAW``.

Turns a ROS map_server map (a YAML file and its PGM or PNG image) into a scene file: free
cells are floor, occupied and unknown cells become box obstacles exact to the cell, the
scene keeps the map's frame (poses as read in RViz on the map). The scene file's header says
which map, image and resolution it came from and what cleaning removed. Exit status: 0
written, 2 bad input (a bad map field, a pose outside the free area or on an obstacle); an
existing --out file is replaced only on success.
"""

from __future__ import annotations

import argparse

from pivot_ompl.cli.args import finite, output_files, positive
from pivot_ompl.errors import InputError, counted
from pivot_ompl.generate.sceneio import write_scene
from pivot_ompl.maps import MapCleaning, import_map
from pivot_ompl.maps.importer import DEFAULT_BOX, DEFAULT_HEIGHT

#: Values of a bare ``--clean specks`` (m²), ``--clean streaks`` and ``--clean gaps`` (m).
CLEAN_DEFAULTS = {"specks": 0.02, "streaks": 0.5, "gaps": 0.2}


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``import-map`` verb."""
    p = sub.add_parser("import-map", help="turn a ROS map_server map into a scene file")
    p.add_argument("map", help="the map's YAML file (image, resolution, origin, ...)")
    p.add_argument("--out", required=True, help="scene file to write (YAML)")
    p.add_argument("--start", type=finite("--start"), nargs=3, required=True,
                   metavar=("X", "Y", "YAW"), help="box start pose in the map frame (m, rad)")
    p.add_argument("--goal", type=finite("--goal"), nargs=3, required=True,
                   metavar=("X", "Y", "YAW"), help="box goal pose in the map frame (m, rad)")
    p.add_argument("--height", type=positive("--height"), default=DEFAULT_HEIGHT,
                   help="height of the obstacles (m)")
    p.add_argument("--box", type=positive("--box"), nargs=3, default=list(DEFAULT_BOX),
                   metavar=("W", "D", "H"), help="box size (m), the regrasp paper's Fig. 10 box "
                   "unless given")
    p.add_argument("--name", help="scene name (default: the map file's name)")
    p.add_argument("--clean", action="append", default=[], metavar="OP[=VALUE]",
                   help="clean the map before boxing it; repeatable: specks[=AREA] frees "
                   "groups of blocked cells of at most AREA m2 clear of the floor area's edge "
                   "(default "
                   f"{CLEAN_DEFAULTS['specks']:g}); streaks[=LENGTH] frees one-cell-wide lines "
                   "held at most at one end, of at most LENGTH m (default "
                   f"{CLEAN_DEFAULTS['streaks']:g}); gaps[=WIDTH] blocks free cells no free "
                   "square of side WIDTH m holds: laser rays into unseen space (default "
                   f"{CLEAN_DEFAULTS['gaps']:g})")
    p.set_defaults(func=run)


def parse_cleaning(items: list[str]) -> MapCleaning:
    """The ``--clean`` options as a :class:`MapCleaning` (:class:`InputError` naming one)."""
    values: dict[str, float] = {}
    for item in items:
        op, sep, text = item.partition("=")
        if op not in CLEAN_DEFAULTS:
            raise InputError("--clean", item, f"unknown operation (known: "
                             f"{', '.join(CLEAN_DEFAULTS)})")
        if not sep:
            values[op] = CLEAN_DEFAULTS[op]
            continue
        try:
            v = float(text)
        except ValueError:
            raise InputError("--clean", item, "the value must be a number") from None
        if not 0 < v < 1e6:
            raise InputError("--clean", item, "the value must be > 0 (and finite)")
        values[op] = v
    return MapCleaning(**values)


def run(args: argparse.Namespace) -> int:
    """Import the map and write the scene."""
    cleaning = parse_cleaning(args.clean)
    (out,) = output_files([args.map], suffixes={"out": (".yaml", ".yml")}, out=args.out)
    assert out is not None  # noqa: S101 - --out is required
    result = import_map(args.map, start=args.start, goal=args.goal, height=args.height,
                        box=args.box, cleaning=cleaning, name=args.name)
    write_scene(result.scene, out, comment=result.header)
    b = result.scene.bounds
    print(f"{out}: {counted(len(result.scene.obstacles), 'box', 'boxes')} over "
          f"{b[2] - b[0]:.2f} x {b[3] - b[1]:.2f} m ({result.map.resolution:g} m/px)")
    return 0

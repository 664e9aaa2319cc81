"""``pivot-ompl robots``: the humanoid profiles a scene can name (``robot: {model: NAME}``).

Prints each profile's key figures (height, footprint, standoff, walking envelope, sole, step
limits, CoM height, joints) and whether its model files are found; ``--json`` prints them as
a JSON list. Exit status 0.
"""

from __future__ import annotations

import argparse
import json

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, HumanoidProfile


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``robots`` verb."""
    p = sub.add_parser("robots", help="list the humanoid profiles and their key figures")
    p.add_argument("--json", action="store_true", help="print a JSON list")
    p.set_defaults(func=run)


def _installed(p: HumanoidProfile) -> str:
    """``"yes"``, or why the model files are not found."""
    try:
        p.urdf_path()
    except InputError as e:
        return f"no ({e.reason})"
    return "yes"


def run(args: argparse.Namespace) -> int:
    """Print the profiles."""
    rows: list[dict[str, object]] = []
    for p in PROFILES.values():
        figures = p.key_figures()
        figures["default"] = p.name == DEFAULT_MODEL
        figures["installed"] = _installed(p)
        rows.append(figures)
    if args.json:
        print(json.dumps(rows, indent=1))
        return 0
    for r in rows:
        print(f"{r['model']}{' (default)' if r['default'] else ''}: {r['title']}")
        print(f"  height {r['height_m']:.2f} m, footprint {_pair(r['footprint_m'])} m, "
              f"standoff {r['standoff_m']:.2f} m, walking envelope ahead/behind/side "
              f"{'/'.join(f'{v:.2f}' for v in r['walk_envelope_m'])} m")  # type: ignore[attr-defined]
        print(f"  sole {_pair(r['sole_m'])} m, steps {r['step_forward_m']:.2f} m forward, "
              f"{r['step_lateral_m']:.2f} m sideways, {r['step_turn_rad']:.2f} rad; "
              f"CoM {r['com_height_m']:.2f} m; model files: {r['installed']}")
    return 0


def _pair(v: object) -> str:
    assert isinstance(v, list)  # noqa: S101 - the key figures' pairs
    return f"{v[0]:.3g} x {v[1]:.3g}"

"""L-shaped corridors: closed ones whose corner the held box cannot turn (no plan exists), and
an open L whose far leg the box ends across."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene, rotated_scene_doc

from pivot_ompl.generate.layout import free_complement
from pivot_ompl.generate.layout import make_scene as layout_scene
from pivot_ompl.scene import Scene, scene_from_dict


def _box(x0: float, y0: float, x1: float, y1: float) -> dict:
    return {"type": "box", "center": [0.5 * (x0 + x1), 0.5 * (y0 + y1)],
            "size": [x1 - x0, y1 - y0], "yaw": 0.0, "height": 2.0}


def tight_corner(seed: int, widths: tuple[float, float] = (0.90, 0.94),
                 turned: bool = True, whole: bool | None = None
                 ) -> tuple[dict, tuple[float, float]]:
    """A closed L-shaped corridor (generated from ``seed``) whose corner the held box cannot
    turn: 0.90-0.94 m wide (the box and the robot holding it need 0.88 m across, 1.54 m
    long), legs of 3-4 m, the whole turned by a random angle; the start at the end of one
    leg, the goal at the end of the other (``widths``: the range of the corridor's width;
    ``turned`` False: axis-aligned, the legs whole decimetres; ``whole``: whole decimetres or
    not, whether turned or not). Returns the scene document
    and the corner's inner point."""
    rng = np.random.default_rng(seed)
    w = float(rng.uniform(*widths))
    run, rise = (float(v) for v in rng.uniform(3.0, 4.0, 2))
    angle = float(rng.uniform(-math.pi, math.pi)) if turned else 0.0
    if (not turned) if whole is None else whole:  # walls on whole decimetres: cell edges
        run, rise = round(run, 1), round(rise, 1)
    x1, y1 = 0.3 + run + w + 0.3, 0.3 + rise + w + 0.3  # walls 0.3 m thick all round
    cx = 0.3 + run  # the vertical leg spans x in [cx, cx + w]
    walls = [_box(0.0, 0.0, x1, 0.3), _box(0.0, 0.3, 0.3, 0.3 + w),  # floor side, west end
             _box(0.0, 0.3 + w, cx, y1), _box(cx + w, 0.3, x1, y1),  # inner block, east side
             _box(cx, y1 - 0.3, cx + w, y1)]  # north end
    doc = {"name": f"tight_corner_{seed}", "bounds": [0.0, 0.0, x1, y1],
           "object": {"size": [0.8, 0.6, 1.3]}, "start": [1.3, 0.3 + 0.5 * w, 0.0],
           "goal": [cx + 0.5 * w, y1 - 1.3, 0.5 * math.pi], "obstacles": walls}
    about = (0.5 * x1, 0.5 * y1)
    doc = rotated_scene_doc(doc, angle, about)
    c, s = math.cos(angle), math.sin(angle)
    px, py = cx - about[0], 0.3 + w - about[1]
    return doc, (about[0] + c * px - s * py, about[1] + s * px + c * py)


def corner_slot(strip: float, slot: float):
    """A strip ``strip`` m deep along the floor's bottom, a slot ``slot`` m wide through the
    1 m thick wall above it at x = 4 (the box long and thin: the assembly must turn into it)."""
    left, right = 4.0 - 0.5 * slot, 4.0 + 0.5 * slot
    walls = [{"type": "box", "center": [0.5 * left, strip + 0.5], "size": [left, 1.0],
              "yaw": 0.0, "height": 2.0},
             {"type": "box", "center": [0.5 * (right + 8.0), strip + 0.5],
              "size": [8.0 - right, 1.0], "yaw": 0.0, "height": 2.0}]
    return make_scene(obstacles=walls, object={"size": [1.2, 0.3, 1.0]},
                      start=[1.5, 0.5 * strip, 0.0], goal=[4.0, 4.5, 0.0])



def ragged_slot(seed: int, angle: float = 0.0, *, strip: float = 0.90, slot: float = 0.92,
                pieces: int = 160) -> Scene:
    """:func:`corner_slot`'s floor as a building map gives it, closed by outer walls and turned
    by ``angle`` (rad): each inner wall cut into ``pieces / 2`` strips 1 m deep whose far
    (room-side) ends are ragged by up to 5 cm (``seed``), so that no two merge. A slot the
    box passes and the box held does not: only the held poses' relaxation proves it."""
    rng = np.random.default_rng(seed)
    left, right = 4.0 - 0.5 * slot, 4.0 + 0.5 * slot
    walls = [_box(-0.3, -0.3, 8.3, 0.0), _box(-0.3, 6.0, 8.3, 6.3),  # the floor's walls
             _box(-0.3, 0.0, 0.0, 6.0), _box(8.0, 0.0, 8.3, 6.0)]
    for x0, x1 in ((0.0, left), (right, 8.0)):
        cuts = np.linspace(x0, x1, pieces // 2 + 1)
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            top = strip + 1.0 + float(rng.uniform(0.0, 0.05))
            walls.append(_box(float(a), strip, float(b), top))
    doc = {"name": f"ragged_slot_{seed}", "bounds": [-0.3, -0.3, 8.3, 6.3],
           "object": {"size": [1.2, 0.3, 1.0]}, "start": [1.5, 0.5 * strip, 0.0],
           "goal": [4.0, 4.5, 0.0], "obstacles": walls}
    return scene_from_dict(rotated_scene_doc(doc, angle, (4.0, 3.0)), source="<test>")


def open_corner(width: float = 1.6) -> Scene:
    """An L of corridors ``width`` m wide; the box ends across the far leg, held at its side."""
    bounds = (0.0, -1.5, 8.0, 8.0)
    free = [(0.3, -0.5 * width, 5.0 + 0.5 * width, 0.5 * width),
            (5.0 - 0.5 * width, -0.5 * width, 5.0 + 0.5 * width, 7.5)]
    return layout_scene("corner", bounds, free_complement(bounds, free), (1.5, 0.0, 0.0),
                        (5.0, 6.0, 0.0))

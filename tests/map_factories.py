"""Small map_server maps written for the tests (a YAML file and its image)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from pivot_ompl.maps import scene_from_map
from pivot_ompl.scene import Scene

FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # map_saver's three values


def write_map(folder: Path, pixels: np.ndarray, *, name: str = "map", image: str | None = None,
              resolution: float = 0.1, origin=(0.0, 0.0, 0.0), extra: str = "",
              fmt: str = "pgm") -> Path:
    """A map_server map of ``pixels`` (row 0 the top) in ``folder``; its YAML path."""
    image = image or f"{name}.{fmt}"
    if fmt == "p2":
        image = f"{name}.pgm"
        h, w = pixels.shape
        body = "\n".join(" ".join(str(v) for v in row) for row in pixels.tolist())
        (folder / image).write_text(f"P2\n# ascii\n{w} {h}\n255\n{body}\n")
    else:
        Image.fromarray(pixels).save(folder / image)
    text = (f"image: {image}\nresolution: {resolution}\norigin: {list(origin)}\n"
            f"negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n{extra}")
    path = folder / f"{name}.yaml"
    path.write_text(text)
    return path


def room(w: int = 60, h: int = 40) -> np.ndarray:
    """A room of free cells with a one-cell unknown margin and two-cell occupied walls."""
    px = np.full((h, w), FREE, dtype=np.uint8)
    px[0, :] = px[-1, :] = px[:, 0] = px[:, -1] = UNKNOWN
    px[1:3, 1:-1] = px[-3:-1, 1:-1] = OCCUPIED
    px[1:-1, 1:3] = px[1:-1, -3:-1] = OCCUPIED
    return px


def lab_floor(seed: int, *, door: float = 0.85, resolution: float = 0.05) -> np.ndarray:
    """Two 8 x 7 m rooms side by side as a SLAM map gives them: walls 0.2 m thick whose
    room-side faces are ragged by up to two cells (``seed``: one box per cell row or column
    of a face), the inner wall's doorway ``door`` m wide at the floor's mid-height (the lab
    door of the corpus is 0.85 m; the box held by the robot needs 0.88 m)."""
    rng = np.random.default_rng(seed)
    w, h = round(16.0 / resolution), round(7.0 / resolution)
    px = np.full((h, w), FREE, dtype=np.uint8)
    px[:4, :] = px[-4:, :] = px[:, :4] = px[:, -4:] = OCCUPIED
    mid = w // 2
    px[:, mid - 2:mid + 2] = OCCUPIED
    for c in range(4, w - 4):
        px[4:4 + rng.integers(0, 3), c] = OCCUPIED
        px[h - 4 - rng.integers(0, 3):h - 4, c] = OCCUPIED
    for r in range(4, h - 4):
        for face in (4, w - 4, mid - 2, mid + 2):  # a face's cells grow into its room
            bump = int(rng.integers(0, 3))
            if face in (4, mid + 2):
                px[r, face:face + bump] = OCCUPIED
            else:
                px[r, face - bump:face] = OCCUPIED
    cells = round(door / resolution)
    top = h // 2 - cells // 2
    px[top:top + cells, mid - 4:mid + 4] = FREE  # the doorway, its faces' bumps cleared
    return px


def lab_door(folder: Path, seed: int, *, door: float = 0.85) -> Scene:
    """:func:`lab_floor` imported as a user's map (written in ``folder``), the start and the
    goal either side of the doorway: no plan exists (the held box cannot pass it)."""
    path = write_map(folder, lab_floor(seed, door=door), name=f"lab_{seed}", resolution=0.05)
    return scene_from_map(path, start=(3.0, 3.5, 0.0), goal=(13.0, 3.5, 0.0))


def grid_boxes(seed: int, count: int, *, cell: float = 0.1) -> list[dict]:
    """``count`` boxes of 1-3 whole cells on an 8 x 6 m floor's ``cell`` grid (a map's),
    clear of the small scenes' start (1.5, 3) and goal (6, 3)."""
    rng = np.random.default_rng(seed)
    boxes: list[dict] = []
    while len(boxes) < count:
        ix, iy = int(rng.integers(0, 76)), int(rng.integers(0, 56))
        w, h = int(rng.integers(1, 4)), int(rng.integers(1, 4))
        cx, cy = (ix + 0.5 * w) * cell, (iy + 0.5 * h) * cell
        if all(abs(cx - x) > 0.9 or abs(cy - 3.0) > 0.9 for x in (1.5, 6.0)):
            boxes.append({"type": "box", "center": [cx, cy], "size": [w * cell, h * cell],
                          "height": 1.0})
    return boxes

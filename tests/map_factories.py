"""Small map_server maps written for the tests (a YAML file and its image)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

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

"""The image half of a ``map_server`` map: which cells are free floor.

The image is read with Pillow (a dependency of matplotlib, so already installed with
pivot_ompl): binary (P5) and ascii (P2) PGM, PNG and the other formats Pillow reads. As
``map_server`` does, a colour pixel's value ``v`` is the mean of its colour channels (alpha
excluded) and image row 0 is the top of the map (the largest y).

A pixel of value ``v`` (0..255) has occupancy ``p = (255 - v) / 255``, or ``p = v / 255``
when ``negate`` is set. By mode:

- ``trinary`` (default): ``p > occupied_thresh`` occupied, ``p < free_thresh`` free, any
  other value unknown.
- ``scale``: as trinary, and a pixel that is not fully opaque (alpha < 255) is unknown;
  values between the thresholds, which ``map_server`` passes on as graded occupancies, are
  not free.
- ``raw``: ``v`` itself is the occupancy in percent (0..100, ``negate`` ignored) classified
  by the thresholds as above; any value above 100 (255 is ROS's -1) is unknown.

Only free cells are floor: occupied and unknown cells are obstacles. Memory: the image's
bytes plus a few masks of one byte a pixel (a 4000 x 4000 map: about 100 MB at the peak);
images over :data:`MAX_PIXELS` pixels are refused before they are decoded.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from pivot_ompl.errors import MapError
from pivot_ompl.maps.mapfile import MapFile

logger = logging.getLogger(__name__)

#: Largest image accepted (pixels): 8000 x 8000, 160 m at 2 cm a pixel (below Pillow's own
#: decompression-bomb limit).
MAX_PIXELS = 64_000_000
#: Image modes read as they are (one byte a channel) or after a lossless conversion.
_CONVERT = {"1": "L", "P": "RGBA", "PA": "RGBA"}
_READ = ("L", "LA", "RGB", "RGBA")


def _free_table(mapfile: MapFile, channels: int) -> np.ndarray:
    """Free or not for every sum of ``channels`` channel values (0 .. 255 * channels)."""
    sums = np.arange(255 * channels + 1, dtype=np.float64)
    value = sums / channels
    if mapfile.mode == "raw":
        p = value / 100.0
        known = value <= 100.0
        return known & (p < mapfile.free_thresh)
    p = value / 255.0 if mapfile.negate else (255.0 - value) / 255.0
    return p < mapfile.free_thresh


def free_cells(mapfile: MapFile) -> np.ndarray:
    """The free cells of ``mapfile``'s image: a boolean array, row 0 the image's top row.

    Raises:
        MapError: the image cannot be read, is larger than :data:`MAX_PIXELS` pixels,
            empty, or of a kind (16-bit, floating point) ``map_server`` does not read.
    """
    from PIL import Image, UnidentifiedImageError

    src = str(mapfile.path)
    path: Path = mapfile.image
    try:
        with Image.open(path) as img:
            w, h = img.size
            if w * h > MAX_PIXELS:
                raise MapError("image", f"{path.name} ({w} x {h} px)", f"is larger than "
                               f"{MAX_PIXELS:,} pixels", source=src)
            if w == 0 or h == 0:
                raise MapError("image", path.name, "is empty (0 pixels)", source=src)
            mode = img.mode
            if mode in _CONVERT:
                pixels = np.asarray(img.convert(_CONVERT[mode]))
            elif mode in _READ:
                pixels = np.asarray(img)
            else:
                raise MapError("image", f"{path.name} (mode {mode})", "must hold 8-bit "
                               "grey or colour pixels (map_server's images)", source=src)
    except MapError:
        raise
    except (UnidentifiedImageError, OSError, ValueError, Image.DecompressionBombError) as e:
        raise MapError("image", path.name, f"cannot be read as an image ({e})",
                       source=src) from None
    return _classify(pixels, mapfile)


def _classify(pixels: np.ndarray, mapfile: MapFile) -> np.ndarray:
    """Free cells of an ``(h, w)`` or ``(h, w, channels)`` uint8 array (see the module)."""
    if pixels.ndim == 2:
        return _free_table(mapfile, 1)[pixels]
    channels = pixels.shape[2]
    alpha = channels in (2, 4)
    colours = channels - 1 if alpha else channels
    total = pixels[:, :, 0].astype(np.uint16)
    for c in range(1, colours):
        total += pixels[:, :, c]
    free = _free_table(mapfile, colours)[total]
    del total
    if alpha and mapfile.mode == "scale":
        free &= pixels[:, :, channels - 1] == 255
    return free

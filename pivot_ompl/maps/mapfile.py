"""The YAML half of a ROS ``map_server`` map: where the image is and how to read its pixels.

Format (written by ``map_saver`` and read by ROS 1 ``map_server`` and Nav2's
``nav2_map_server``)::

    image: map.pgm              # PGM (binary P5 or ascii P2) or PNG, relative to this file
    resolution: 0.05            # metres per pixel
    origin: [-10.0, -10.0, 0.0] # map-frame pose [x, y, yaw] of the image's lower-left pixel
    negate: 0                   # 1: white is occupied
    occupied_thresh: 0.65       # occupancy above it: occupied
    free_thresh: 0.196          # occupancy below it: free
    mode: trinary               # optional: trinary (default), scale or raw

``negate``, ``occupied_thresh`` and ``free_thresh`` default to 0, 0.65 and 0.196 (the values
``map_saver`` writes) when absent. Other keys are ignored (a warning names them). The yaw of
``origin`` turns the image about its lower-left corner, as RViz shows it (several ROS
consumers, ``amcl`` and ``costmap_2d`` among them, ignore it).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pivot_ompl.errors import MapError
from pivot_ompl.fileio import input_path, load_yaml, regular_file

logger = logging.getLogger(__name__)

#: Accepted resolutions (m per pixel): a millimetre to ten metres.
MIN_RESOLUTION, MAX_RESOLUTION = 1e-3, 10.0
#: Largest magnitude of an origin coordinate (m), the scene files' coordinate limit.
MAX_ORIGIN = 1.0e4
#: The modes of ``map_server``.
MODES = ("trinary", "scale", "raw")
#: Defaults of the optional keys (``map_saver``'s values).
DEFAULTS = {"negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196, "mode": "trinary"}
_KNOWN = {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"}


@dataclass(frozen=True)
class MapFile:
    """A validated ``map_server`` YAML file.

    Attributes:
        path: the YAML file.
        image: the image file (resolved against the YAML file's folder).
        resolution: metres per pixel.
        origin: map-frame ``(x, y)`` of the lower-left corner of the image's lower-left
            pixel (m).
        negate: white is occupied.
        occupied_thresh: occupancy above it is occupied (in [0, 1]).
        free_thresh: occupancy below it is free (in [0, 1], below ``occupied_thresh``).
        mode: ``"trinary"``, ``"scale"`` or ``"raw"``.
        yaw: the image's rotation in the map frame (rad, ``origin[2]``).
    """

    path: Path
    image: Path
    resolution: float
    origin: tuple[float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: str
    yaw: float = 0.0


def _finite(v: Any, key: str, source: str) -> float:
    """A finite number, or a string of one.

    ``1e-05`` is a string to YAML 1.1 (PyYAML) and a number to yaml-cpp (ROS).
    """
    if isinstance(v, str):
        try:
            v = float(v)
        except ValueError:
            pass
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise MapError(key, v, "must be a finite number", source=source)
    return float(v)


def _number(doc: dict, key: str, source: str, lo: float, hi: float) -> float:
    v = _finite(doc[key], key, source)
    if not lo <= v <= hi:
        raise MapError(key, v, f"must be within [{lo:g}, {hi:g}]", source=source)
    return v


def read_map_yaml(path: str | Path) -> MapFile:
    """Read and validate a ``map_server`` YAML file (the image is checked to exist, not read).

    Raises:
        MapError: unreadable or invalid YAML, a missing or wrong field (naming it and its
            value), a missing image file.
    """
    p = regular_file(input_path(path, error=MapError, field="map"), error=MapError,
                     field="map")
    src = str(p)
    doc = load_yaml(p, error=MapError)
    if not isinstance(doc, dict):
        raise MapError("<document>", type(doc).__name__, "must be a mapping (a map_server "
                       "YAML file: image, resolution, origin, ...)", source=src)
    for key in ("image", "resolution", "origin"):
        if key not in doc:
            raise MapError(key, None, "is required", source=src)
    unknown = sorted(str(k) for k in doc if k not in _KNOWN)
    if unknown:
        logger.warning("%s: ignoring unknown keys %s", src, ", ".join(unknown))
    doc = {**DEFAULTS, **doc}
    image = doc["image"]
    if not isinstance(image, str) or not image:
        raise MapError("image", image, "must be a file name", source=src)
    image_path = Path(image) if Path(image).is_absolute() else p.parent / image
    try:
        image_path = regular_file(image_path, error=MapError, field="image")
    except MapError as e:
        raise MapError("image", image, f"{e.reason} (looked for {image_path})",
                       source=src) from None
    resolution = _number(doc, "resolution", src, MIN_RESOLUTION, MAX_RESOLUTION)
    *origin, yaw = _origin(doc["origin"], src)
    negate = doc["negate"]
    if negate not in (0, 1) or isinstance(negate, float):
        raise MapError("negate", negate, "must be 0 or 1", source=src)
    occupied = _number(doc, "occupied_thresh", src, 0.0, 1.0)
    free = _number(doc, "free_thresh", src, 0.0, 1.0)
    if free > occupied:
        raise MapError("free_thresh", free, f"must be <= occupied_thresh ({occupied:g})",
                       source=src)
    mode = doc["mode"]
    if mode not in MODES:
        raise MapError("mode", mode, f"must be one of {', '.join(MODES)}", source=src)
    return MapFile(p, image_path, resolution, (origin[0], origin[1]), bool(negate), occupied,
                   free, mode, yaw)


def _origin(v: Any, src: str) -> tuple[float, float, float]:
    if not isinstance(v, list) or len(v) != 3:
        raise MapError("origin", v, "must be a list of 3 numbers [x, y, yaw]", source=src)
    x, y, yaw = (_finite(c, f"origin[{i}]", src) for i, c in enumerate(v))
    for i, c in enumerate((x, y)):
        if abs(c) > MAX_ORIGIN:
            raise MapError(f"origin[{i}]", c, f"must be within +-{MAX_ORIGIN:g} m", source=src)
    return x, y, yaw

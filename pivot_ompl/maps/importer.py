"""A ROS ``map_server`` map turned into a scene: :func:`scene_from_map`, :func:`import_map`.

The scene keeps the map's frame: its coordinates are those a user reads in RViz on the map
(``origin`` places the image's lower-left pixel), and the start and goal are given in it.
The floor area (``bounds``) is the smallest rectangle of whole cells holding every free
cell; every other cell inside it (occupied or unknown, see :mod:`~pivot_ompl.maps.occupancy`)
is covered by box obstacles, exact to the cell and few (:mod:`~pivot_ompl.maps.rectangles`),
after the optional cleaning (:mod:`~pivot_ompl.maps.cleaning`); a map whose origin has a yaw
is turned by it (:mod:`~pivot_ompl.maps.placement`). What was read and done is returned as
header lines for the scene file (:attr:`MapImport.header`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pivot_ompl.errors import MapError, counted, require_type
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.maps.cleaning import CleaningReport, MapCleaning, clean_blocked, close_gaps
from pivot_ompl.maps.mapfile import MapFile, read_map_yaml
from pivot_ompl.maps.occupancy import free_cells
from pivot_ompl.maps.placement import ImageFrame, check_pose
from pivot_ompl.maps.rectangles import cell_rectangles
from pivot_ompl.scene import MAX_EXTENT, MAX_OBSTACLES, MAX_SIZE, MIN_SIZE, Scene, scene_from_dict
from pivot_ompl.scene import check_pose as scene_pose

logger = logging.getLogger(__name__)

#: Height of the walls (m) unless given.
DEFAULT_HEIGHT = 2.0
#: The box unless given: the regrasp paper's Fig. 10 box (m), its 0.4 m side passing slots.
DEFAULT_BOX = (0.8, 0.4, 1.0)


@dataclass(frozen=True)
class MapImport:
    """A map imported as a scene, with what was read and done.

    Attributes:
        scene: the scene (map frame; ``source`` is the map's YAML file).
        map: the validated YAML file.
        image_size: ``(width, height)`` of the image (pixels).
        crop: ``(row0, col0, row1, col1)`` of the image cells inside ``scene.bounds``
            (end-exclusive; row 0 is the image's top).
        free_cells: free cells inside the floor area after cleaning.
        blocked_cells: obstacle cells inside the floor area after cleaning.
        cleaning: what cleaning was asked for.
        cleaned: what it removed.
        image_sha256: SHA-256 (hex) of the image file.
    """

    scene: Scene
    map: MapFile
    image_size: tuple[int, int]
    crop: tuple[int, int, int, int]
    free_cells: int
    blocked_cells: int
    cleaning: MapCleaning
    cleaned: CleaningReport
    image_sha256: str

    @property
    def header(self) -> str:
        """Comment lines for the scene file: the source map, its reading and the cleaning."""
        m, (w, h) = self.map, self.image_size
        c, k = self.cleaning, self.cleaned
        parts = []
        if c.specks > 0:
            parts.append(f"specks of at most {c.specks:g} m2 made free ({k.specks} groups, "
                         f"{k.speck_cells} cells)")
        if c.streaks > 0:
            parts.append(f"dangling one-cell lines of at most {c.streaks:g} m made free "
                         f"({k.streaks} lines, {k.streak_cells} cells)")
        if c.gaps > 0:
            parts.append(f"free gaps narrower than {c.gaps:g} m made blocked "
                         f"({k.gap_cells} cells)")
        return "\n".join([
            f"Imported from the ROS map_server map {m.path.name} by pivot-ompl import-map.",
            f"source: image {m.image.name} ({w} x {h} px, sha256 {self.image_sha256[:16]}...), "
            f"resolution {m.resolution:g} m/px, origin [{m.origin[0]:g}, {m.origin[1]:g}, "
            f"{m.yaw:g}], "
            f"mode {m.mode}, negate {int(m.negate)}, occupied_thresh {m.occupied_thresh:g}, "
            f"free_thresh {m.free_thresh:g}",
            f"reading: free cells are floor, occupied and unknown cells are obstacles; "
            f"{counted(len(self.scene.obstacles), 'box', 'boxes')} exact to the cell over "
            f"{self.blocked_cells} cells; the floor area is the free cells' bounding "
            f"rectangle (image rows {self.crop[0]}..{self.crop[2] - 1}, columns "
            f"{self.crop[1]}..{self.crop[3] - 1})",
            "cleaning: " + ("; ".join(parts) if parts else "none"),
            "frame: the map's (poses as read in RViz on this map)",
        ])


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _crop(free: np.ndarray, src: str, image: str) -> tuple[int, int, int, int]:
    rows = np.flatnonzero(free.any(axis=1))
    if rows.size == 0:
        raise MapError("image", image, "has no free cell (nothing to plan on: check negate, "
                       "the thresholds and the cleaning of gaps)", source=src)
    cols = np.flatnonzero(free.any(axis=0))
    return int(rows[0]), int(cols[0]), int(rows[-1]) + 1, int(cols[-1]) + 1


def _check_sizes(height: float, box: Sequence[float]) -> tuple[float, float, float]:
    if isinstance(height, bool) or not isinstance(height, int | float) or not (
            MIN_SIZE <= height <= MAX_SIZE):
        raise MapError("height", height, f"must be a number within [{MIN_SIZE:g}, "
                       f"{MAX_SIZE:g}] m")
    if not isinstance(box, Sequence) or isinstance(box, str) or len(box) != 3:
        raise MapError("box", box, "must be 3 numbers [width, depth, height] (m)")
    for i, v in enumerate(box):
        if isinstance(v, bool) or not isinstance(v, int | float) or not (
                MIN_SIZE <= v <= MAX_SIZE):
            raise MapError(f"box[{i}]", v, f"must be a number within [{MIN_SIZE:g}, "
                           f"{MAX_SIZE:g}] m")
    return float(box[0]), float(box[1]), float(box[2])


def import_map(map_file: str | Path, *, start: Sequence[float], goal: Sequence[float],
               height: float = DEFAULT_HEIGHT, box: Sequence[float] = DEFAULT_BOX,
               cleaning: MapCleaning | None = None, name: str | None = None) -> MapImport:
    """Read a ``map_server`` map and build its scene (see the module docstring).

    Args:
        map_file: the map's YAML file.
        start: the box's start pose ``(x, y, yaw)`` in the map frame (m, rad).
        goal: the box's goal pose, likewise.
        height: height of every obstacle (m).
        box: the box's size ``(width, depth, height)`` (m), as a scene's ``object.size``.
        cleaning: optional cleaning of specks and streaks (none by default).
        name: the scene's name (default: the YAML file's stem, or its folder's name when
            the stem is ``map``).

    Raises:
        MapError: a bad map (naming the YAML field and its value), a map too large for a
            scene (over the scene's 200 m a side or its obstacle limit), a start or goal
            outside the free area or overlapping an obstacle.
        InputError: a bad pose, height, box size or name.
    """
    cleaning = MapCleaning() if cleaning is None else cleaning
    require_type(cleaning, MapCleaning, "cleaning", "a MapCleaning")
    size = _check_sizes(height, box)
    for fld, v in (("cleaning.specks", cleaning.specks), ("cleaning.streaks", cleaning.streaks),
                   ("cleaning.gaps", cleaning.gaps)):
        if not (isinstance(v, int | float) and not isinstance(v, bool) and 0 <= v < 1e6):
            raise MapError(fld, v, "must be a number >= 0")
    start_pose = scene_pose(start, field="start")
    goal_pose = scene_pose(goal, field="goal")
    mapfile = read_map_yaml(map_file)
    src, res = str(mapfile.path), mapfile.resolution
    free = free_cells(mapfile)
    image_h, image_w = free.shape
    gap_cells = close_gaps(free, cleaning.gaps, res) if cleaning.gaps > 0 else 0
    r0, c0, r1, c1 = _crop(free, src, mapfile.image.name)
    frame = ImageFrame(mapfile.origin, mapfile.yaw, res, image_h)
    bounds, outside = frame.floor((r0, c0, r1, c1), float(height))
    width, depth = bounds[2] - bounds[0], bounds[3] - bounds[1]
    if max(width, depth) > MAX_EXTENT:
        raise MapError("image", f"{mapfile.image.name} ({image_w} x {image_h} px)",
                       f"its free area spans {width:.1f} x {depth:.1f} m: a scene is at most "
                       f"{MAX_EXTENT:g} m on a side", source=src)
    blocked = ~free[r0:r1, c0:c1]
    del free
    report = dataclasses.replace(clean_blocked(blocked, cleaning, res), gap_cells=gap_cells)
    rects = cell_rectangles(blocked)
    n_blocked = int(np.count_nonzero(blocked))
    n_free = blocked.size - n_blocked
    del blocked
    if len(rects) + len(outside) > MAX_OBSTACLES:
        raise MapError("image", mapfile.image.name, f"gives {len(rects) + len(outside)} boxes, "
                       f"more than a scene's {MAX_OBSTACLES}: clean it (--clean specks, "
                       "streaks, gaps)", source=src)
    boxes = frame.boxes(frame.local_rectangles(rects, (r0, c0, r1, c1)), float(height))
    boxes += outside
    if name is None:
        stem = mapfile.path.stem
        name = mapfile.path.parent.name if stem == "map" and mapfile.path.parent.name else stem
    if not isinstance(name, str) or not name:
        raise MapError("name", name, "must be a non-empty string")
    model = BoxGraspModel(size)
    check_pose(start_pose, "start", model, bounds, boxes)
    check_pose(goal_pose, "goal", model, bounds, boxes)
    doc = {"name": name, "bounds": list(bounds), "object": {"size": list(size)},
           "start": list(start_pose), "goal": list(goal_pose)}
    base = scene_from_dict(doc, source=src)
    scene = Scene(base.name, base.bounds, base.model, base.start, base.goal, tuple(boxes),
                  base.alpha_max, base.turning_radius, base.robot_model, src, walk=base.walk)
    logger.info("%s: %d x %d px, %s over %d blocked cells", mapfile.path.name, image_w,
                image_h, counted(len(boxes), "box", "boxes"), n_blocked)
    return MapImport(scene, mapfile, (image_w, image_h), (r0, c0, r1, c1), n_free, n_blocked,
                     cleaning, report, _sha256(mapfile.image))


def scene_from_map(map_file: str | Path, *, start: Sequence[float], goal: Sequence[float],
                   height: float = DEFAULT_HEIGHT, box: Sequence[float] = DEFAULT_BOX,
                   cleaning: MapCleaning | None = None, name: str | None = None) -> Scene:
    """The scene of a ``map_server`` map: :func:`import_map`'s ``scene`` (same arguments)."""
    return import_map(map_file, start=start, goal=goal, height=height, box=box,
                      cleaning=cleaning, name=name).scene

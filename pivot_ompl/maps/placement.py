"""Image cells placed in the map frame: the floor area, the boxes, the poses on them.

A cell's corner at image row ``r`` and column ``c`` (row 0 the top of an image ``H`` rows
high) lies at ``(c, H - r) * resolution`` in the image's own frame, which ``origin``
``[x, y, yaw]`` places in the map frame: ``p_map = (x, y) + R(yaw) p_image``. With yaw 0 the
boxes are axis-aligned and the floor area is exactly the kept cells. With another yaw every
box is turned by it, the floor area (axis-aligned, as scenes have it) is the bounding box of
the kept cells, and four more boxes of that yaw, outside the kept cells' rectangle, block the
corners of the floor area that the image does not cover.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from pivot_ompl.errors import MapError
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import BoxObstacle
from pivot_ompl.se2 import Pose, wrap_angle

#: Decimals kept of a coordinate (m): far below any resolution, it only drops the round-off
#: of ``origin + index * resolution`` (no 5.699999999999999).
DIGITS = 9


@dataclass(frozen=True)
class ImageFrame:
    """Where an image's cells lie in the map frame.

    Attributes:
        origin: map-frame ``(x, y)`` of the image's lower-left corner (m).
        yaw: the image's rotation in the map frame (rad).
        resolution: metres per cell.
        height: the image's rows.
    """

    origin: tuple[float, float]
    yaw: float
    resolution: float
    height: int

    def to_map(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Image-frame points (m) in the map frame, rounded to :data:`DIGITS` decimals."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        if self.yaw == 0.0:
            c, s = 1.0, 0.0
        return (np.round(self.origin[0] + c * x - s * y, DIGITS),
                np.round(self.origin[1] + s * x + c * y, DIGITS))

    def local_rectangles(self, rects: np.ndarray, crop: tuple[int, int, int, int]
                         ) -> np.ndarray:
        """Cell rectangles ``[row0, col0, row1, col1]`` of the crop, as image-frame boxes.

        Returns ``[x0, y0, x1, y1]`` (m) per rectangle.
        """
        r0, c0 = crop[0], crop[1]
        res, h = self.resolution, self.height
        return np.stack([(c0 + rects[:, 1]) * res, (h - r0 - rects[:, 2]) * res,
                         (c0 + rects[:, 3]) * res, (h - r0 - rects[:, 0]) * res], axis=1)

    def boxes(self, local: np.ndarray, height: float) -> list[BoxObstacle]:
        """Boxes over image-frame rectangles ``[x0, y0, x1, y1]``, placed in the map frame."""
        cx, cy = self.to_map(0.5 * (local[:, 0] + local[:, 2]), 0.5 * (local[:, 1] + local[:, 3]))
        w = np.round(local[:, 2] - local[:, 0], DIGITS)
        d = np.round(local[:, 3] - local[:, 1], DIGITS)
        yaw = float(wrap_angle(self.yaw)) if self.yaw else 0.0
        return [BoxObstacle((x, y), (a, b), yaw, float(height))
                for x, y, a, b in zip(cx.tolist(), cy.tolist(), w.tolist(), d.tolist(),
                                      strict=True)]

    def floor(self, crop: tuple[int, int, int, int], height: float
              ) -> tuple[tuple[float, float, float, float], list[BoxObstacle]]:
        """The floor area of the cells of ``crop`` and the boxes blocking what is not image."""
        (x0, y0, x1, y1), = self.local_rectangles(
            np.array([[0, 0, crop[2] - crop[0], crop[3] - crop[1]]]), crop).tolist()
        xs, ys = self.to_map(np.array([x0, x1, x1, x0]), np.array([y0, y0, y1, y1]))
        bounds = (float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max()))
        if self.yaw == 0.0:
            return bounds, []
        reach = max(bounds[2] - bounds[0], bounds[3] - bounds[1])
        outside = np.array([[x0 - reach, y0 - reach, x0, y1 + reach],
                            [x1, y0 - reach, x1 + reach, y1 + reach],
                            [x0, y0 - reach, x1, y0], [x0, y1, x1, y1 + reach]])
        return bounds, self.boxes(outside, height)


def box_polygons(boxes: list[BoxObstacle]) -> np.ndarray:
    """The boxes' footprints as shapely polygons."""
    if not boxes:
        return np.array([], dtype=object)
    centre = np.array([o.center for o in boxes])
    half = 0.5 * np.array([o.size for o in boxes])
    yaw = np.array([o.yaw for o in boxes])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    signs = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    u = signs[None, :, 0] * half[:, 0:1]
    v = signs[None, :, 1] * half[:, 1:2]
    corners = np.stack([centre[:, 0:1] + c * u - s * v, centre[:, 1:2] + s * u + c * v], axis=2)
    return shapely.polygons(corners)


def check_pose(pose: Pose, fld: str, model: BoxGraspModel,
               bounds: tuple[float, float, float, float], boxes: list[BoxObstacle]) -> None:
    """Refuse a pose whose box footprint leaves the floor area or overlaps an obstacle.

    Raises:
        MapError: naming ``fld``, the pose, and the floor area or the obstacle in the way.
    """
    corners = model.object_corners(pose)
    b = bounds
    if any(not (b[0] - 1e-9 <= x <= b[2] + 1e-9 and b[1] - 1e-9 <= y <= b[3] + 1e-9)
           for x, y in corners):
        raise MapError(fld, list(pose), "the box leaves the map's free area "
                       f"(x {b[0]:g}..{b[2]:g}, y {b[1]:g}..{b[3]:g} m in the map frame)")
    if not boxes:
        return
    footprint = shapely.Polygon(corners)
    polygons = box_polygons(boxes)
    for i in shapely.STRtree(polygons).query(footprint, predicate="intersects"):
        if shapely.intersection(footprint, polygons[i]).area > 1e-12:
            o = boxes[int(i)]
            raise MapError(fld, list(pose), "the box overlaps an occupied or unknown cell of "
                           f"the map (an obstacle at x {o.center[0]:g}, y {o.center[1]:g} m, "
                           f"{o.size[0]:g} x {o.size[1]:g} m)")

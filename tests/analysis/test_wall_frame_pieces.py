"""A turned map of thousands of boxes gets its walls' frame; finding its free floor polls the stop.

The Willow Garage office (5049 boxes) turned by 0.5 rad had no frame (the free floor was not
tried beyond 4000 pieces): its lattice lay across its walls and its plan timed out.
"""

from __future__ import annotations

import math

from factories import make_scene

from pivot_ompl.analysis.wall_frame import MAX_PIECES, UNION_CHUNK, wall_frame
from pivot_ompl.generate import rotate_scene
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import drop_shared

RES = 0.1


def _many_boxes(n: int) -> Scene:
    """A 20 x 12 m floor with ``n`` one-cell boxes apart on a 0.1 m map grid, off the ends' row."""
    cells = [(i, j) for i in range(0, 200, 2) for j in range(0, 120, 2)
             if not 2.2 < j * RES < 3.8]
    boxes = [{"type": "box", "center": [(i + 0.5) * RES, (j + 0.5) * RES],
              "size": [RES, RES], "height": 1.0} for i, j in cells[:n]]
    assert len(boxes) == n
    return make_scene(obstacles=boxes, bounds=[0.0, 0.0, 20.0, 12.0])


def test_a_turned_floor_of_more_than_4000_boxes_gets_the_frame_of_its_walls():
    n = 4200
    assert n < MAX_PIECES
    scene = rotate_scene(_many_boxes(n), 0.5)
    frame = wall_frame(scene, worth=math.inf, floor_grid=RES, facing=True)
    assert frame is not None and abs(frame.yaw - 0.5) < 1e-9


def test_the_free_floor_polls_the_stop_between_chunks_of_pieces():
    scene = rotate_scene(_many_boxes(3 * UNION_CHUNK), 0.5)
    drop_shared(scene, ("free floor",))
    asked = []

    def stop() -> bool:
        asked.append(1)
        return len(asked) > 12

    assert wall_frame(scene, worth=math.inf, floor_grid=RES, should_stop=stop) is None
    assert len(asked) > 12  # asked on, and stopped within, the union
    drop_shared(scene, ("free floor",))
    assert wall_frame(scene, worth=math.inf, floor_grid=RES) is not None

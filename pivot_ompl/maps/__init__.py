"""ROS ``map_server`` occupancy maps (YAML + PGM/PNG image) imported as scenes.

:func:`scene_from_map` and :func:`import_map` (:mod:`~pivot_ompl.maps.importer`) read a map
(:mod:`~pivot_ompl.maps.mapfile`, :mod:`~pivot_ompl.maps.occupancy`), optionally clean it
(:mod:`~pivot_ompl.maps.cleaning`), cover its obstacle cells with few boxes
(:mod:`~pivot_ompl.maps.rectangles`) and place them in the map frame
(:mod:`~pivot_ompl.maps.placement`). See ``docs/maps.md``.
"""

from pivot_ompl.maps.cleaning import CleaningReport, MapCleaning
from pivot_ompl.maps.importer import MapImport, import_map, scene_from_map
from pivot_ompl.maps.mapfile import MapFile, read_map_yaml

__all__ = ["CleaningReport", "MapCleaning", "MapFile", "MapImport", "import_map",
           "read_map_yaml", "scene_from_map"]

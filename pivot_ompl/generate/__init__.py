"""Scene generator: families of scenes that come with a witness plan (known solvable).

``generate("walls", seed=3)`` gives a :class:`Generated` (scene and witness);
:func:`write_generated` writes ``<name>.yaml`` and ``<name>.witness.json``
(:func:`write_all_generated` those of several scenes, all or nothing); :func:`rotate_scene` and
:func:`mirror_scene` make rigid copies of any scene.
"""

from pivot_ompl.generate.families import FAMILIES, Generated, GeneratorParams, generate
from pivot_ompl.generate.output import write_all_generated, write_generated
from pivot_ompl.generate.sceneio import scene_to_dict, write_scene
from pivot_ompl.generate.transform import RigidMap, mirror_scene, rotate_scene, transform_scene
from pivot_ompl.generate.witness import build_witness

__all__ = ["FAMILIES", "Generated", "GeneratorParams", "RigidMap", "build_witness", "generate",
           "mirror_scene", "rotate_scene", "scene_to_dict", "transform_scene",
           "write_all_generated", "write_generated", "write_scene"]

"""The ``pivot-plan/1`` JSON plan file: dataclasses, writer and reader.

Format (a contract read by outside tools)::

    {"format": "pivot-plan/1", "scene": <name>, "status": "exact" | "approximate" | "none",
     "object_size": [w, d, h], "robot_footprint": [depth, width], "standoff": s,
     "alpha_max": a,
     "phases": [
       {"type": "transfer", "grasp": k, "robot_start": [x, y, yaw],
        "steps": [{"pivot": [px, py], "angle": a, "object": [x, y, yaw],
                   "robot": [x, y, yaw]}, ...]},
       {"type": "transit", "from_grasp": k, "to_grasp": j,
        "robot_path": [[x, y, yaw], ...]}]}

A step's ``object``/``robot`` are the poses *after* the rotation; ``angle`` is signed (rad,
counter-clockwise positive) about the vertical through the world point ``pivot``. Lengths in
metres, angles in radians, numbers at full double precision. Consecutive ``robot_path`` poses
are joined by straight-line motion of the robot's centre with the yaw interpolated linearly
along the shorter way round. Extra fields are kept in :attr:`Plan.extra`.

Optional extra field ``quality`` (written by ``pivot-ompl plan``; plans without it load as
before): the plan's figures and cost, :func:`pivot_ompl.quality.plan_quality` (which says
what each field means).

Optional field ``robot_model`` (written when the plan is not for the default model, HRP-2;
plans without it are HRP-2's): the humanoid profile the plan was made for
(:mod:`pivot_ompl.humanoids`, ``pivot-ompl robots``).

Optional extra fields ``scene_path`` and ``scene_sha256`` (written by ``plan``, ``steer``,
``replan`` and ``generate``; plans without them load as before): the scene file the plan was
made from, relative to the plan file's folder (an absolute path is read as it is), and the
scene's :func:`~pivot_ompl.scene.scene_digest`. In memory :attr:`Plan.extra` holds the path
absolute: :meth:`Plan.to_json` writes it relative to the new file, :func:`load_plan` resolves
it against the file read.

Reading is strict (:mod:`pivot_ompl.fileio`): UTF-8, no duplicate key, no ``NaN``; every number
must be finite and within +-:data:`MAX_VALUE` (metres or radians), else :class:`PlanFileError`.

Modules: :mod:`~pivot_ompl.planfile.phases` (transfer and transit phases),
:mod:`~pivot_ompl.planfile.plan` (the plan and its writing), :mod:`~pivot_ompl.planfile.reading`
(documents and files read).
"""

from pivot_ompl.planfile.phases import Phase, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.planfile.plan import FORMAT, STATUSES, Plan
from pivot_ompl.planfile.reading import MAX_VALUE, load_plan, plan_from_dict

__all__ = ["FORMAT", "MAX_VALUE", "STATUSES", "Phase", "Plan", "TransferPhase", "TransferStep",
           "TransitPhase", "load_plan", "plan_from_dict"]

"""A ``pivot-plan/1`` plan in memory, and its writing (:mod:`pivot_ompl.planfile`: the format).

:meth:`Plan.to_dict` is the document, :meth:`Plan.to_text` its JSON text (the scene's path
made relative to the folder written to), :meth:`Plan.to_json` the file, replaced only once
completely written.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pivot_ompl.argcheck import guard as _guard
from pivot_ompl.argcheck import guard_all as _guard_all
from pivot_ompl.errors import InputError
from pivot_ompl.fileio import atomic_output
from pivot_ompl.fileio.json_text import json_text
from pivot_ompl.humanoids import DEFAULT_MODEL
from pivot_ompl.planfile.phases import Phase, TransferPhase, TransitPhase
from pivot_ompl.se2 import Pose

__all__ = ["FORMAT", "STATUSES", "Plan"]

FORMAT = "pivot-plan/1"
STATUSES = ("exact", "approximate", "none")


@dataclass
class Plan:
    """A plan in memory; :meth:`to_json` writes ``pivot-plan/1``.

    Attributes:
        scene: scene name.
        status: ``"exact"`` (reaches the goal), ``"approximate"`` or ``"none"``.
        object_size, robot_footprint, standoff, alpha_max: geometry the plan was made with.
        start: the object's start pose.
        phases: transfer and transit phases in order.
        extra: further top-level fields (planner, seed, timings...).
        robot_model: the humanoid the plan is for (its profile's name); written as the
            optional field ``robot_model`` when it is not the default model's.
    """

    scene: str
    status: str
    object_size: tuple[float, float, float]
    robot_footprint: tuple[float, float]
    standoff: float
    alpha_max: float
    start: Pose
    phases: list[Phase] = field(default_factory=list)
    extra: dict[str, Any] = field(default_factory=dict)
    robot_model: str = DEFAULT_MODEL

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a wrong field (the phases check their own)."""
        for name in ("scene", "robot_model"):
            if not isinstance(getattr(self, name), str):
                raise InputError(f"Plan.{name}", getattr(self, name), "must be a string")
        if self.status not in STATUSES:
            raise InputError("Plan.status", self.status, f"must be one of {STATUSES}")
        _guard("Plan", object_size=(self.object_size, 3), robot_footprint=(
            self.robot_footprint, 2), standoff=(self.standoff, None), alpha_max=(
            self.alpha_max, None), start=(self.start, 3))
        _guard_all("Plan", "phases", self.phases, TransferPhase | TransitPhase)
        if not isinstance(self.extra, dict):
            raise InputError("Plan.extra", self.extra, "must be a dict")

    @property
    def pivots(self) -> int:
        """Number of pivot rotations."""
        return sum(len(p.steps) for p in self.phases if isinstance(p, TransferPhase))

    @property
    def regrasps(self) -> int:
        """Number of grasp changes (transit phases)."""
        return sum(1 for p in self.phases if isinstance(p, TransitPhase))

    @property
    def object_end(self) -> Pose:
        """Object pose at the end of the plan."""
        pose = self.start
        for p in self.phases:
            if isinstance(p, TransferPhase):
                pose = p.object_end
        return pose

    def to_dict(self) -> dict[str, Any]:
        """The ``pivot-plan/1`` document as a JSON-ready dict."""
        phases: list[dict[str, Any]] = []
        for p in self.phases:
            if isinstance(p, TransferPhase):
                d: dict[str, Any] = {
                    "type": "transfer", "grasp": p.grasp, "robot_start": list(p.robot_start),
                    "steps": [{"pivot": list(s.pivot), "angle": s.angle,
                               "object": list(s.object), "robot": list(s.robot)}
                              for s in p.steps]}
                if p.rs_path:
                    d["rs_path"] = [list(q) for q in p.rs_path]
                phases.append(d)
            else:
                phases.append({"type": "transit", "from_grasp": p.from_grasp,
                               "to_grasp": p.to_grasp,
                               "robot_path": [list(q) for q in p.robot_path]})
        doc: dict[str, Any] = {
            "format": FORMAT, "scene": self.scene, "status": self.status,
            "object_size": list(self.object_size), "robot_footprint": list(self.robot_footprint),
            "standoff": self.standoff, "alpha_max": self.alpha_max,
            "start": list(self.start), "phases": phases}
        if self.robot_model != DEFAULT_MODEL:
            doc["robot_model"] = self.robot_model
        for k, v in self.extra.items():
            doc.setdefault(k, v)
        return doc

    def to_text(self, *, folder: str | Path | None = None) -> str:
        """The ``pivot-plan/1`` document as JSON text (full double precision).

        ``folder``: where the text will be written; ``scene_path`` is then written relative
        to it (the plan and its scene can move together).
        """
        doc = self.to_dict()
        scene_path = doc.get("scene_path")
        if folder is not None and isinstance(scene_path, str) and os.path.isabs(scene_path):
            try:
                doc["scene_path"] = Path(os.path.relpath(scene_path,
                                                         Path(folder).resolve())).as_posix()
            except ValueError:  # another drive (Windows): keep it absolute
                pass
        return json_text(doc)

    def to_json(self, path: str | Path) -> Path:
        """Write the plan to ``path`` (full double precision); return the path.

        ``scene_path`` is written relative to the plan file's folder. The file is replaced
        only once completely written (a temporary file moved into place).
        """
        path = Path(path)
        with atomic_output(path) as tmp:
            tmp.write_text(self.to_text(folder=path.parent), encoding="utf-8")
        return path

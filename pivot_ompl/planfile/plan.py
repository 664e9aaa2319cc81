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
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pivot_ompl.argcheck import guard as _guard
from pivot_ompl.argcheck import guard_all as _guard_all
from pivot_ompl.errors import InputError, PlanFileError
from pivot_ompl.fileio import atomic_output, input_path, load_json
from pivot_ompl.fileio.json_text import json_text
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES
from pivot_ompl.se2 import Pose

FORMAT = "pivot-plan/1"
STATUSES = ("exact", "approximate", "none")
#: Largest magnitude of any number of a plan (m or rad): the scenes' coordinate limit.
MAX_VALUE = 1.0e4


@dataclass(frozen=True)
class TransferStep:
    """One pivot rotation of a transfer phase (poses after the rotation)."""

    pivot: tuple[float, float]
    angle: float
    object: Pose
    robot: Pose

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a field that is not finite numbers."""
        _guard("TransferStep", pivot=(self.pivot, 2), angle=(self.angle, None),
               object=(self.object, 3), robot=(self.robot, 3))


@dataclass(frozen=True)
class TransferPhase:
    """The robot holds the box at ``grasp`` and pivots it through ``steps``.

    Attributes:
        grasp: grasp index (0..3).
        robot_start: robot pose at the phase start.
        steps: the rotations.
        object_start: object pose at the phase start (not written: the previous phase's end).
        rs_path: optional car poses along the Reeds-Shepp path(s), for plotting.
    """

    grasp: int
    robot_start: Pose
    steps: tuple[TransferStep, ...]
    object_start: Pose
    rs_path: tuple[Pose, ...] = ()

    type = "transfer"

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a wrong field."""
        _guard("TransferPhase", grasp=(self.grasp, -1), robot_start=(self.robot_start, 3),
               object_start=(self.object_start, 3))
        _guard_all("TransferPhase", "steps", self.steps, TransferStep)
        _guard_all("TransferPhase", "rs_path", self.rs_path)

    @property
    def object_end(self) -> Pose:
        """Object pose at the end of the phase."""
        return self.steps[-1].object if self.steps else self.object_start

    @property
    def robot_end(self) -> Pose:
        """Robot pose at the end of the phase."""
        return self.steps[-1].robot if self.steps else self.robot_start


@dataclass(frozen=True)
class TransitPhase:
    """The robot walks alone from grasp ``from_grasp`` to ``to_grasp`` of the resting box."""

    from_grasp: int
    to_grasp: int
    robot_path: tuple[Pose, ...]
    object_pose: Pose

    type = "transit"

    def __post_init__(self) -> None:
        """Raise :class:`InputError` naming a wrong field."""
        _guard("TransitPhase", from_grasp=(self.from_grasp, -1), to_grasp=(self.to_grasp, -1),
               object_pose=(self.object_pose, 3))
        _guard_all("TransitPhase", "robot_path", self.robot_path)

    @property
    def length(self) -> float:
        """Walking distance of the robot's centre (m)."""
        p = self.robot_path
        return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(p, p[1:], strict=False))


Phase = TransferPhase | TransitPhase


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


# -- reading -----------------------------------------------------------------------------

def _num(v: Any, fld: str, src: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise PlanFileError(fld, v, "must be a finite number", source=src)
    try:
        x = float(v)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        raise PlanFileError(fld, v, "must be a finite number", source=src)
    if abs(x) > MAX_VALUE:
        raise PlanFileError(fld, v, f"must be within +-{MAX_VALUE:g}", source=src)
    return x


def _vec(v: Any, n: int, fld: str, src: str) -> tuple[float, ...]:
    if not isinstance(v, list) or len(v) != n:
        raise PlanFileError(fld, v, f"must be a list of {n} numbers", source=src)
    return tuple(_num(x, f"{fld}[{i}]", src) for i, x in enumerate(v))


def _grasp(v: Any, fld: str, src: str) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 3:
        raise PlanFileError(fld, v, "must be a grasp index 0..3", source=src)
    return v


def _steps(raw: Any, f: str, src: str) -> list[TransferStep]:
    """The ``steps`` list of the transfer phase ``f``."""
    if not isinstance(raw, list):
        raise PlanFileError(f"{f}.steps", raw, "must be a list", source=src)
    steps = []
    for j, st in enumerate(raw):
        fs = f"{f}.steps[{j}]"
        if not isinstance(st, dict):
            raise PlanFileError(fs, st, "must be an object", source=src)
        steps.append(TransferStep(
            _vec(st.get("pivot"), 2, f"{fs}.pivot", src),  # type: ignore[arg-type]
            _num(st.get("angle"), f"{fs}.angle", src),
            _vec(st.get("object"), 3, f"{fs}.object", src),  # type: ignore[arg-type]
            _vec(st.get("robot"), 3, f"{fs}.robot", src)))  # type: ignore[arg-type]
    return steps


def plan_from_dict(doc: Any, *, source: str = "") -> Plan:
    """Parse a ``pivot-plan/1`` document.

    The object's start pose is the ``start`` field if present, else it is recovered from the
    first transfer phase's ``robot_start`` and grasp (the plan's geometry fixes the offset).

    Raises:
        PlanFileError: naming the field and value that are wrong.
    """
    from pivot_ompl.grasp import BoxGraspModel  # local: grasp imports nothing from here

    src = source
    if not isinstance(doc, dict):
        raise PlanFileError("<document>", type(doc).__name__, "must be a JSON object", source=src)
    if doc.get("format") != FORMAT:
        raise PlanFileError("format", doc.get("format"), f"must be {FORMAT!r}", source=src)
    status = doc.get("status")
    if status not in STATUSES:
        raise PlanFileError("status", status, f"must be one of {STATUSES}", source=src)
    for key in ("object_size", "robot_footprint", "standoff", "alpha_max", "phases"):
        if key not in doc:
            raise PlanFileError(key, None, "is required", source=src)
    size = _vec(doc["object_size"], 3, "object_size", src)
    foot = _vec(doc["robot_footprint"], 2, "robot_footprint", src)
    standoff = _num(doc["standoff"], "standoff", src)
    alpha_max = _num(doc["alpha_max"], "alpha_max", src)
    robot_model = doc.get("robot_model", DEFAULT_MODEL)
    if robot_model not in PROFILES:
        raise PlanFileError("robot_model", robot_model,
                            f"unknown robot model (known: {sorted(PROFILES)})", source=src)
    model = BoxGraspModel(size, foot, standoff)  # type: ignore[arg-type]
    raw = doc["phases"]
    if not isinstance(raw, list):
        raise PlanFileError("phases", raw, "must be a list", source=src)
    start: Pose | None = None
    if "start" in doc:
        start = _vec(doc["start"], 3, "start", src)  # type: ignore[assignment]
    phases: list[Phase] = []
    obj: Pose | None = start
    for i, ph in enumerate(raw):
        f = f"phases[{i}]"
        if not isinstance(ph, dict):
            raise PlanFileError(f, ph, "must be an object", source=src)
        kind = ph.get("type")
        if kind == "transfer":
            g = _grasp(ph.get("grasp"), f"{f}.grasp", src)
            rs = _vec(ph.get("robot_start"), 3, f"{f}.robot_start", src)
            if obj is None:  # recover the object's start from the robot's
                h = rs[2]
                r = model.robot_offset(g)
                obj = (rs[0] + r * math.cos(h), rs[1] + r * math.sin(h),
                       h - g * 0.5 * math.pi)
                start = obj
            steps = _steps(ph.get("steps"), f, src)
            rs_raw = ph.get("rs_path", [])
            if not isinstance(rs_raw, list):
                raise PlanFileError(f"{f}.rs_path", rs_raw, "must be a list of [x, y, yaw]",
                                    source=src)
            rsp = tuple(_vec(q, 3, f"{f}.rs_path[{j}]", src) for j, q in enumerate(rs_raw))
            phase = TransferPhase(g, rs, tuple(steps), obj, rsp)  # type: ignore[arg-type]
            phases.append(phase)
            obj = phase.object_end
        elif kind == "transit":
            a = _grasp(ph.get("from_grasp"), f"{f}.from_grasp", src)
            b = _grasp(ph.get("to_grasp"), f"{f}.to_grasp", src)
            path_raw = ph.get("robot_path")
            if not isinstance(path_raw, list) or not path_raw:
                raise PlanFileError(f"{f}.robot_path", path_raw, "must be a non-empty list",
                                    source=src)
            path = tuple(_vec(q, 3, f"{f}.robot_path[{j}]", src) for j, q in enumerate(path_raw))
            if obj is None:
                raise PlanFileError(f"{f}", kind, "a plan without 'start' must begin with a "
                                    "transfer phase", source=src)
            phases.append(TransitPhase(a, b, path, obj))  # type: ignore[arg-type]
        else:
            raise PlanFileError(f"{f}.type", kind, "must be 'transfer' or 'transit'", source=src)
    if start is None:
        raise PlanFileError("start", None, "is required when the plan has no phase", source=src)
    known = {"format", "scene", "status", "object_size", "robot_footprint", "standoff",
             "alpha_max", "start", "phases", "robot_model"}
    extra = {k: v for k, v in doc.items() if k not in known}
    return Plan(str(doc.get("scene", "")), status, size, foot, standoff,  # type: ignore[arg-type]
                alpha_max, start, phases, extra, robot_model)


def load_plan(path: str | Path) -> Plan:
    """Read a ``pivot-plan/1`` file.

    Raises:
        PlanFileError: not a path, unreadable file, invalid JSON or a malformed field.
    """
    path = input_path(path, error=PlanFileError)
    plan = plan_from_dict(load_json(path, error=PlanFileError), source=str(path))
    scene_path = plan.extra.get("scene_path")
    if scene_path is not None and not isinstance(scene_path, str):
        raise PlanFileError("scene_path", scene_path, "must be a path (text)", source=str(path))
    if scene_path:
        plan.extra["scene_path"] = os.path.normpath(path.resolve().parent / scene_path)
    return plan

"""Reading ``pivot-plan/1`` (:mod:`pivot_ompl.planfile`: the format), strictly.

Every field is checked and a wrong one named with its value (:class:`PlanFileError`): numbers
finite and within +-:data:`MAX_VALUE`, vectors of their length, grasps ``0..3``; a plan
without ``start`` has its object's start recovered from its first transfer.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from pivot_ompl.errors import PlanFileError
from pivot_ompl.fileio import input_path, load_json
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES
from pivot_ompl.planfile.phases import Phase, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.planfile.plan import FORMAT, STATUSES, Plan
from pivot_ompl.se2 import Pose

__all__ = ["MAX_VALUE", "load_plan", "plan_from_dict"]

#: Largest magnitude of any number of a plan (m or rad): the scenes' coordinate limit.
MAX_VALUE = 1.0e4


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

"""Chapters and the on-screen phase label of a replay.

A replay (plan or whole-body motion) is a time line of samples, each tagged with the plan
phase it belongs to and the pivot step being rotated in that phase (``-1`` between
rotations). :func:`replay_guide` turns those tags into

* **chapters**: one per phase (``transfer k/T · 18 pivots``, ``regrasp k/R · walk 3.2 m``)
  plus key moments (the start when no phase starts at once, each phase's narrowest passage,
  the goal reached), each with the replay time to seek to;
* **marks**: the label shown on screen from a time on (``transfer 3/5 · pivot 41/84``),
  one per change of phase or pivot, and the end's (``goal reached · 84 pivots, 1 regrasp``)
  at the last sample.

The HTML overlay (:mod:`pivot_ompl.viz.overlay`) reads the guide as JSON; notebooks can use
:meth:`ReplayGuide.label_at` and :attr:`ReplayGuide.chapters` directly.
"""

from __future__ import annotations

import bisect
import logging
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError, counted, require_type
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: Chapter kinds: a transfer phase, a regrasp (transit) phase, or a key moment.
KINDS = ("transfer", "regrasp", "moment")


@dataclass(frozen=True)
class Chapter:
    """A place in the replay a viewer can jump to.

    Attributes:
        time: replay time (s) to seek to.
        title: what happens there (``"transfer 2/5 · 18 pivots (grasp 1)"``).
        kind: ``"transfer"``, ``"regrasp"`` or ``"moment"``.
        phase: index of the plan phase (``-1``: none).
    """

    time: float
    title: str
    kind: str
    phase: int = -1

    def to_json(self) -> dict[str, Any]:
        """Plain structure for the page."""
        return {"time": round(self.time, 4), "title": self.title, "kind": self.kind,
                "phase": self.phase}


@dataclass(frozen=True)
class ReplayGuide:
    """Chapters and on-screen labels of one replay.

    Attributes:
        duration: replay length (s).
        chapters: phases and key moments, sorted by time.
        marks: ``(time, label)``: the label shown from that time on, sorted by time.
        bounds: floor area ``(xmin, ymin, xmax, ymax)`` (m) the camera frames on load.
        height: tallest thing on the floor (m), obstacles and robot, for framing.
        extra: further settings for the page's script (JSON values).
    """

    duration: float
    chapters: tuple[Chapter, ...] = ()
    marks: tuple[tuple[float, str], ...] = ()
    bounds: tuple[float, float, float, float] | None = None
    height: float = 1.5
    extra: dict[str, Any] = field(default_factory=dict)

    def label_at(self, t: float) -> str:
        """The label shown at replay time ``t`` (s)."""
        if not self.marks:
            return ""
        i = bisect.bisect_right([m[0] for m in self.marks], t) - 1
        return self.marks[max(i, 0)][1]

    def chapter_at(self, t: float) -> Chapter | None:
        """The last phase chapter (not a key moment) started at or before ``t``."""
        best = None
        for c in self.chapters:
            if c.kind != "moment" and c.time <= t + 1e-9:
                best = c
        return best

    def with_frame(self, bounds: tuple[float, float, float, float],
                   height: float) -> ReplayGuide:
        """The same guide framing ``bounds`` (m) up to ``height`` (m)."""
        x0, y0, x1, y1 = (float(b) for b in bounds)
        return replace(self, bounds=(x0, y0, x1, y1), height=float(height),
                       extra=dict(self.extra))

    def to_json(self) -> dict[str, Any]:
        """The structure the page's script reads (``window.PIVOT_REPLAY``)."""
        return {"duration": round(self.duration, 4),
                "chapters": [c.to_json() for c in self.chapters],
                "marks": [[round(t, 4), s] for t, s in self.marks],
                "bounds": list(self.bounds) if self.bounds is not None else None,
                "height": self.height, **self.extra}


def _phase_titles(plan: Plan | None, n_phases: int) -> tuple[list[str], list[str], list[int]]:
    """Per phase: chapter title, label prefix, and pivots before it (global count)."""
    titles, prefixes, before = [], [], []
    if plan is None:
        for i in range(n_phases):
            titles.append(f"phase {i + 1}/{n_phases}")
            prefixes.append(f"phase {i + 1}/{n_phases}")
            before.append(0)
        return titles, prefixes, before
    n_tr = sum(isinstance(p, TransferPhase) for p in plan.phases)
    n_rg = plan.regrasps
    k_tr = k_rg = piv = 0
    for ph in plan.phases:
        before.append(piv)
        if isinstance(ph, TransferPhase):
            k_tr += 1
            n = len(ph.steps)
            titles.append(f"transfer {k_tr}/{n_tr} · {n} pivot{'s' * (n != 1)} "
                          f"(grasp {ph.grasp})")
            prefixes.append(f"transfer {k_tr}/{n_tr}")
            piv += n
        else:
            k_rg += 1
            titles.append(f"regrasp {k_rg}/{n_rg} · walk {ph.length:.1f} m "
                          f"(grasp {ph.from_grasp}→{ph.to_grasp})")
            prefixes.append(f"regrasp {k_rg}/{n_rg} · walk {ph.length:.1f} m")
    return titles, prefixes, before


def narrowest_steps(plan: Plan, scene: Scene) -> dict[int, tuple[int, float]]:
    """Per transfer phase: the pivot step ending at the smallest clearance, and that clearance.

    Clearance (m) of the box and of the robot's bounding box to the scene's obstacles after
    each rotation (coal distances); phases are keyed by their index in ``plan.phases``.
    Empty when the scene has no obstacle.

    Raises:
        InputError: ``plan`` is not a Plan or ``scene`` not a Scene.
    """
    from pivot_ompl.validity.collision import CollisionWorld

    require_type(plan, Plan, "plan", "a Plan (load_plan)")
    require_type(scene, Scene, "scene", "a Scene (load_scene)")

    if not scene.obstacles:
        return {}
    world = CollisionWorld.from_scene(scene, clearance=0.0)  # true distances
    out: dict[int, tuple[int, float]] = {}
    for i, ph in enumerate(plan.phases):
        if not isinstance(ph, TransferPhase) or not ph.steps:
            continue
        d = [min(world.box_distance(s.object), world.held_distance(s.robot, ph.grasp))
             for s in ph.steps]
        j = int(np.argmin(d))
        out[i] = (j, float(d[j]))
    return out


def replay_guide(times: Sequence[float] | np.ndarray, phase: Sequence[int] | np.ndarray,
                 step: Sequence[int] | np.ndarray | None = None, *, plan: Plan | None = None,
                 scene: Scene | None = None, narrow_below: float = 0.3) -> ReplayGuide:
    """Chapters and labels of a replay sampled at ``times`` (s, from 0, non-decreasing).

    Args:
        times: sample times (s).
        phase: per sample, index of the plan phase (``-1``: before/outside any phase).
        step: per sample, index of the pivot step rotating in that phase (``-1``: none).
        plan: the plan the replay shows; without it phases are only numbered.
        scene: with ``plan``, adds a key moment at each transfer's narrowest passage.
        narrow_below: clearance (m) under which a narrowest passage is a key moment.

    Raises:
        InputError: the arrays differ in length or a phase index is outside the plan.
    """
    t = np.asarray(times, dtype=float)
    ph = np.asarray(phase, dtype=int)
    st = np.full(len(t), -1, dtype=int) if step is None else np.asarray(step, dtype=int)
    if not (len(t) == len(ph) == len(st)):
        raise InputError("phase", f"{len(ph)} samples", f"must match the {len(t)} times")
    if len(t) == 0:
        return ReplayGuide(0.0)
    n_phases = len(plan.phases) if plan is not None else int(ph.max()) + 1
    if ph.max() >= n_phases:
        raise InputError("phase", int(ph.max()), f"the plan has {n_phases} phases")
    titles, prefixes, before = _phase_titles(plan, n_phases)
    total = plan.pivots if plan is not None else 0
    chapters = [Chapter(float(t[0]), "start", "moment")]
    marks: list[tuple[float, str]] = []
    narrow = narrowest_steps(plan, scene) if plan is not None and scene is not None else {}

    # Change points of (phase, step): one label each.
    key = ph.astype(np.int64) * 1_000_003 + st
    change = np.r_[0, np.flatnonzero(np.diff(key)) + 1]
    seen: set[int] = set()
    done = 0  # pivots finished, for labels between rotations
    for i in change:
        p, s, ti = int(ph[i]), int(st[i]), float(t[i])
        if p < 0:
            marks.append((ti, "start" if ti <= t[0] else "standing"))
            continue
        if p not in seen:
            seen.add(p)
            kind = ("regrasp" if plan is not None and isinstance(plan.phases[p], TransitPhase)
                    else "transfer")
            chapters.append(Chapter(ti, titles[p], kind, p))
            done = before[p]
        if plan is not None and isinstance(plan.phases[p], TransferPhase) and total:
            if s >= 0:
                done = before[p] + s
                marks.append((ti, f"{prefixes[p]} · pivot {before[p] + s + 1}/{total}"))
            else:
                marks.append((ti, f"{prefixes[p]} · pivot {done}/{total}"))
            if p in narrow and s == narrow[p][0]:
                j, d = narrow[p]
                if d < narrow_below and not any(c.phase == p and c.kind == "moment"
                                                 for c in chapters):
                    chapters.append(Chapter(ti, f"narrowest passage · {100 * d:.0f} cm clear "
                                                f"({prefixes[p]}, pivot {before[p] + j + 1})",
                                            "moment", p))
            if s >= 0:
                done = before[p] + s + 1
        else:
            marks.append((ti, prefixes[p]))
    end = "goal reached" if plan is not None and plan.status == "exact" else "end"
    chapters.append(Chapter(float(t[-1]), end, "moment"))
    if plan is not None and end == "goal reached":
        end = (f"goal reached · {counted(plan.pivots, 'pivot')}, "
               f"{counted(plan.regrasps, 'regrasp')}")
    marks.append((float(t[-1]), end))  # the label at the end names the end
    if any(c.kind != "moment" and c.time <= t[0] for c in chapters):
        chapters = chapters[1:]  # the first phase starts at once: no separate "start"
    chapters.sort(key=lambda c: (c.time, KINDS.index(c.kind) if c.kind != "moment" else -1))
    return ReplayGuide(float(t[-1]), tuple(chapters), tuple(marks))


def standing_height(model: BoxGraspModel | None, scene: Scene | None) -> float:
    """Tallest thing standing on the floor (m): obstacles, the box and the robot."""
    heights = [model.robot_height, model.object_size[2]] if model is not None else [1.5]
    if scene is not None:
        heights += [o.height for o in scene.obstacles]
    return float(max(heights))

"""Replanning in a warm session against a fresh plan, side by side in one process.

Along the plan of each scene (``--scenes``: fig10, slot, a generated walls scene), at
``--points`` points of its execution (pivot steps spread over its transfers): the box drifted
(5 cm and 5 deg, then 15 cm and 15 deg), an obstacle dropped (a 0.3 m block 1 m ahead of the
box along its heading, or further, :data:`DROP_AHEAD`, where it meets neither the box nor the
robot holding it: a block is not dropped on the robot; none when it meets them everywhere;
where the plan pivots the box backwards the block lands behind it, on the route it came
along), an obstacle removed (the scene's last). For each event: the replan
of a :class:`pivot_ompl.session.PlanningSession` that planned the scene (its roadmaps, checked
motions and route kept: *warm*), that of a new session given only the plan being executed, as
read from its file (what ``pivot-ompl replan`` does in a new process: *cli*), and that of a
fresh session that searches from scratch (``repair=False``: *fresh*), one after the other on
the same changed scene (all start with the grasp the robot holds): success, seconds, whether
the plan passes ``check`` against the changed scene, regrasps and cost (the quality block's
``cost``) of each. Prints one row per event kind and scene (medians) and the ratios of the
medians to the fresh plan's.

**An event where no plan exists is not a failure.** When none of the three finds a plan, the
changed scene is asked whether any plan exists (:func:`no_plan_proof`: the replans' own
``INFEASIBLE``, else the regrasp bound's relaxation and the held poses' proof, within
``--proof-time`` s): such an event counts as *no plan exists (proven)*, apart from the
others; one neither solved nor proven counts as *undecided* (a block dropped by a gap the
box passes narrow side first, in the way of the robot pushing it there, can leave only
passages that the relaxations join and the planners do not find). The success columns count
the events that are not proven to have no plan.

The points are poses of the plan's own pivot steps, some inside gaps the plan passes within
the checks' resolution of the walls (``MIN_CLEARANCE`` of
:mod:`pivot_ompl.checking.refinement`): no new pivot sequence starts there, so a fresh plan
from such a pose fails, while *warm* and *cli* go on with the plan's own rotations.

    python benchmarks/replanning.py [--scenes fig10,slot,gen:walls:1] [--points 10] [--time 30]
        [--events drift,dropped,removed] [--proof-time 60] [--out results/replanning.json]

``--events`` keeps the event kinds whose names contain one of the words (a long run split in
shorter ones).

Run timing figures under ``flock /tmp/pivot-bench.lock``.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()


def _points(plan: Any, n: int) -> list[tuple[tuple[float, float, float], int]]:
    from pivot_ompl.planfile import TransferPhase

    steps = [(st.object, ph.grasp) for ph in plan.phases if isinstance(ph, TransferPhase)
             for st in ph.steps]
    if not steps:
        return []
    return [steps[int(k * (len(steps) - 1) / max(1, n - 1))] for k in range(n)]


#: Distances (m) ahead of the box along its heading where the dropped block is tried, in order.
DROP_AHEAD = (1.0, 1.25, 1.5, 1.75, 2.0)


def _events(scene: Any, q: tuple[float, float, float], grasp: int) -> dict[str, dict[str, Any]]:
    """The events at ``q`` (the robot holding the box with ``grasp``), by name."""
    import dataclasses

    from pivot_ompl.checking.pivot_checker import PivotChecker
    from pivot_ompl.scene import obstacles_from_list

    x, y, t = q
    c, s = math.cos(t), math.sin(t)
    out: dict[str, dict[str, Any]] = {
        "drift 5cm/5deg": {"box": (x + 0.05 * c, y + 0.05 * s, t + math.radians(5))},
        "drift 15cm/15deg": {"box": (x + 0.15 * c, y + 0.15 * s, t + math.radians(15))},
    }
    for d in DROP_AHEAD:  # the first block clear of the box and the robot holding it
        block = {"type": "box", "center": [x + d * c, y + d * s], "size": [0.3, 0.3],
                 "yaw": 0.0, "height": 1.0}
        added = obstacles_from_list([block], field="add_obstacles")
        if PivotChecker(dataclasses.replace(scene, obstacles=scene.obstacles + added)
                        ).state_valid(q, grasp):
            out["obstacle dropped"] = {"box": q, "add_obstacles": [block]}
            break
    out["obstacle removed"] = {"box": q, "remove": True}
    return out


MODES = ("warm", "cli", "fresh")


def _run(row: dict[str, Any], mode: str, session: Any, kw: dict[str, Any]) -> None:
    """Time one replan; record success, the check on the changed scene, regrasps and cost."""
    from pivot_ompl.validity.plan_check import check_plan

    t0 = time.perf_counter()
    res = session.replan(**kw)
    row[mode + "_s"] = time.perf_counter() - t0
    q = res.plan.extra.get("quality") or {}
    row.update({mode + "_ok": res.solved, mode + "_status": res.status,
                mode + "_solve_s": res.timings.get("solve", math.nan),
                mode + "_check": res.solved and check_plan(res.plan, session.scene).ok,
                mode + "_regrasps": res.regrasps, mode + "_pivots": res.pivots,
                mode + "_cost": q.get("cost", math.nan),
                mode + "_repaired": bool(res.roadmap.get("repaired"))})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default="fig10,slot,gen:walls:1")
    ap.add_argument("--points", type=int, default=10)
    ap.add_argument("--time", type=float, default=30.0)
    ap.add_argument("--events", default="", help="comma-separated words; default: all events")
    ap.add_argument("--proof-time", type=float, default=60.0,
                    help="s to prove that no plan exists where none is found")
    ap.add_argument("--out", default="results/replanning.json")
    args = ap.parse_args()
    sys.path[:0] = [str(HERE.parent)]
    from common import scene_from_spec, write_json
    from ompl import util as ou

    from pivot_ompl.errors import PlanningError
    from pivot_ompl.planfile import plan_from_dict
    from pivot_ompl.session import PlanningSession

    ou.setLogLevel(ou.LOG_ERROR)
    rows: list[dict[str, Any]] = []
    for name in args.scenes.split(","):
        base = scene_from_spec(name)
        first = PlanningSession(base, seed=0).plan(time_limit=args.time)
        if not first.solved:
            print(f"{name}: no first plan")
            continue
        executed = plan_from_dict(json.loads(first.plan.to_text()))  # as the CLI reads it
        for q, grasp in _points(first.plan, args.points):
            for kind, ev in _events(base, q, grasp).items():
                if args.events and not any(w and w in kind for w in args.events.split(",")):
                    continue
                session = PlanningSession(base, seed=0)
                session.plan(time_limit=args.time)  # the session that executes the plan
                kw: dict[str, Any] = {"box": ev["box"], "grasp": grasp, "time_limit": args.time,
                                      "add_obstacles": ev.get("add_obstacles", ())}
                if ev.get("remove"):
                    kw["remove_obstacles"] = [len(base.obstacles) - 1]
                row: dict[str, Any] = {"scene": name, "event": kind}
                try:
                    _run(row, "warm", session, kw)
                    _run(row, "cli", PlanningSession(base, seed=0, executing=executed), kw)
                    _run(row, "fresh", PlanningSession(session.scene, seed=0, repair=False),
                         {"box": ev["box"], "grasp": grasp, "time_limit": args.time})
                except PlanningError as e:  # the observed pose collides
                    row.update(error=str(e)[:80])
                if "error" not in row and not any(row[m + "_ok"] for m in MODES):
                    row["no_plan"] = no_plan_proof(row, session.scene, args.proof_time)
                rows.append(row)
                print(f"{name:10s} {kind:18s} " + (" ".join(
                    f"{m} {row[m + '_s']:.2f} s ({row[m + '_status']}, {row[m + '_cost']:.0f})"
                    for m in MODES) if "error" not in row else row["error"])
                    + (f" no plan: {row['no_plan']}" if "no_plan" in row else ""), flush=True)
    print("\n| scene | event | runs | no plan (proven) | undecided | fresh ok | fresh s "
          "| warm s (ratio) | cli solve s (ratio) | ok/checked warm cli | repaired warm cli "
          "| cost fresh warm cli |")
    table = {}
    keys = sorted({(r["scene"], r["event"]) for r in rows})
    for sc, ev in keys:
        every = [r for r in rows if r["scene"] == sc and r["event"] == ev and "error" not in r]
        rs = [r for r in every if r.get("no_plan") != PROVEN]  # events with a plan, or unknown
        if not rs:
            table[f"{sc}/{ev}"] = {"runs": 0, "proven_none": len(every)}
            print(f"| {sc} | {ev} | 0 | {len(every)} | 0 | | | | | | | |")
            continue
        t: dict[str, Any] = {"runs": len(rs), "proven_none": len(every) - len(rs),
                             "undecided": sum(r.get("no_plan") == UNDECIDED for r in rs)}
        for m in MODES:
            ok = [r for r in rs if r[m + "_ok"]]
            t[m] = {"ok": len(ok), "checked": sum(r[m + "_check"] for r in ok),
                    "median_s": statistics.median(r[m + "_s"] for r in rs),
                    "median_solve_s": statistics.median(r[m + "_solve_s"] for r in rs),
                    "median_cost": statistics.median(r[m + "_cost"] for r in ok) if ok
                    else math.nan,
                    "median_regrasps": statistics.median(r[m + "_regrasps"] for r in ok) if ok
                    else math.nan,
                    "repaired": sum(r[m + "_repaired"] for r in rs)}
        f = t["fresh"]
        for m in ("warm", "cli"):
            t[m]["ratio"] = t[m]["median_s"] / f["median_s"] if f["median_s"] > 0 else math.nan
            t[m]["solve_ratio"] = (t[m]["median_solve_s"] / f["median_solve_s"]
                                   if f["median_solve_s"] > 0 else math.nan)
        table[f"{sc}/{ev}"] = t
        w, c = t["warm"], t["cli"]
        print(f"| {sc} | {ev} | {len(rs)} | {t['proven_none']} | {t['undecided']} | "
              f"{f['ok']} | {f['median_s']:.2f} | "
              f"{w['median_s']:.2f} ({w['ratio']:.2f}) | {c['median_solve_s']:.2f} "
              f"({c['solve_ratio']:.2f}) | {w['ok']}/{w['checked']} {c['ok']}/{c['checked']} | "
              f"{w['repaired']} {c['repaired']} | {f['median_cost']:.0f} {w['median_cost']:.0f} "
              f"{c['median_cost']:.0f} |")
    errors = _error_kinds(rows)
    write_json({"time_limit": args.time, "rows": rows, "table": table, "errors": errors}, args.out)


#: What :func:`no_plan_proof` says of an event that no replan solved.
PROVEN, UNDECIDED = "proven", "undecided"


def no_plan_proof(row: dict[str, Any], scene: Any, seconds: float) -> str:
    """:data:`PROVEN` when no plan of the changed ``scene`` exists, else :data:`UNDECIDED`.

    Proven by a replan's own ``INFEASIBLE`` status, else by the regrasp bound's relaxation
    (it joins no start to the goal) or the held poses' proof, within ``seconds``.
    """
    from pivot_ompl.analysis.bound_cache import lower_bound
    from pivot_ompl.analysis.late_proof import held_pose_proof

    if any(row.get(m + "_status") == "INFEASIBLE" for m in MODES):
        return PROVEN
    end = time.monotonic() + seconds

    def stop() -> bool:
        return time.monotonic() > end

    solvable = lower_bound(scene, should_stop=stop).solvable
    if solvable is False or solvable and held_pose_proof(scene, should_stop=stop) is not None:
        return PROVEN
    return UNDECIDED


#: Error kinds of the rows, by the words of their messages (the first that matches).
ERROR_KINDS = (("box or every grasp in collision", "no valid grasp at start"),
               ("held grasp in collision", "held grasp"),
               ("no walk from the held grasp", "cannot walk"))


def _error_kinds(rows: list[dict[str, Any]]) -> dict[str, int]:
    """How many rows ended in each kind of error (:data:`ERROR_KINDS`, else ``other``), printed."""
    out: dict[str, int] = {}
    for r in rows:
        if "error" in r:
            kind = next((k for k, words in ERROR_KINDS if words in r["error"]), "other")
            out[kind] = out.get(kind, 0) + 1
    print("errors by kind: " + (", ".join(f"{k} {n}" for k, n in out.items()) or "none"))
    return out


if __name__ == "__main__":
    main()

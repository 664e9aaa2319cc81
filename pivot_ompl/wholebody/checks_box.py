"""Motion checks of the box: floor, pivot corner, robot and obstacle clearance, plan poses."""

from __future__ import annotations

import logging
import math

import numpy as np

from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, profile_of
from pivot_ompl.planfile import TransferPhase, TransitPhase
from pivot_ompl.wholebody.box import matrix_from_quat
from pivot_ompl.wholebody.check_context import CheckContext, CheckResult, box_T, runs
from pivot_ompl.wholebody.clearance import ClearanceReport, obstacle_clearance

log = logging.getLogger(__name__)


def box_floor(ctx: CheckContext) -> CheckResult:
    """No box corner below the floor."""
    corners, tol = ctx.box_corners, ctx.tol.corner
    low = float(corners[:, :, 2].min())
    return CheckResult("box_floor", low > -tol, -low, tol, "m",
                       "deepest corner below the floor",
                       int(np.argmin(corners[:, :, 2].min(axis=1))))


def pivot_corner(ctx: CheckContext) -> CheckResult:
    """During each pivot rotation one bottom corner of the supporting edge stays fixed.

    With a plan, that corner is at the step's ``pivot``.
    """
    plan, corners, tol = ctx.plan, ctx.box_corners, ctx.tol.corner
    phase, step = ctx.array("phase"), ctx.array("step")
    key = phase.astype(np.int64) * 100_000 + step
    worst, where, rotations, wi = 0.0, "", 0, -1
    for a, b in runs(step >= 0):
        # split runs where (phase, step) changes
        cuts = [a] + [i for i in range(a + 1, b) if key[i] != key[i - 1]] + [b]
        for c0, c1 in zip(cuts[:-1], cuts[1:], strict=True):
            rotations += 1
            cs = corners[c0:c1]
            bottom = np.argsort(cs[0, :, 2])[:2]
            moves = [float(np.linalg.norm(cs[:, c] - cs[0, c], axis=1).max()
                           + np.abs(cs[:, c, 2]).max()) for c in bottom]
            best = int(bottom[int(np.argmin(moves))])
            v = min(moves)
            if plan is not None:
                ph = plan.phases[int(phase[c0])]
                if isinstance(ph, TransferPhase) and step[c0] < len(ph.steps):
                    piv = np.array([*ph.steps[int(step[c0])].pivot, 0.0])
                    v = max(v, float(np.linalg.norm(cs[:, best] - piv, axis=1).max()))
                else:
                    v = math.inf
            if v > worst:
                worst, wi = v, c0
                where = f"phase {phase[c0]} step {step[c0]}"
    return CheckResult("pivot_corner", worst < tol and rotations > 0
                       or (rotations == 0 and worst == 0.0), worst,
                       tol, "m", f"{rotations} rotations; {where}", wi)


def obstacles(ctx: CheckContext) -> CheckResult | None:
    """Every link and the box keep their clearance to the scene's obstacles (with a scene).

    The clearance report is kept in ``ctx.clearance``. ``None`` without a scene.
    """
    if ctx.scene is None:
        return None
    ctx.clearance = obstacle_clearance(ctx.motion, ctx.scene, robot=ctx.robot)
    return obstacles_result(ctx.clearance, ctx.tol.obstacle)


def obstacles_result(cl: ClearanceReport, tol: float) -> CheckResult:
    """The ``obstacles`` check from the clearance report."""
    w = cl.worst
    if w is None or math.isinf(w.clearance):
        return CheckResult("obstacles", True, math.inf, tol, "m", "no obstacle")
    what = "depth" if w.clearance < 0 else "clearance"
    return CheckResult("obstacles", w.clearance >= tol, w.clearance, tol, "m",
                       f"{w.link} {what} {1000 * abs(w.clearance):.1f} mm at t = {w.time:.3f} s"
                       f" to {w.obstacle}; {cl.queries} queries, {cl.seconds:.1f} s", w.index)


#: Links allowed to touch the box: the hands and fingers (the default model's; each profile
#: names its own: :attr:`~pivot_ompl.humanoids.HumanoidProfile.contact_links`).
CONTACT_LINKS = PROFILES[DEFAULT_MODEL].contact_links


def box_clearance(ctx: CheckContext, *, samples: int = 2000) -> CheckResult:
    """Smallest distance between the box and the robot's collision primitives (hands excluded).

    Evaluated on at most ``samples`` evenly spread samples.
    """
    import coal
    import pinocchio as pin

    motion = ctx.motion
    model, geom = ctx.robot.model, ctx.robot.geom
    data, gdata = model.createData(), geom.createData()
    box_size = motion.box_size
    assert box_size is not None  # required by check_motion
    box = coal.Box(*[float(x) for x in box_size])
    keep = [k for k, g in enumerate(geom.geometryObjects)
            if not g.name.startswith(profile_of(motion.model).contact_links)]
    req, res = coal.DistanceRequest(), coal.DistanceResult()
    worst, where, wi = math.inf, "", -1
    stride = max(1, len(motion.t) // samples)
    for i in range(0, len(motion.t), stride):
        pin.updateGeometryPlacements(model, data, geom, gdata, motion.q[i])
        Tb = coal.Transform3s(matrix_from_quat(motion.box[i, 3:]), motion.box[i, :3])
        for k in keep:
            res.clear()
            M = gdata.oMg[k]
            d = coal.distance(geom.geometryObjects[k].geometry,
                              coal.Transform3s(M.rotation, M.translation), box, Tb, req, res)
            if d < worst:
                worst, wi = float(d), i
                where = f"{geom.geometryObjects[k].name} t = {motion.t[i]:.3f} s"
    return CheckResult("box_clearance", worst >= 0.0, worst, 0.0, "m",
                       f"robot (hands excluded) to box, every {stride} samples; {where}", wi)


def box_plan(ctx: CheckContext) -> CheckResult | None:
    """Box pose against the plan: at every pivot step's end and throughout transits.

    ``None`` without a plan.
    """
    if ctx.plan is None:
        return None
    motion, plan, hold, tol = ctx.motion, ctx.plan, ctx.hold, ctx.tol.corner
    phase, step, tilt = ctx.array("phase"), ctx.array("step"), ctx.array("tilt")
    worst, where, checked, wi = 0.0, "", 0, -1

    def compare(i: int, T_expected: np.ndarray, label: str) -> None:
        nonlocal worst, where, checked, wi
        B = box_T(motion.box[i])
        dp = float(np.linalg.norm(B[:3, 3] - T_expected[:3, 3]))
        cos = (np.trace(B[:3, :3].T @ T_expected[:3, :3]) - 1) / 2
        da = math.acos(max(-1.0, min(1.0, cos)))
        v = max(dp, da * tol / 1e-3)  # 1e-3 rad counts as tol
        checked += 1
        if v > worst:
            worst, where, wi = v, label, i

    if int(phase.max()) >= len(plan.phases):
        return CheckResult("box_plan", False, math.inf, tol, "m",
                           f"motion has phase {int(phase.max())}, plan has "
                           f"{len(plan.phases)}")
    for p, ph in enumerate(plan.phases):
        idx = np.nonzero(phase == p)[0]
        if len(idx) == 0:
            return CheckResult("box_plan", False, math.inf, tol, "m", f"phase {p} missing")
        if isinstance(ph, TransitPhase):
            T = hold.T_world_box(hold.T_world_G(ph.object_pose, 0), 0, 0.0)
            for i in idx[:: max(1, len(idx) // 50)]:
                compare(int(i), T, f"transit phase {p}")
            continue
        k = ph.grasp
        steps_seen = sorted(set(int(s) for s in step[idx] if s >= 0))
        if steps_seen != list(range(len(ph.steps))):
            return CheckResult("box_plan", False, math.inf, tol, "m",
                               f"phase {p}: motion pivots {len(steps_seen)} times, plan "
                               f"{len(ph.steps)}")
        for j, st in enumerate(ph.steps):
            last = int(idx[step[idx] == j][-1])
            T = hold.T_world_box(hold.T_world_G(st.object, k), k, float(tilt[last]))
            compare(last, T, f"phase {p} step {j}")
        first = int(idx[0])
        compare(first, hold.T_world_box(hold.T_world_G(ph.object_start, k), k,
                                        float(tilt[first])), f"phase {p} start")
        lastp = int(idx[-1])
        compare(lastp, hold.T_world_box(hold.T_world_G(ph.object_end, k), k,
                                        float(tilt[lastp])), f"phase {p} end")
    return CheckResult("box_plan", worst < tol, worst, tol, "m", f"{checked} poses; worst {where}",
                       wi)

"""Motion checks of the robot's own body: CoM file, ZMP, feet, hands, joints, plan poses."""

from __future__ import annotations

import logging
import math

import numpy as np

from pivot_ompl.humanoids import profile_of
from pivot_ompl.motionfile import SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT
from pivot_ompl.planfile import TransitPhase
from pivot_ompl.wholebody.check_context import CheckContext, CheckResult, box_T, runs
from pivot_ompl.wholebody.hull import convex_hull
from pivot_ompl.wholebody.lipm import lipm_zmp

log = logging.getLogger(__name__)


def com_file(ctx: CheckContext) -> CheckResult:
    """The ``com`` array agrees with the CoM of ``q`` (< 1 mm)."""
    dev = np.abs(ctx.kin.com - ctx.array("com")).max(axis=1)
    d = float(dev.max())
    return CheckResult("com_file", d < 1e-3, d, 1e-3, "m", "", int(np.argmax(dev)))


def _margin(poly: np.ndarray, p: np.ndarray) -> float:
    """Signed distance from ``p`` to the boundary of CCW convex ``poly`` (> 0 inside)."""
    best = math.inf
    inside = True
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        e = b - a
        n = np.array([-e[1], e[0]]) / np.linalg.norm(e)  # inward normal for CCW
        d = float(n @ (p - a))
        inside &= d >= 0
        best = min(best, d)
    if inside:
        return best
    # outside: Euclidean distance to the polygon, negated
    dist = math.inf
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        e = b - a
        s = min(1.0, max(0.0, float((p - a) @ e / (e @ e))))
        dist = min(dist, float(np.linalg.norm(p - (a + s * e))))
    return -dist


def _sole_corners(T: np.ndarray, sole: np.ndarray) -> np.ndarray:
    hx, hy = 0.5 * sole[0], 0.5 * sole[1]
    local = np.array([[hx, hy, 0, 1], [-hx, hy, 0, 1], [-hx, -hy, 0, 1], [hx, -hy, 0, 1]])
    return (T @ local.T).T[:, :2]




def zmp(ctx: CheckContext) -> CheckResult:
    """The LIPM ZMP of the CoM of ``q`` inside the support polygon at every sample."""
    motion, kin, t = ctx.motion, ctx.kin, ctx.motion.t
    support, phase = ctx.array("support"), ctx.array("phase")
    p = lipm_zmp(t, kin.com)
    sole = np.asarray(motion.sole_size or profile_of(motion.model).sole_size)
    worst, where, wi = math.inf, "", -1
    for i in range(len(t)):
        s = support[i]
        pts = []
        if s in (SUPPORT_DOUBLE, SUPPORT_LEFT):
            pts.append(_sole_corners(kin.feet["left_foot"][i], sole))
        if s in (SUPPORT_DOUBLE, SUPPORT_RIGHT):
            pts.append(_sole_corners(kin.feet["right_foot"][i], sole))
        m = _margin(convex_hull(np.vstack(pts)), p[i])
        if m < worst:
            worst, where, wi = m, f"t = {t[i]:.3f} s, phase {phase[i]}, support {s}", i
    tol = ctx.tol.zmp
    return CheckResult("zmp", worst >= tol, worst, tol, "m", f"worst at {where}", wi)


def feet(ctx: CheckContext) -> CheckResult:
    """A foot in contact does not slide, turn or sink."""
    t, support = ctx.motion.t, ctx.array("support")
    worst, where, wi = 0.0, "", -1
    for side, code in (("left_foot", SUPPORT_LEFT), ("right_foot", SUPPORT_RIGHT)):
        T = ctx.kin.feet[side]
        contact = (support == SUPPORT_DOUBLE) | (support == code)
        for a, b in runs(contact):
            p = T[a:b, :3, 3]
            slide = float(np.linalg.norm(p - p[0], axis=1).max())
            sink = float(max(0.0, -p[:, 2].min()))
            x = T[a:b, :3, 0]
            turn = float(np.linalg.norm(x - x[0], axis=1).max()) * 0.12  # toe displacement
            v = max(slide, sink, turn)
            if v > worst:
                worst, where = v, f"{side} contact t = {t[a]:.3f}..{t[b - 1]:.3f} s"
                wi = a + int(np.argmax(np.linalg.norm(p - p[0], axis=1)))
    tol = ctx.tol.foot
    return CheckResult("feet", worst < tol, worst, tol, "m", where, wi)


def hands(ctx: CheckContext) -> CheckResult:
    """While holding, each hand frame is near its grip point on the box."""
    motion = ctx.motion
    t, phase, grasp = motion.t, ctx.array("phase"), ctx.array("grasp")
    worst, where, wi = 0.0, "", -1
    for i in np.nonzero(ctx.array("holding"))[0]:
        k = int(grasp[i])
        B = box_T(motion.box[i])
        for h, name in enumerate(("left_hand", "right_hand")):
            g = B[:3, :3] @ motion.grip_box[k, h] + B[:3, 3]
            e = float(np.linalg.norm(ctx.kin.hands[name][i] - g))
            if e > worst:
                worst, where, wi = e, f"{name} t = {t[i]:.3f} s, phase {phase[i]}", i
    tol = ctx.tol.hand
    return CheckResult("hands", worst < tol, worst, tol, "m", where, int(wi))


def joint_limits(ctx: CheckContext) -> CheckResult:
    """Every joint within its URDF limits (1e-6 rad slack)."""
    motion, kin = ctx.motion, ctx.kin
    q = motion.q[:, 7:]
    over = np.maximum(kin.lower - q, q - kin.upper)
    worst = float(over.max())
    si, sj = np.unravel_index(int(np.argmax(over)), over.shape)
    return CheckResult("joint_limits", worst <= 1e-6, worst, 1e-6, "rad",
                       f"{motion.joint_names[sj]} at t = {motion.t[si]:.3f} s", int(si))


def _point_polyline(p: np.ndarray, poly: np.ndarray) -> float:
    """Distance from 2-D point ``p`` to the polyline ``poly`` (M x 2)."""
    if len(poly) == 1:
        return float(np.linalg.norm(p - poly[0]))
    a, b = poly[:-1], poly[1:]
    e = b - a
    L2 = np.maximum((e * e).sum(axis=1), 1e-18)
    u = np.clip(((p - a) * e).sum(axis=1) / L2, 0.0, 1.0)
    return float(np.linalg.norm(a + u[:, None] * e - p, axis=1).min())


def robot_plan(ctx: CheckContext, *, step_tol: float = 0.01,
               path_tol: float = 0.03) -> CheckResult | None:
    """The robot (sole midpoint, double-support samples) against the plan's robot poses.

    At the end of every pivot step it stands at the step's ``robot`` pose (< 1 cm and
    0.02 rad); during a transit it stays within 3 cm of the ``robot_path`` polyline.
    The value is the worst of (step error / 1 cm, path deviation / 3 cm): pass below 1.
    ``None`` without a plan.
    """
    if ctx.plan is None:
        return None
    motion, plan, kin = ctx.motion, ctx.plan, ctx.kin
    phase, support, step = ctx.array("phase"), ctx.array("support"), ctx.array("step")
    mid = 0.5 * (kin.feet["left_foot"][:, :2, 3] + kin.feet["right_foot"][:, :2, 3])
    xl, xr = kin.feet["left_foot"][:, :2, 0], kin.feet["right_foot"][:, :2, 0]
    yaw = np.arctan2(xl[:, 1] + xr[:, 1], xl[:, 0] + xr[:, 0])
    worst, where, wi = 0.0, "", -1
    for p, ph in enumerate(plan.phases):
        idx = np.nonzero((phase == p) & (support == SUPPORT_DOUBLE))[0]
        if len(idx) == 0:
            continue
        if isinstance(ph, TransitPhase):
            poly = np.array([q[:2] for q in ph.robot_path])
            for i in idx[:: max(1, len(idx) // 400)]:
                v = _point_polyline(mid[i], poly) / path_tol
                if v > worst:
                    worst, where, wi = v, f"transit phase {p} t = {motion.t[i]:.3f} s", int(i)
            continue
        for j, st in enumerate(ph.steps):
            sel = idx[step[idx] == j]
            if len(sel) == 0:
                continue
            i = int(sel[-1])
            d = float(np.linalg.norm(mid[i] - np.array(st.robot[:2])))
            da = abs(math.remainder(float(yaw[i]) - st.robot[2], 2 * math.pi))
            v = max(d / step_tol, da / 0.02)
            if v > worst:
                worst, where, wi = v, f"phase {p} step {j}: {1000 * d:.1f} mm, {da:.3f} rad", i
    return CheckResult("robot_plan", worst < 1.0, worst, 1.0, "x",
                       f"step pose / 1 cm, transit deviation / 3 cm; worst {where}", wi)

"""Checks of a whole-body motion file, computed from the motion's own configurations.

Every check recomputes what it needs with pinocchio from ``q`` and the URDF named in the file
(never from the generator's internals):

* ``zmp`` -- ZMP of the LIPM from the CoM of ``q`` (second finite differences):
  ``zmp = c_xy - c_z / g * c''_xy``, inside the support polygon (sole rectangles of the feet in
  contact per ``support``; convex hull in double support) at every sample. The value is the
  worst signed margin (m, > 0 inside).
* ``feet`` -- a foot in contact does not slide, turn or sink: sole-centre displacement from the
  start of each contact interval < 1 mm, height > -1 mm.
* ``hands`` -- while ``holding``, each hand frame is within 1 cm of its grip point on the box
  (``box`` pose x ``grip_box``).
* ``joint_limits`` -- every joint within its URDF limits (1e-6 rad slack).
* ``joint_velocity`` -- finite-difference joint speeds within the URDF velocity limits
  (value: worst fraction of the limit).
* ``pivot_corner`` -- during each pivot rotation one bottom corner of the box's supporting edge
  stays fixed (< 1 mm) on the floor; with a plan, at the step's ``pivot``.
* ``joint_accel`` -- no chattering: the 99th percentile over samples of the largest joint
  acceleration (second differences) below 100 rad/s^2 (the maximum is reported; single-tick
  peaks occur where a joint reaches a position limit).
* ``box_clearance`` -- the robot's collision primitives, hands and fingers excluded, never
  penetrate the box (checked on about 2000 evenly spread samples).
* ``box_floor`` -- no box corner below the floor (> -1 mm).
* ``obstacles`` (with a scene) -- every link's collision geometry and the (tilted) box keep
  at least ``obstacle_clearance`` (1 cm by default) from every obstacle at every sample
  (coal broad phase; samples between queries are certified by a bound on how far the body
  can move, see :mod:`pivot_ompl.wholebody.clearance`). A failure names the link, the time,
  the obstacle and the depth; ``MotionReport.clearance`` holds the minimum per link.
* ``com_file`` -- the ``com`` array agrees with the CoM of ``q`` (< 1 mm).
* ``robot_plan`` (with a plan) -- the robot (sole midpoint) stands at each pivot step's
  ``robot`` pose at the step's end (< 1 cm, 0.02 rad) and keeps within 3 cm of a transit's
  ``robot_path``.
* ``box_plan`` (with a plan) -- the box pose equals the plan's object pose (with the recorded
  tilt) at the end of every pivot step and during transits (< 1 mm, < 1e-3 rad).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.hrp2 import SOLE_SIZE
from pivot_ompl.motionfile import DYNAMICS, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT, Motion
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene
from pivot_ompl.wholebody.box import BoxHold, matrix_from_quat, transform
from pivot_ompl.wholebody.clearance import ClearanceReport, obstacle_clearance
from pivot_ompl.wholebody.hull import convex_hull
from pivot_ompl.wholebody.lipm import lipm_zmp
from pivot_ompl.wholebody.urdf_model import UrdfModel, load_urdf_model

log = logging.getLogger(__name__)

@dataclass(frozen=True)
class CheckResult:
    """One check: its worst value against its limit.

    Attributes:
        name: check name.
        passed: whether the motion satisfies it.
        value: the worst measured value (unit in ``unit``).
        limit: the threshold.
        unit: unit of value and limit.
        detail: where the worst value occurs.
        index: sample index of the worst value (-1 if not tied to a sample).
    """

    name: str
    passed: bool
    value: float
    limit: float
    unit: str
    detail: str = ""
    index: int = -1


@dataclass
class MotionReport:
    """All checks of a motion."""

    results: list[CheckResult] = field(default_factory=list)
    #: Obstacle clearance per link and of the box (with a scene).
    clearance: ClearanceReport | None = None

    @property
    def passed(self) -> bool:
        """True when every check passed."""
        return all(r.passed for r in self.results)

    def __getitem__(self, name: str) -> CheckResult:
        for r in self.results:
            if r.name == name:
                return r
        raise KeyError(name)

    def table(self) -> str:
        """A printable table of the results."""
        lines = [f"{'check':14s} {'result':6s} {'worst':>12s} {'limit':>10s}  detail"]
        for r in self.results:
            lines.append(f"{r.name:14s} {'PASS' if r.passed else 'FAIL':6s} "
                         f"{r.value:12.6f} {r.limit:10.4g} {r.unit:4s} {r.detail}")
        lines.append("PASS" if self.passed else "FAIL")
        return "\n".join(lines)


@dataclass
class _Kinematics:
    com: np.ndarray
    feet: dict[str, np.ndarray]  # name -> N x 4 x 4
    hands: dict[str, np.ndarray]  # name -> N x 3
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray


def _kinematics(motion: Motion, robot: UrdfModel) -> _Kinematics:
    import pinocchio as pin

    model = robot.model
    names = [str(n) for n in model.names[2:]]
    if names != list(motion.joint_names):
        raise InputError("motion.joint_names", motion.joint_names[:3],
                         f"do not match the joints of {motion.urdf}")
    if motion.q.shape[1] != model.nq:
        raise InputError("motion.q", motion.q.shape, f"must have {model.nq} columns")
    data = model.createData()
    fids = {n: model.getFrameId(n) for n in ("left_foot", "right_foot", "left_hand",
                                             "right_hand")}
    n = len(motion.t)
    com = np.empty((n, 3))
    feet = {k: np.empty((n, 4, 4)) for k in ("left_foot", "right_foot")}
    hands = {k: np.empty((n, 3)) for k in ("left_hand", "right_hand")}
    for i, q in enumerate(motion.q):
        com[i] = pin.centerOfMass(model, data, q)
        pin.updateFramePlacements(model, data)
        for k in feet:
            feet[k][i] = data.oMf[fids[k]].homogeneous
        for k in hands:
            hands[k][i] = data.oMf[fids[k]].translation
    return _Kinematics(com, feet, hands, model.lowerPositionLimit[7:],
                       model.upperPositionLimit[7:], model.velocityLimit[6:])


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


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [a, b) where ``mask`` is true."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        elif not m and start is not None:
            out.append((start, i))
            start = None
    if start is not None:
        out.append((start, len(mask)))
    return out


def _box_T(row: np.ndarray) -> np.ndarray:
    return transform(matrix_from_quat(row[3:]), row[:3])


def _phase_sequence(phase: np.ndarray, n_phases: int | None) -> CheckResult:
    """Phases run 0, 1, 2, ... in order (each sample in its phase or the next one)."""
    bad = np.zeros(len(phase), dtype=bool)
    if len(phase):
        bad[0] = phase[0] != 0
        bad[1:] = (np.diff(phase) < 0) | (np.diff(phase) > 1)
        bad |= phase < 0
        if n_phases is not None:
            bad |= phase >= n_phases
    idx = np.nonzero(bad)[0]
    i = int(idx[0]) if len(idx) else -1
    detail = f"sample {i}: phase {int(phase[i])}" if i >= 0 else ""
    return CheckResult("phase_order", not len(idx), float(len(idx)), 0.0, "smp", detail, i)


def _all_finite(motion: Motion) -> CheckResult:
    """Every numeric array of the motion is finite (NaN anywhere fails)."""
    for key in ("t", "q", "box", "com", "zmp", "tilt"):
        a = getattr(motion, key)
        if a is None:
            continue
        rows = np.isfinite(np.asarray(a, dtype=float)).reshape(len(a), -1).all(axis=1)
        if not rows.all():
            i = int(np.argmin(rows))
            return CheckResult("finite", False, float((~rows).sum()), 0.0, "smp",
                               f"{key} at sample {i}", i)
    return CheckResult("finite", True, 0.0, 0.0, "smp", "")


def check_motion(motion: Motion, plan: Plan | None = None, *, scene: Scene | None = None,
                 zmp_tolerance: float = 0.0, foot_tolerance: float = 1e-3,
                 hand_tolerance: float = 0.01, corner_tolerance: float = 1e-3,
                 accel_limit: float = 100.0,
                 obstacle_tolerance: float = 0.01) -> MotionReport:
    """Run every check on ``motion`` (and against ``plan`` when given).

    Args:
        motion: the motion.
        plan: the plan it was generated from (enables ``pivot_corner`` at the plan's pivots
            ``box_plan`` and ``robot_plan``).
        zmp_tolerance: smallest accepted ZMP margin (m; 0 = on the polygon boundary).
        foot_tolerance: feet slide/sink limit (m).
        hand_tolerance: hand-to-grip limit (m).
        corner_tolerance: pivot corner / box pose limit (m).
        accel_limit: limit of the 99th percentile of the largest joint acceleration (rad/s^2).
        scene: the scene of the motion: enables the ``obstacles`` check.
        obstacle_tolerance: smallest accepted clearance of a link or the box to an
            obstacle (m).

    Raises:
        InputError: the motion file is inconsistent with its URDF, or ``plan`` is not the
            plan of this motion (phase count, box size).
    """
    motion.require(*DYNAMICS, "box_size")
    com, support, phase, box_size = motion.com, motion.support, motion.phase, motion.box_size
    step, holding, grasp = motion.step, motion.holding, motion.grasp
    assert com is not None and support is not None and phase is not None  # required above
    assert box_size is not None  # required above
    assert step is not None and holding is not None and grasp is not None  # Motion defaults
    if plan is not None:
        n_phases = int(phase.max()) + 1
        if len(plan.phases) != n_phases:
            raise InputError("plan.phases", len(plan.phases),
                             f"the motion has {n_phases} phases: not the plan it was made from")
        if not np.allclose(plan.object_size, box_size, atol=1e-9):
            raise InputError("plan.object_size", plan.object_size,
                             f"the motion's box is {tuple(box_size)}")
    rep = MotionReport()
    rep.results.append(_phase_sequence(phase, None if plan is None else len(plan.phases)))
    finite = _all_finite(motion)
    rep.results.append(finite)
    if not finite.passed:  # NaN would make every other check meaningless (or PASS)
        return rep
    robot = load_urdf_model(motion.urdf)
    kin = _kinematics(motion, robot)
    t = motion.t
    n = len(t)

    # com file
    dev = np.abs(kin.com - com).max(axis=1)
    d = float(dev.max())
    rep.results.append(CheckResult("com_file", d < 1e-3, d, 1e-3, "m", "",
                                   int(np.argmax(dev))))

    # zmp
    zmp = lipm_zmp(t, kin.com)
    sole = np.asarray(motion.sole_size or SOLE_SIZE)
    worst, where, wi = math.inf, "", -1
    for i in range(n):
        s = support[i]
        pts = []
        if s in (SUPPORT_DOUBLE, SUPPORT_LEFT):
            pts.append(_sole_corners(kin.feet["left_foot"][i], sole))
        if s in (SUPPORT_DOUBLE, SUPPORT_RIGHT):
            pts.append(_sole_corners(kin.feet["right_foot"][i], sole))
        poly = convex_hull(np.vstack(pts))
        m = _margin(poly, zmp[i])
        if m < worst:
            worst, where, wi = m, f"t = {t[i]:.3f} s, phase {phase[i]}, support {s}", i
    rep.results.append(CheckResult("zmp", worst >= zmp_tolerance, worst, zmp_tolerance, "m",
                                   f"worst at {where}", wi))

    # feet
    worst, where, wi = 0.0, "", -1
    for side, code in (("left_foot", SUPPORT_LEFT), ("right_foot", SUPPORT_RIGHT)):
        T = kin.feet[side]
        contact = (support == SUPPORT_DOUBLE) | (support == code)
        for a, b in _runs(contact):
            p = T[a:b, :3, 3]
            slide = float(np.linalg.norm(p - p[0], axis=1).max())
            sink = float(max(0.0, -p[:, 2].min()))
            x = T[a:b, :3, 0]
            turn = float(np.linalg.norm(x - x[0], axis=1).max()) * 0.12  # toe displacement
            v = max(slide, sink, turn)
            if v > worst:
                worst, where = v, f"{side} contact t = {t[a]:.3f}..{t[b - 1]:.3f} s"
                wi = a + int(np.argmax(np.linalg.norm(p - p[0], axis=1)))
    rep.results.append(CheckResult("feet", worst < foot_tolerance, worst, foot_tolerance, "m",
                                   where, wi))

    # hands
    worst, where, wi = 0.0, "", -1
    for i in np.nonzero(holding)[0]:
        k = int(grasp[i])
        B = _box_T(motion.box[i])
        for h, name in enumerate(("left_hand", "right_hand")):
            g = B[:3, :3] @ motion.grip_box[k, h] + B[:3, 3]
            e = float(np.linalg.norm(kin.hands[name][i] - g))
            if e > worst:
                worst, where, wi = e, f"{name} t = {t[i]:.3f} s, phase {phase[i]}", i
    rep.results.append(CheckResult("hands", worst < hand_tolerance, worst, hand_tolerance, "m",
                                   where, int(wi)))

    # joint limits
    q = motion.q[:, 7:]
    over = np.maximum(kin.lower - q, q - kin.upper)
    worst = float(over.max())
    si, sj = np.unravel_index(int(np.argmax(over)), over.shape)
    rep.results.append(CheckResult("joint_limits", worst <= 1e-6, worst, 1e-6, "rad",
                                   f"{motion.joint_names[sj]} at t = {t[si]:.3f} s", int(si)))

    # joint velocities (finite differences)
    vel = np.abs(np.diff(q, axis=0)) / np.diff(t)[:, None]
    ratio = vel / kin.velocity
    worst = float(ratio.max())
    si, sj = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
    rep.results.append(CheckResult("joint_velocity", worst <= 1.0 + 1e-6, worst, 1.0,
                                   "x", f"{motion.joint_names[sj]} at t = {t[si]:.3f} s "
                                   "(fraction of its velocity limit)", int(si)))

    # smoothness: joint accelerations (second differences); sustained QP chattering at the
    # velocity limits shows as ~2 v_max / dt (1200 rad/s^2) at most samples
    acc = np.abs(q[2:] - 2 * q[1:-1] + q[:-2]) / (motion.dt ** 2)
    per_sample = acc.max(axis=1)
    p99 = float(np.percentile(per_sample, 99))
    si, sj = np.unravel_index(int(np.argmax(acc)), acc.shape)
    rep.results.append(CheckResult("joint_accel", p99 < accel_limit, p99, accel_limit,
                                   "r/s2", f"99th percentile; max {acc[si, sj]:.0f} at "
                                   f"{motion.joint_names[sj]} t = {t[si + 1]:.3f} s",
                                   int(np.argmax(per_sample)) + 1))

    # box on/above floor, pivot corner fixed
    hold = BoxHold(cast("tuple[float, float, float]", tuple(float(x) for x in box_size)))
    corners = np.array([hold.box_corners(_box_T(row)) for row in motion.box])
    low = float(corners[:, :, 2].min())
    rep.results.append(CheckResult("box_floor", low > -corner_tolerance, -low,
                                   corner_tolerance, "m", "deepest corner below the floor",
                                   int(np.argmin(corners[:, :, 2].min(axis=1)))))
    key = phase.astype(np.int64) * 100_000 + step
    worst, where, rotations, wi = 0.0, "", 0, -1
    for a, b in _runs(step >= 0):
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
    rep.results.append(CheckResult("pivot_corner", worst < corner_tolerance and rotations > 0
                                   or (rotations == 0 and worst == 0.0), worst,
                                   corner_tolerance, "m", f"{rotations} rotations; {where}", wi))

    rep.results.append(_box_clearance(motion, robot))
    if scene is not None:
        rep.clearance = obstacle_clearance(motion, scene, robot=robot)
        rep.results.append(_obstacles(rep.clearance, obstacle_tolerance))
    if plan is not None:
        rep.results.append(_box_plan(motion, plan, hold, corner_tolerance))
        rep.results.append(_robot_plan(motion, plan, kin))
    return rep


def _obstacles(cl: ClearanceReport, tol: float) -> CheckResult:
    """The ``obstacles`` check from the clearance report."""
    w = cl.worst
    if w is None or math.isinf(w.clearance):
        return CheckResult("obstacles", True, math.inf, tol, "m", "no obstacle")
    what = "depth" if w.clearance < 0 else "clearance"
    return CheckResult("obstacles", w.clearance >= tol, w.clearance, tol, "m",
                       f"{w.link} {what} {1000 * abs(w.clearance):.1f} mm at t = {w.time:.3f} s"
                       f" to {w.obstacle}; {cl.queries} queries, {cl.seconds:.1f} s", w.index)


def _point_polyline(p: np.ndarray, poly: np.ndarray) -> float:
    """Distance from 2-D point ``p`` to the polyline ``poly`` (M x 2)."""
    if len(poly) == 1:
        return float(np.linalg.norm(p - poly[0]))
    a, b = poly[:-1], poly[1:]
    e = b - a
    L2 = np.maximum((e * e).sum(axis=1), 1e-18)
    u = np.clip(((p - a) * e).sum(axis=1) / L2, 0.0, 1.0)
    return float(np.linalg.norm(a + u[:, None] * e - p, axis=1).min())


def _robot_plan(motion: Motion, plan: Plan, kin: _Kinematics, *, step_tol: float = 0.01,
                path_tol: float = 0.03) -> CheckResult:
    """The robot (sole midpoint, double-support samples) against the plan's robot poses.

    At the end of every pivot step it stands at the step's ``robot`` pose (< 1 cm and
    0.02 rad); during a transit it stays within 3 cm of the ``robot_path`` polyline.
    The value is the worst of (step error / 1 cm, path deviation / 3 cm): pass below 1.
    """
    phase, support, step = motion.phase, motion.support, motion.step
    assert phase is not None and support is not None  # required by check_motion
    assert step is not None  # a Motion default
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


#: Links allowed to touch the box: the hands and fingers.
CONTACT_LINKS = ("RARM_LINK5", "RARM_LINK6", "LARM_LINK5", "LARM_LINK6")


def _box_clearance(motion: Motion, robot: UrdfModel, *, samples: int = 2000) -> CheckResult:
    """Smallest distance between the box and the robot's collision primitives (hands excluded).

    Evaluated on at most ``samples`` evenly spread samples.
    """
    import coal
    import pinocchio as pin

    model, geom = robot.model, robot.geom
    data, gdata = model.createData(), geom.createData()
    box_size = motion.box_size
    assert box_size is not None  # required by check_motion
    box = coal.Box(*[float(x) for x in box_size])
    keep = [k for k, g in enumerate(geom.geometryObjects)
            if not any(g.name.startswith(n) for n in CONTACT_LINKS)]
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


def _box_plan(motion: Motion, plan: Plan, hold: BoxHold, tol: float) -> CheckResult:
    """Box pose against the plan: at every pivot step's end and throughout transits."""
    phase, step, tilt = motion.phase, motion.step, motion.tilt
    assert phase is not None  # required by check_motion
    assert step is not None and tilt is not None  # Motion defaults
    worst, where, checked, wi = 0.0, "", 0, -1

    def compare(i: int, T_expected: np.ndarray, label: str) -> None:
        nonlocal worst, where, checked, wi
        B = _box_T(motion.box[i])
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

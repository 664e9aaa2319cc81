"""Issue 28, class 4: the motion reader refuses what the checks cannot judge, and the checks
raise nothing but the package's errors on anything the reader lets through."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError, PivotError
from pivot_ompl.motionfile import load_motion
from pivot_ompl.resources import urdf_path
from pivot_ompl.viz.samples import sample_plan, write_urdf_motion
from pivot_ompl.wholebody.motion_checks import MotionReport, check_motion

N = 24  # samples of the base motion (short: every example runs every check)


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> dict[str, np.ndarray]:
    p = write_urdf_motion(tmp_path_factory.mktemp("m"), urdf_path(), duration=0.5)
    with np.load(p) as d:
        n = len(d["t"])
        arrays = {k: (d[k][:N] if d[k].ndim and len(d[k]) == n else d[k]) for k in d.files}
    arrays["com"] = np.c_[arrays["q"][:, :2], np.full(N, 0.8)]
    arrays["zmp"] = arrays["com"][:, :2].copy()
    arrays["support"] = np.zeros(N, dtype=int)
    arrays["phase"] = np.zeros(N, dtype=int)
    return arrays


def _save(tmp_path: Path, arrays: dict) -> Path:
    p = tmp_path / "m.npz"
    np.savez(p, **arrays)
    return p


def _with(arrays: dict, key: str, row: int, value) -> dict:
    a = np.array(arrays[key], dtype=float)
    a[row] = value
    return {**arrays, key: a}


@pytest.mark.parametrize(("change", "field"), [
    (lambda a: _with(a, "t", 5, a["t"][4]), "motion.t[5]"),  # two samples at one time
    (lambda a: _with(a, "t", 5, a["t"][4] + 1e-9), "motion.t[5]"),
    (lambda a: {**a, "t": a["t"][::-1].copy()}, "motion.t"),
    (lambda a: _with(a, "q", 3, np.r_[a["q"][3, :3], 0, 0, 0, 2, a["q"][3, 7:]]), "motion.q[3]"),
    (lambda a: _with(a, "q", 3, a["q"][3] * 1e200), "motion.q[3]"),
    (lambda a: _with(a, "box", 7, np.r_[1e5, 0, 0, 0, 0, 0, 1]), "motion.box[7]"),
    (lambda a: _with(a, "box", 7, np.zeros(7)), "motion.box[7]"),
    (lambda a: _with(a, "com", 2, [0, 0, 1e300]), "motion.com[2]"),
    (lambda a: {**a, "sole_size": np.array([1e-12, 0.1])}, "motion.sole_size"),
    (lambda a: {**a, "box_size": np.array([1e-12, 0.6, 1.3])}, "motion.box_size")])
def test_values_the_checks_cannot_judge_are_refused(base, tmp_path, change, field):
    p = _save(tmp_path, change(base))
    with pytest.raises(InputError) as e:
        load_motion(p)
    assert e.value.field == field
    assert main(["check-motion", str(p), "--scene", "open"]) == 2


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    return v / n if n > 1e-6 else np.array([0.0, 0.0, 0.0, 1.0])


@st.composite
def motions(draw, base: dict) -> tuple[dict, bool]:
    n = draw(st.integers(2, N))
    a = {k: (v[:n].copy() if isinstance(v, np.ndarray) and v.ndim and len(v) == N else v)
         for k, v in base.items()}
    steps = draw(st.lists(st.floats(1e-6, 0.2), min_size=n - 1, max_size=n - 1))
    a["t"] = np.r_[0.0, np.cumsum(steps)]
    scale = draw(st.sampled_from([0.0, 1e-3, 0.3, 10.0, 1e3]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    q = a["q"].astype(float)
    q[:, 7:] += scale * rng.standard_normal(q[:, 7:].shape)
    q[:, :3] += draw(st.floats(-100, 100)) * rng.standard_normal((n, 3)) * (scale > 1)
    q[:, 3:7] = [_unit(x) for x in q[:, 3:7] + scale * rng.standard_normal((n, 4))]
    a["q"] = q
    box = np.tile([0.5, 0.0, 0.65, 0.0, 0.0, 0.0, 1.0], (n, 1))
    box[:, :3] += draw(st.floats(0, 1e3)) * rng.standard_normal((n, 3))
    box[:, 3:7] = [_unit(x) for x in rng.standard_normal((n, 4))]
    a["box"] = box
    a["com"] = q[:, :3] + scale * rng.standard_normal((n, 3))
    a["zmp"] = a["com"][:, :2].copy()
    a["support"] = rng.integers(0, 3, n)
    a["phase"] = np.sort(rng.integers(0, draw(st.integers(1, 4)), n))
    a["step"] = rng.integers(-1, 6, n)
    a["holding"] = rng.integers(0, 2, n).astype(bool)
    a["grasp"] = np.where(a["holding"], rng.integers(0, 4, n), -1)
    a["tilt"] = draw(st.floats(-3.0, 3.0)) * rng.random(n)
    a["box_size"] = np.array([draw(st.floats(0.05, 20.0)) for _ in range(3)])
    a["sole_size"] = np.array([draw(st.floats(1e-3, 1.0)) for _ in range(2)])
    a["grip_box"] = rng.standard_normal((4, 2, 3))
    return a, draw(st.booleans())


@pytest.fixture(scope="module")
def plan():
    return sample_plan()


def test_the_checks_raise_only_the_packages_errors(base, plan, tmp_path_factory):
    """Random motions the reader accepts: check_motion returns a report or raises a
    PivotError (never a ValueError, IndexError, ZeroDivisionError ...)."""
    folder = tmp_path_factory.mktemp("random")

    @settings(max_examples=100, deadline=None, suppress_health_check=list(HealthCheck))
    @given(case=motions(base))
    def run(case):
        arrays, with_plan = case
        try:
            motion = load_motion(_save(folder, arrays))
            report = check_motion(motion, plan if with_plan else None)
        except PivotError:
            return
        assert isinstance(report, MotionReport)

    run()

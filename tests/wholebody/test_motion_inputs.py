"""Motion files on hostile input: NaN, phases out of order, foreign URDF paths, broken files."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import load_motion
from pivot_ompl.resources import urdf_path
from pivot_ompl.scene import load_scene
from pivot_ompl.viz.samples import write_urdf_motion
from pivot_ompl.wholebody.motion_checks import check_motion


@pytest.fixture(scope="module")
def hrp2_arrays(tmp_path_factory) -> dict[str, np.ndarray]:
    """A short synthetic HRP-2 motion with every array check-motion needs (phase 0)."""
    p = write_urdf_motion(tmp_path_factory.mktemp("m"), urdf_path(), duration=0.5)
    with np.load(p) as d:
        arrays = {k: d[k] for k in d.files}
    n = len(arrays["t"])
    arrays["com"] = np.c_[arrays["q"][:, :2], np.full(n, 0.8)]
    arrays["zmp"] = arrays["com"][:, :2].copy()
    arrays["support"] = np.zeros(n, dtype=int)
    arrays["phase"] = np.zeros(n, dtype=int)
    return arrays


def save(tmp_path: Path, arrays: dict, **changes) -> Path:
    p = tmp_path / "m.npz"
    np.savez(p, **{**arrays, **changes})
    return p


def test_phase_out_of_range_without_plan_fails(hrp2_arrays, tmp_path):
    ok = check_motion(load_motion(save(tmp_path, hrp2_arrays)))
    assert ok["phase_order"].passed and ok["finite"].passed
    n = len(hrp2_arrays["t"])
    bad = check_motion(load_motion(save(tmp_path, hrp2_arrays, phase=np.full(n, 999))))
    assert not bad["phase_order"].passed and not bad.passed
    assert "phase 999" in bad["phase_order"].detail
    assert main(["check-motion", str(tmp_path / "m.npz"), "--scene", "open"]) == 1


def test_phases_going_back_fail(hrp2_arrays, tmp_path):
    n = len(hrp2_arrays["t"])
    phase = np.r_[np.zeros(n // 2, int), np.ones(n - n // 2, int)]
    phase[-1] = 0
    rep = check_motion(load_motion(save(tmp_path, hrp2_arrays, phase=phase)))
    assert not rep["phase_order"].passed and rep["phase_order"].index == n - 1


@pytest.mark.parametrize("key", ["q", "box", "com", "zmp"])
def test_nan_is_refused_by_the_reader(hrp2_arrays, tmp_path, key):
    a = hrp2_arrays[key].astype(float).copy()
    a[3, -1] = np.nan
    with pytest.raises(InputError) as e:
        load_motion(save(tmp_path, hrp2_arrays, **{key: a}))
    assert e.value.field == f"motion.{key}" and "sample 3" in str(e.value)
    assert main(["check-motion", str(tmp_path / "m.npz")]) == 2


def test_nan_in_memory_fails_every_check(hrp2_arrays, tmp_path):
    motion = load_motion(save(tmp_path, hrp2_arrays))
    motion.q[5, 10] = np.nan
    rep = check_motion(motion)
    assert not rep.passed and not rep["finite"].passed and "q at sample 5" in rep["finite"].detail


@pytest.mark.parametrize("urdf", ["/etc/passwd", "../../etc/hrp2.urdf", "robots/../../x.urdf"])
def test_motion_naming_another_urdf_path_is_refused(hrp2_arrays, tmp_path, urdf):
    p = save(tmp_path, hrp2_arrays, urdf=np.array(urdf))
    with pytest.raises(InputError) as e:
        check_motion(load_motion(p))
    assert e.value.field == "motion.urdf"
    assert main(["check-motion", str(p)]) == 2


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04 truncated", b"\x93NUMPY garbage"])
def test_broken_files_are_input_errors(tmp_path, content):
    p = tmp_path / "m.npz"
    p.write_bytes(content)
    with pytest.raises(InputError):
        load_motion(p)


def test_a_single_array_is_not_a_motion(tmp_path):
    p = tmp_path / "m.npz"
    with p.open("wb") as fh:
        np.save(fh, np.zeros(3))
    with pytest.raises(InputError, match="single array"):
        load_motion(p)


def test_save_is_atomic(hrp2_arrays, tmp_path, monkeypatch):
    motion = load_motion(save(tmp_path, hrp2_arrays))
    motion.box_size = (0.8, 0.6, 1.3)
    out = tmp_path / "out.npz"
    out.write_bytes(b"previous motion")

    def boom(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez_compressed", boom)
    with pytest.raises(OSError):
        motion.save(out)
    assert out.read_bytes() == b"previous motion"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.npz", "out.npz"]


# -- values out of range: refused by the reader, naming array and sample ------------------
def _at(n: int, k: int, value: float, base: float = 0) -> np.ndarray:
    a = np.full(n, base, dtype=float)
    a[k] = value
    return a


@pytest.mark.parametrize(("key", "value"), [("support", 3), ("support", -1), ("support", 0.5),
                                            ("grasp", 4), ("grasp", -2), ("phase", -1),
                                            ("step", -2), ("holding", 2)])
def test_out_of_range_codes_are_refused(hrp2_arrays, tmp_path, key, value):
    n = len(hrp2_arrays["t"])
    p = save(tmp_path, hrp2_arrays, **{key: _at(n, n // 2, value)})
    with pytest.raises(InputError) as e:
        load_motion(p)
    assert e.value.field == f"motion.{key}[{n // 2}]"
    assert main(["check-motion", str(p)]) == 2


def test_one_sample_or_no_duration_is_refused(hrp2_arrays, tmp_path):
    one = {k: (v[:1] if isinstance(v, np.ndarray) and v.ndim and len(v) == len(hrp2_arrays["t"])
               else v) for k, v in hrp2_arrays.items()}
    with pytest.raises(InputError, match="at least two samples"):
        load_motion(save(tmp_path, one))
    frozen = save(tmp_path, hrp2_arrays, t=np.zeros(len(hrp2_arrays["t"])))
    with pytest.raises(InputError, match="positive duration"):
        load_motion(frozen)
    assert main(["check-motion", str(frozen)]) == 2


def test_a_valid_motion_still_loads(hrp2_arrays, tmp_path):
    m = load_motion(save(tmp_path, hrp2_arrays))
    assert m.duration > 0 and len(m.t) == len(hrp2_arrays["t"])


def test_the_check_table_says_which_way_each_check_passes(hrp2_arrays, tmp_path):
    n = len(hrp2_arrays["t"])
    rep = check_motion(load_motion(save(tmp_path, hrp2_arrays, phase=np.full(n, 999))),
                       scene=load_scene("open"))
    lines = rep.table().splitlines()
    assert "passes" in lines[0] and "limit" in lines[0]
    rows = {line.split()[0]: line.split() for line in lines[1:1 + len(rep.results)]}
    assert any(not r.passed for r in rep.results) and any(r.passed for r in rep.results)
    for r in rep.results:
        sense = rows[r.name][3]
        assert sense in (">=", "<=")
        if math.isfinite(r.value):
            holds = r.value >= r.limit if sense == ">=" else r.value <= r.limit
            assert holds == r.passed, (r.name, r.value, sense, r.limit)
    legend = "\n".join(lines[1 + len(rep.results):])
    for unit in {r.unit for r in rep.results}:
        assert f"{unit} " in legend, unit  # every unit shown is explained

"""Motion files whose values are out of range: refused by the reader, naming array and sample.

Every verb that reads a motion (check-motion, replay) then exits 2 with that message instead
of a traceback that reads as "check failed".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import load_motion
from pivot_ompl.resources import urdf_path
from pivot_ompl.viz.samples import write_urdf_motion


@pytest.fixture(scope="module")
def arrays(tmp_path_factory) -> dict[str, np.ndarray]:
    p = write_urdf_motion(tmp_path_factory.mktemp("m"), urdf_path(), duration=0.5)
    with np.load(p) as d:
        out = {k: d[k] for k in d.files}
    n = len(out["t"])
    out["com"] = np.c_[out["q"][:, :2], np.full(n, 0.8)]
    out["zmp"] = out["com"][:, :2].copy()
    out["support"] = np.zeros(n, dtype=int)
    out["phase"] = np.zeros(n, dtype=int)
    return out


def _save(tmp_path: Path, arrays: dict, **changes) -> Path:
    p = tmp_path / "m.npz"
    np.savez(p, **{**arrays, **changes})
    return p


def _at(n: int, k: int, value: float, base: float = 0) -> np.ndarray:
    a = np.full(n, base, dtype=float)
    a[k] = value
    return a


@pytest.mark.parametrize(("key", "value"), [("support", 3), ("support", -1), ("support", 0.5),
                                            ("grasp", 4), ("grasp", -2), ("phase", -1),
                                            ("step", -2), ("holding", 2)])
def test_out_of_range_codes_are_refused(arrays, tmp_path, key, value):
    n = len(arrays["t"])
    p = _save(tmp_path, arrays, **{key: _at(n, n // 2, value)})
    with pytest.raises(InputError) as e:
        load_motion(p)
    assert e.value.field == f"motion.{key}[{n // 2}]"
    assert main(["check-motion", str(p)]) == 2


def test_one_sample_or_no_duration_is_refused(arrays, tmp_path):
    one = {k: (v[:1] if isinstance(v, np.ndarray) and v.ndim and len(v) == len(arrays["t"])
               else v) for k, v in arrays.items()}
    with pytest.raises(InputError, match="at least two samples"):
        load_motion(_save(tmp_path, one))
    frozen = _save(tmp_path, arrays, t=np.zeros(len(arrays["t"])))
    with pytest.raises(InputError, match="positive duration"):
        load_motion(frozen)
    assert main(["check-motion", str(frozen)]) == 2


def test_a_valid_motion_still_loads(arrays, tmp_path):
    m = load_motion(_save(tmp_path, arrays))
    assert m.duration > 0 and len(m.t) == len(arrays["t"])

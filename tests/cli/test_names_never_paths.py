"""Issue 28, class 2: a name read from a file (a scene's, a motion's or a plan's ``scene``)
never becomes a path, for writing or for reading."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from factories import scene_file
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.cli.main import main
from pivot_ompl.fileio import MAX_STEM, file_stem
from pivot_ompl.resources import urdf_path
from pivot_ompl.viz.samples import write_urdf_motion

HOSTILE = ["../outside", "../../etc/passwd", "/etc/passwd", "a/../../b", "..", ".", "~/x",
           "scenes/../open"]


@given(st.one_of(st.sampled_from(HOSTILE), st.text(max_size=300)))
def test_a_stem_is_one_plain_name(name):
    stem = file_stem(name)
    assert stem and "/" not in stem and "\0" not in stem and not stem.startswith(".")
    assert len(stem) <= MAX_STEM


@pytest.mark.parametrize("name", ["../outside.yaml", "outside.yaml"])
def test_a_motions_scene_name_is_never_read_as_a_file(name, tmp_path, monkeypatch, capsys):
    """check-motion loads a shipped scene by the motion's name, never a file of that name."""
    work = tmp_path / "work"
    work.mkdir()
    shutil.copy(scene_file("open"), tmp_path / "outside.yaml")
    shutil.copy(scene_file("open"), work / "outside.yaml")
    monkeypatch.chdir(work)
    p = write_urdf_motion(tmp_path, urdf_path(), duration=0.2)
    with np.load(p) as d:
        arrays = {k: d[k] for k in d.files}
    n = len(arrays["t"])
    arrays.update(com=np.c_[arrays["q"][:, :2], np.full(n, 0.8)], support=np.zeros(n, int),
                  phase=np.zeros(n, int), scene=np.array(name))
    arrays["zmp"] = arrays["com"][:, :2].copy()
    np.savez(tmp_path / "m.npz", **arrays)
    code = main(["check-motion", str(tmp_path / "m.npz")])
    err = capsys.readouterr().err
    assert code == 2 and "motion.scene" in err and "not a shipped scene" in err, err

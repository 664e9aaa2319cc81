"""Files a plan or motion names (issue 43, class 2): never echoed, and a scene or nothing.

A plan's or motion's ``scene_path`` may name any file. Every verb that reads it (check,
check-motion, replay, animate) must either find a scene there or say "is not a scene file",
never print a part of what the file holds.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import numpy as np
import pytest

from pivot_ompl.cli.animate import plan_scene
from pivot_ompl.cli.main import main
from pivot_ompl.cli.scenes import SceneRecord, find_scene
from pivot_ompl.errors import SceneError
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import load_scene
from pivot_ompl.viz.samples import sample_motion_arrays, sample_plan, write_samples

SECRET = "TOKEN=hunter2-s3cr3t"

#: Contents a secret file might hold, each parsed differently by YAML.
CONTENTS = {
    "plain": f"{SECRET} second line\n",
    "mapping": f"{SECRET}: yes\nname: x\n",
    "list": f"- {SECRET}\n- two\n",
    "broken": f"{SECRET}: [unclosed\n",
    "nested": f"name: a\nbounds: {{'{SECRET}': 1}}\n",
    "binary": None,
}


def _secret(tmp_path: Path, kind: str) -> Path:
    p = tmp_path / "secret.env"
    text = CONTENTS[kind]
    if text is None:
        p.write_bytes(b"\xff\xfe" + SECRET.encode())
    else:
        p.write_text(text)
    return p


def _plan_naming(tmp_path: Path, target: Path) -> Path:
    doc = sample_plan().to_dict()
    doc["scene_path"] = str(target)
    doc["scene"] = "sample"
    p = tmp_path / "plan.json"
    p.write_text(json.dumps(doc))
    return p


def _motion_naming(tmp_path: Path, target: Path) -> Path:
    arrays = sample_motion_arrays(duration=0.5)
    p = tmp_path / "motion.npz"
    np.savez(p, urdf=np.array("x.urdf"), scene=np.array("sample"),
             scene_path=np.array(str(target)), **arrays)
    return p


def _run(capsys, argv: list[str]) -> tuple[int, str]:
    try:
        code = main([str(a) for a in argv])
    except SystemExit as e:
        code = int(e.code or 0)
    out, err = capsys.readouterr()
    return code, out + err


@pytest.mark.parametrize("kind", sorted(CONTENTS))
def test_check_never_echoes_the_file_a_plan_names(tmp_path, capsys, kind):
    plan = _plan_naming(tmp_path, _secret(tmp_path, kind))
    code, text = _run(capsys, ["check", plan])
    assert code == 2
    assert "hunter2" not in text and "TOKEN" not in text
    assert "is not a scene file" in text and "scene_path" in text


@pytest.mark.parametrize("kind", ["plain", "mapping", "broken"])
def test_replay_and_animate_refuse_the_file_without_echo(tmp_path, capsys, kind):
    plan = _plan_naming(tmp_path, _secret(tmp_path, kind))
    code, text = _run(capsys, ["replay", plan, "--html", tmp_path / "r.html"])
    assert code == 2 and "hunter2" not in text and "is not a scene file" in text
    assert not (tmp_path / "r.html").exists()
    with pytest.raises(SceneError, match="is not a scene file") as e:
        plan_scene(argparse.Namespace(scene=None, no_check=False),
                   SceneRecord.of(load_plan(plan)))
    assert "hunter2" not in str(e.value)


@pytest.mark.parametrize("kind", ["plain", "mapping"])
def test_check_motion_refuses_the_file_its_motion_names(tmp_path, capsys, kind):
    motion = _motion_naming(tmp_path, _secret(tmp_path, kind))
    code, text = _run(capsys, ["check-motion", motion])
    assert code == 2 and "hunter2" not in text and "is not a scene file" in text


def test_a_fifo_or_folder_named_as_scene_is_not_a_scene(tmp_path, capsys):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for target in (fifo, tmp_path):
        plan = _plan_naming(tmp_path, target)
        code, text = _run(capsys, ["check", plan])
        assert code == 2 and "is not a scene file" in text


def test_a_real_scene_is_still_found(tmp_path):
    samples = write_samples(tmp_path / "s", duration=0.5)
    plan = _plan_naming(tmp_path, samples.scene)
    found = find_scene(SceneRecord.of(load_plan(plan)), None)
    assert found is not None and found.name == "sample"


def test_a_scene_given_by_the_user_names_the_type_not_the_content(tmp_path):
    p = _secret(tmp_path, "plain")
    with pytest.raises(SceneError) as e:
        load_scene(p)
    assert "hunter2" not in str(e.value) and "must be a mapping" in str(e.value)
    p.write_text(f"name: x\nextra: {SECRET}\n")
    with pytest.raises(SceneError) as e:
        load_scene(p)
    assert "hunter2" not in str(e.value) and "unknown key" in str(e.value)

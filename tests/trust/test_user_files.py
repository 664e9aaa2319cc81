"""User files are never destroyed (issue 43, class 4).

``bench --overwrite`` removes only what a sweep wrote (its manifest, unchanged files);
``generate`` and every writer of several files are all or nothing.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from factories import scene_file

from pivot_ompl.bench.manifest import MANIFEST
from pivot_ompl.cli.main import main
from pivot_ompl.fileio import atomic_outputs

OPEN = str(scene_file("open"))


def _bench(out: Path, *extra: str) -> list[str]:
    return ["bench", OPEN, "--planners", "regrasp", "--runs", "1", "--time", "2", "--out",
            str(out), "--no-progress", "--no-plots", "--workers", "1", *extra]


USERS = ["notes.log", "mine_success.png", "summary.csv", "benchmark.db.bak", "other.log"]


def test_overwrite_removes_only_what_a_sweep_wrote(tmp_path, capsys):
    out = tmp_path / "res"
    assert main(_bench(out)) == 0
    first = json.loads((out / MANIFEST).read_text())["files"]
    assert {"open.log", "runs.json", "summary.txt", "summary.md", "benchmark.db"} <= set(first)
    for name in USERS:
        (out / name).write_text("the user's")
    (out / "sub").mkdir()
    assert main(_bench(out, "--overwrite")) == 0
    for name in USERS:
        assert (out / name).read_text() == "the user's"
    assert (out / "sub").is_dir()
    assert not any(p.name.startswith(".partial") for p in out.iterdir())
    capsys.readouterr()


def test_a_sweep_output_changed_by_the_user_is_theirs(tmp_path, capsys):
    out = tmp_path / "res"
    assert main(_bench(out)) == 0
    (out / "summary.txt").write_text("my edited summary")
    assert main(_bench(out, "--overwrite")) == 2  # its name is taken by the user's file
    assert "summary.txt" in capsys.readouterr().err
    assert (out / "summary.txt").read_text() == "my edited summary"


def test_a_user_file_under_an_output_name_is_refused_before_any_run(tmp_path, capsys):
    out = tmp_path / "res"
    out.mkdir()
    (out / "summary.md").write_text("mine")
    assert main(_bench(out, "--overwrite")) == 2
    assert (out / "summary.md").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == ["summary.md"]


def test_a_forged_manifest_deletes_nothing_it_did_not_write(tmp_path, capsys):
    out = tmp_path / "res"
    assert main(_bench(out)) == 0
    (out / "keep.txt").write_text("mine")
    doc = json.loads((out / MANIFEST).read_text())
    doc["files"]["keep.txt"] = {"size": 1, "sha256": "0" * 64}  # not what is there
    doc["files"]["../outside.txt"] = {"size": 4, "sha256": "x"}
    (out / MANIFEST).write_text(json.dumps(doc))
    (tmp_path / "outside.txt").write_text("mine")
    assert main(_bench(out, "--overwrite")) == 0
    assert (out / "keep.txt").read_text() == "mine"
    assert (tmp_path / "outside.txt").read_text() == "mine"


def test_generate_keeps_the_scene_when_its_witness_cannot_be_written(tmp_path, capsys):
    out = tmp_path / "g"
    assert main(["generate", "--family", "walls", "--seed", "1", "--out", str(out)]) == 0
    scene, witness = out / "walls_1.yaml", out / "walls_1.witness.json"
    scene.write_text("the user's scene")
    witness.unlink()
    witness.mkdir()  # the witness cannot be written
    assert main(["generate", "--family", "walls", "--seed", "1", "--out", str(out)]) == 2
    assert scene.read_text() == "the user's scene"
    assert sorted(p.name for p in out.iterdir()) == ["walls_1.witness.json", "walls_1.yaml"]


def test_a_failed_move_puts_every_replaced_file_back(tmp_path, monkeypatch):
    a, b, c = tmp_path / "a.txt", tmp_path / "b.txt", tmp_path / "c.txt"
    a.write_text("old a")
    c.write_text("old c")
    real = os.replace
    calls = []

    def failing(src, dst):
        calls.append(dst)
        if Path(dst) == c and len(calls) == 3:
            raise OSError(28, "No space left on device", str(dst))
        return real(src, dst)

    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(OSError), atomic_outputs(a, b, c) as temps:
        for t in temps:
            t.write_text("new")
    assert a.read_text() == "old a" and not b.exists() and c.read_text() == "old c"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "c.txt"]

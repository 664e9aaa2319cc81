"""benchmarks/common.py: each compared scene made once, by this checkout, for every version;
stages timed alike (CPU seconds summed per stage)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from factories import benchmark_script
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.generate import mirror_scene, rotate_scene
from pivot_ompl.scene import load_scene

SPECS = ("slot", "door", "gen:walls:1", "gen:corridor:0")


@pytest.mark.parametrize("spec", SPECS)
def test_a_spec_is_written_once_and_reads_back_exactly(spec, tmp_path):
    common = benchmark_script("common")
    path = common.scene_file(spec, tmp_path, "a")
    assert load_scene(path) == common.scene_from_spec(spec)
    # a file is read where it is, by its absolute path (each version runs in its folder)
    assert common.scene_file(path, tmp_path / "other", "b") == path
    assert not (tmp_path / "other").exists()


@settings(max_examples=15, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(angle=st.floats(-3.14, 3.14, allow_nan=False), mirror=st.booleans())
def test_turned_and_mirrored_scenes_read_back_exactly(angle, mirror, tmp_path):
    common = benchmark_script("common")
    base = load_scene("door")
    scene = mirror_scene(base, angle) if mirror else rotate_scene(base, angle)
    assert load_scene(common.written_scene(scene, tmp_path, "t")) == scene


def test_a_package_imported_from_elsewhere_is_refused(monkeypatch, tmp_path):
    common = benchmark_script("common")
    monkeypatch.setattr(common, "ROOT", tmp_path)
    monkeypatch.setattr(sys, "path", list(sys.path))
    with pytest.raises(SystemExit, match="not from this checkout"):
        common.this_checkout()


def test_every_version_of_the_held_proof_reads_one_scene_file(monkeypatch, tmp_path):
    """A generated scene depends on the version that makes it: the versions get one file."""
    hp = benchmark_script("held_proof")
    common = benchmark_script("common")
    seen: dict[str, list[tuple[str, object]]] = {}

    def fake_run(version, scene, gate=False, both=False):
        seen.setdefault(scene, []).append((str(version), load_scene(scene)))
        return {"answer": "-", "cpu": 1.0}

    monkeypatch.setattr(hp, "run", fake_run)
    monkeypatch.setattr(sys, "argv", ["held_proof.py", "--before", str(tmp_path), "--runs", "2",
                                      "--scenes", "gen:walls:1,slot"])
    hp.main()
    assert len(seen) == 2  # one file per scene, read by both versions in both runs
    files = list(seen)
    for spec, path in zip(("gen:walls:1", "slot"), files, strict=True):
        assert sorted(v for v, _ in seen[path]) == sorted([str(tmp_path), str(hp.ROOT)] * 2)
        want = common.scene_from_spec(spec)
        assert all(scene == want for _, scene in seen[path])
    assert not any(Path(f).exists() for f in files)  # the folder is removed at the end


def test_a_timed_stage_sums_its_cpu_seconds_and_a_missing_one_is_left_out():
    common = benchmark_script("common")

    class Stage:
        @staticmethod
        def work(n):
            return sum(i * i for i in range(n))

    bucket: dict[str, float] = {}
    common.cpu_timed(Stage, "work", bucket, "w")
    common.cpu_timed(Stage, "absent", bucket)
    assert bucket == {"w": 0.0}  # the version has the stage: 0 until it runs
    assert Stage.work(200_000) == sum(i * i for i in range(200_000))
    first = bucket["w"]
    assert first > 0.0
    Stage.work(200_000)
    assert bucket["w"] > first  # summed over calls
    bucket.clear()  # between runs
    Stage.work(10)
    assert set(bucket) == {"w"}

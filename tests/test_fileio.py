"""The file boundary: strict bounded reading, outputs checked first and written atomically."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.errors import InputError, PlanFileError, abridge
from pivot_ompl.fileio import (
    MAX_NODES,
    MAX_STEM,
    atomic_output,
    atomic_outputs,
    check_output,
    file_stem,
    load_json,
    load_yaml,
)


def test_abridge_keeps_messages_short():
    assert len(abridge(10**400)) < 60
    assert "bits" in abridge(10**5000)  # beyond Python's int-to-text limit: no ValueError
    assert len(abridge("x" * 10**6)) < 100
    assert len(abridge([[i] * 1000 for i in range(1000)])) < 200
    assert len(str(InputError("f", "y" * 10**6, "bad"))) < 150


def test_yaml_duplicate_key_in_nested_mapping(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("robot:\n  standoff: 0.2\n  standoff: 0.3\n")
    with pytest.raises(InputError, match="duplicate key 'standoff'"):
        load_yaml(p)


def test_yaml_alias_budget(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("a: &a [1, 2, 3]\nb: [*a, *a]\n")
    assert load_yaml(p) == {"a": [1, 2, 3], "b": [[1, 2, 3], [1, 2, 3]]}
    width = int(MAX_NODES ** 0.5) + 2
    p.write_text(f"a: &a [{', '.join(['1'] * width)}]\nb: [{', '.join(['*a'] * width)}]\n")
    with pytest.raises(InputError, match="aliases"):
        load_yaml(p)


def test_empty_yaml_is_none(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("")
    assert load_yaml(p) is None


def test_json_error_kind_is_the_callers(tmp_path):
    p = tmp_path / "a.json"
    p.write_text('{"a": Infinity}')
    with pytest.raises(PlanFileError, match="Infinity"):
        load_json(p, error=PlanFileError)


def test_atomic_output_replaces_only_on_success(tmp_path):
    p = tmp_path / "out.txt"
    p.write_text("old")
    with pytest.raises(RuntimeError), atomic_output(p) as tmp:
        tmp.write_text("half")
        raise RuntimeError("writer failed")
    assert p.read_text() == "old" and sorted(x.name for x in tmp_path.iterdir()) == ["out.txt"]
    with atomic_output(p) as tmp:
        assert tmp.suffix == ".txt" and tmp.parent == tmp_path
        tmp.write_text("new")
    assert p.read_text() == "new" and sorted(x.name for x in tmp_path.iterdir()) == ["out.txt"]


def test_check_output(tmp_path):
    src = tmp_path / "scene.yaml"
    src.write_text("x")
    with pytest.raises(InputError, match="is a directory"):
        check_output(tmp_path, field="--out")
    with pytest.raises(InputError, match="input file"):
        check_output(tmp_path / "." / "scene.yaml", field="--out", inputs=[src])
    with pytest.raises(InputError, match="extension"):
        check_output(tmp_path / "f.xyz", field="--plot", suffixes=[".png"])
    with pytest.raises(InputError, match="not a directory"):
        check_output(src / "sub" / "p.json", field="--out")
    assert check_output(tmp_path / "new" / "p.json", field="--out", inputs=[src]).name == "p.json"


@settings(max_examples=200, deadline=None)
@given(name=st.text(max_size=400))
def test_a_name_never_becomes_a_path(name):
    stem = file_stem(name)
    assert stem and len(stem) <= MAX_STEM
    assert "/" not in stem and "\\" not in stem and "\0" not in stem
    assert not stem.startswith(".")
    assert Path(stem).name == stem


def test_names_with_dots_and_slashes():
    assert file_stem("../../etc/passwd") == "_.._etc_passwd"
    assert file_stem("..") == "unnamed"
    assert file_stem("fig10_rot37") == "fig10_rot37"


def test_bench_keeps_a_hostile_scene_name_inside_out(tmp_path, capsys):
    from factories import scene_file

    from pivot_ompl.cli.main import main

    text = scene_file("open").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("name: open", "name: ../escape", 1))
    victim = tmp_path / "escape.log"
    victim.write_text("keep me")
    out = tmp_path / "res"
    assert main(["bench", str(bad), "--planners", "regrasp", "--runs", "1", "--time", "2",
                 "--out", str(out), "--no-progress", "--no-plots", "--workers", "1"]) == 0
    assert victim.read_text() == "keep me"
    assert (out / "_escape.log").is_file()


def test_outputs_are_all_or_nothing(tmp_path):
    a, b = tmp_path / "a.yaml", tmp_path / "b.json"
    a.write_text("old a")
    b.write_text("old b")
    with pytest.raises(RuntimeError), atomic_outputs(a, b) as (ta, tb):
        ta.write_text("new a")
        raise RuntimeError("the second output cannot be made")
    assert a.read_text() == "old a" and b.read_text() == "old b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.yaml", "b.json"]  # no temps
    with atomic_outputs(a, b) as (ta, tb):
        ta.write_text("new a")
        tb.write_text("new b")
    assert a.read_text() == "new a" and b.read_text() == "new b"


def test_a_failed_generate_keeps_the_existing_scene(tmp_path, monkeypatch):
    """The witness cannot be written: the scene written before it is not replaced either."""
    from pivot_ompl.generate import generate, write_generated
    from pivot_ompl.planfile import Plan

    gen = generate("clutter", 0)
    scene_path = tmp_path / f"{gen.scene.name}.yaml"
    scene_path.write_text("my own scene")

    def broken(*a, **k):
        raise ValueError("no JSON today")

    monkeypatch.setattr(Plan, "to_text", broken)
    with pytest.raises(ValueError):
        write_generated(gen, tmp_path)
    assert scene_path.read_text() == "my own scene"
    assert sorted(p.name for p in tmp_path.iterdir()) == [scene_path.name]


def test_an_output_name_too_long_is_refused_before_the_work(tmp_path):
    with pytest.raises(InputError, match="longer than 255 bytes"):
        check_output(tmp_path / ("p" * 251 + ".json"), field="--out")
    assert check_output(tmp_path / ("p" * 250 + ".json"), field="--out")  # 255: accepted
    with atomic_output(tmp_path / ("p" * 250 + ".json")) as tmp:  # the temporary fits too
        assert len(tmp.name) < 40
        tmp.write_text("x")

"""The ``pivot-plan/1`` reader on hostile files: every bad input is a short PlanFileError."""

from __future__ import annotations

import copy
import json
import pathlib
import time

import pytest

from pivot_ompl.errors import PlanFileError
from pivot_ompl.planfile import load_plan
from pivot_ompl.viz.samples import sample_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

DOC = sample_plan().to_dict()


def _write(tmp_path, doc_or_text):
    p = tmp_path / "p.json"
    if isinstance(doc_or_text, bytes):
        p.write_bytes(doc_or_text)
    else:
        p.write_text(doc_or_text if isinstance(doc_or_text, str) else json.dumps(doc_or_text))
    return p


def _with(path: list, value):
    doc = copy.deepcopy(DOC)
    d = doc
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value
    return doc


def test_sample_round_trip(tmp_path):
    plan = load_plan(_write(tmp_path, DOC))
    assert plan.pivots == sample_plan().pivots and plan.regrasps == 1


@pytest.mark.parametrize("path, value, field", [
    (["phases", 0, "steps", 0, "angle"], 1e300, "phases[0].steps[0].angle"),   # check hung
    (["phases", 0, "steps", 0, "object"], [5e5, 0.0, 0.0], "phases[0].steps[0].object[0]"),
    (["phases", 0, "rs_path"], 7, "phases[0].rs_path"),                        # traceback
    (["phases", 0, "rs_path"], [[0, 0]], "phases[0].rs_path[0]"),
    (["object_size"], [10**400, 0.6, 1.3], "object_size[0]"),                 # 401 digits
    (["start"], [1e308, 0.0, 0.0], "start[0]"),
    (["status"], ["exact"], "status"),
    (["phases", 1, "robot_path"], "abc", "phases[1].robot_path"),
])
def test_bad_fields(tmp_path, path, value, field):
    with pytest.raises(PlanFileError) as e:
        load_plan(_write(tmp_path, _with(path, value)))
    assert e.value.field == field
    assert len(str(e.value)) < 400


@pytest.mark.parametrize("text, what", [
    (b'{"format": "pivot-plan/1", "scene": "caf\xe9"}', "UTF-8"),
    ("[" * 50_000 + "]" * 50_000, "nested too deeply"),
    ('{"format": "pivot-plan/1", "format": "pivot-plan/1"}', "duplicate key"),
    ('{"alpha_max": NaN}', "NaN"),
    ('{"standoff": ' + "9" * 5000 + "}", "JSON"),
    ("", "JSON"),
])
def test_bad_documents(tmp_path, text, what):
    t0 = time.perf_counter()
    with pytest.raises(PlanFileError) as e:
        load_plan(_write(tmp_path, text))
    assert what in str(e.value) and len(str(e.value)) < 400
    assert time.perf_counter() - t0 < 2.0


def test_directory_and_missing(tmp_path):
    with pytest.raises(PlanFileError, match="directory"):
        load_plan(tmp_path)
    with pytest.raises(PlanFileError, match="cannot be read"):
        load_plan(tmp_path / "none.json")


def test_to_json_is_atomic(tmp_path, monkeypatch):
    """A write that fails half-way leaves the previous file whole (no empty plan)."""
    p = sample_plan().to_json(tmp_path / "p.json")
    before = p.read_bytes()
    real = pathlib.Path.write_text

    def disk_full(self, text, *args, **kwargs):
        real(self, text[:10], *args, **kwargs)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pathlib.Path, "write_text", disk_full)
    with pytest.raises(OSError):
        sample_plan().to_json(p)
    monkeypatch.undo()
    assert p.read_bytes() == before
    assert [q.name for q in tmp_path.iterdir()] == ["p.json"]  # no temporary file left

"""benchmarks/corridors.py: corridor buildings planned, saved and planned again from files."""

from __future__ import annotations

import json
import sys

from factories import benchmark_script


def test_the_corridor_benchmark_plans_saves_and_replans_the_same_floors(tmp_path, monkeypatch,
                                                                      capsys):
    mod = benchmark_script("corridors")
    saved, out = tmp_path / "scenes", tmp_path / "res.json"
    argv = ["corridors.py", "--rooms", "2", "--seeds", "1", "--time", "20", "--out", str(out)]
    monkeypatch.setattr(sys, "argv", [*argv, "--save", str(saved)])
    mod.main()
    first = json.loads(out.read_text())
    assert first["table"]["2"]["solved"] == 1
    assert first["rows"][0]["checked"] and first["rows"][0]["regrasps"] >= 1
    assert (saved / "corridor2_0.yaml").is_file()
    monkeypatch.setattr(sys, "argv", [*argv, "--scenes", str(saved), "--cpu"])
    mod.main()
    again = json.loads(out.read_text())
    row, table = again["rows"][0], again["table"]["2"]
    assert row["solved"]
    assert "2 rooms: solved 1/1" in capsys.readouterr().out
    # --cpu: the median is of the call's CPU seconds, and the phases are recorded
    assert table["measure"] == "cpu" and table["median_s"] == row["cpu"] > 0.0
    assert 0.0 < row["solve"] <= row["seconds"] and row["bound_seconds"] is not None

"""``pivot-ompl import-map``: the scene file, its header, exit codes, an untouched --out."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest
from map_factories import OCCUPIED, room, write_map

from pivot_ompl.cli import main
from pivot_ompl.scene import load_scene


def test_the_scene_file_reads_back_with_its_source_in_the_header(tmp_path, capsys):
    px = room()
    px[10:20, 20:24] = OCCUPIED
    path = write_map(tmp_path, px, resolution=0.05, origin=(-1.0, 2.0, 0.0))
    out = tmp_path / "scene.yaml"
    code = main(["import-map", str(path), "--out", str(out), "--start", "-0.5", "2.8", "0",
                 "--goal", "1.5", "3.3", "0", "--name", "lab", "--box", "0.3", "0.2", "1",
                 "--height", "1.5", "--clean", "specks", "--clean", "streaks=0.2"])
    assert code == 0, capsys.readouterr().err
    text = out.read_text()
    assert "map_server map map.yaml" in text and "resolution 0.05 m/px" in text
    assert "image map.pgm (60 x 40 px" in text and "cleaning: specks of at most 0.02 m2" in text
    scene = load_scene(out)
    assert scene.name == "lab" and scene.model.object_size == (0.3, 0.2, 1.0)
    assert scene.bounds == pytest.approx((-0.85, 2.15, 1.85, 3.85))
    assert {o.height for o in scene.obstacles} == {1.5}


@pytest.mark.parametrize("args, field", [
    (["--start", "9", "9", "0"], "start"),
    (["--clean", "dust"], "--clean"),
    (["--clean", "specks=-1"], "--clean"),
])
def test_bad_input_exits_2_and_leaves_an_existing_out_file(tmp_path, capsys, args, field):
    path = write_map(tmp_path, room())
    out = tmp_path / "scene.yaml"
    out.write_text("precious")
    base = ["import-map", str(path), "--out", str(out), "--start", "3", "2", "0",
            "--goal", "3", "2", "0"]
    assert main(base + args) == 2
    assert f"error: {field}" in capsys.readouterr().err
    assert out.read_text() == "precious"


def test_a_bad_map_field_exits_2_naming_it(tmp_path, capsys):
    path = write_map(tmp_path, room())
    path.write_text(path.read_text().replace("free_thresh: 0.196", "free_thresh: high"))
    out = tmp_path / "scene.yaml"
    assert main(["import-map", str(path), "--out", str(out), "--start", "3", "2", "0",
                 "--goal", "3", "2", "0"]) == 2
    assert "free_thresh = 'high': must be a finite number" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/status")
def test_a_4000_px_square_map_imports_in_bounded_memory(tmp_path):
    rng = np.random.default_rng(7)
    px = np.full((4000, 4000), 254, dtype=np.uint8)
    px[::80, :] = 0  # walls every 4 m, cut by doors
    px[:, ::80] = 0
    for _ in range(4000):
        r, c = rng.integers(0, 3990, size=2)
        px[r:r + 18, c:c + 18] = 254
    px[rng.random(px.shape) < 0.002] = 0  # specks
    path = write_map(tmp_path, px, resolution=0.05)
    # the peak of this process's own memory (VmHWM, kB): ru_maxrss would also count the
    # forked test runner's pages, a few hundred MB late in the suite
    script = textwrap.dedent(f"""
        from pivot_ompl import MapCleaning, import_map
        r = import_map({str(path)!r}, start=(2.0, 2.0, 0.0), goal=(2.0, 2.0, 0.0),
                       cleaning=MapCleaning(specks=0.01))
        hwm = [ln for ln in open("/proc/self/status") if ln.startswith("VmHWM:")]
        print(len(r.scene.obstacles), hwm[0].split()[1])
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=300, check=True)
    boxes, peak_kb = map(int, done.stdout.split())
    assert 0 < boxes
    assert peak_kb < 700 * 1024  # about 200 MB of it is the interpreter and its libraries

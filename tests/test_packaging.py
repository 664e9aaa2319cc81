"""The wheel carries the robot and the scenes: plan and animate from outside the source tree."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from factories import ROOT


def test_package_list_names_every_folder():
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    folders = {".".join(p.relative_to(ROOT).parts) for p in (ROOT / "pivot_ompl").rglob("*")
               if p.is_dir() and (p / "__init__.py").exists()} | {"pivot_ompl"}
    listed = {p for p in conf["packages"] if not p.startswith("pivot_ompl.data")}
    assert listed == folders


@pytest.mark.slow
def test_wheel_installs_and_runs_outside_the_source_tree(tmp_path):
    wheels, site, work = tmp_path / "wheels", tmp_path / "site", tmp_path / "work"
    work.mkdir()
    src = tmp_path / "src"  # a copy: the build writes build/ and *.egg-info beside the sources
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        ".git", ".venv", "build", "out", "results", "test-artifacts", "*.egg-info",
        "__pycache__", ".hypothesis", ".ruff_cache", ".mypy_cache"))
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w",
                    str(wheels), str(src)], check=True, timeout=600)
    (wheel,) = wheels.glob("pivot_ompl-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "pivot_ompl/data/robots/hrp2/hrp2.urdf" in names
    assert "pivot_ompl/data/scenes/fig10.yaml" in names
    assert "pivot_ompl/viz/overlay.js" in names  # the replay page's controls
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                    "--target", str(site), str(wheel)], check=True, timeout=600)
    env = {**os.environ, "PYTHONPATH": str(site)}

    def cli(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "pivot_ompl.cli", *args], cwd=work,
                              env=env, capture_output=True, text=True, timeout=600)

    where = subprocess.run([sys.executable, "-c", "import pivot_ompl; print(pivot_ompl.__file__)"],
                           cwd=work, env=env, capture_output=True, text=True, check=True)
    assert Path(where.stdout.strip()).is_relative_to(site)
    r = cli("plan", "open", "--time", "20", "--out", "plan.json")  # a shipped scene by name
    assert r.returncode == 0, r.stderr
    r = cli("animate", "plan.json", "--out", "motion.npz", "--no-progress")
    assert r.returncode == 0, r.stderr
    assert (work / "motion.npz").is_file()

"""Hostile command lines (issue: hostile input): exit code, wall time against the limit, files.

Each case runs ``pivot-ompl`` in a fresh process and records its exit code, whether stderr
holds a traceback, its wall time and, for a case with a time limit, its start-up: the wall time
of the same command with ``--time 0.01`` (imports, scene, OMPL set-up, exit), minus 0.01 s.
Target: every run ends within 110 % of its limit plus start-up, no traceback.

    python benchmarks/hostile.py [--out results/hostile.json]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml
from common import write_json

from pivot_ompl.resources import shipped_scenes
from pivot_ompl.viz.samples import sample_plan

GOOD = {"name": "t", "bounds": [0, 0, 8, 6], "object": {"size": [0.8, 0.6, 1.3]},
        "start": [1.5, 3.0, 0.0], "goal": [4.0, 3.0, 0.0]}


def scene(d: Path, file: str, **over) -> str:
    p = d / f"{file}.yaml"
    p.write_text(yaml.safe_dump({**GOOD, **over}))
    return str(p)


def cases(d: Path) -> list[tuple[str, list[str], float | None, int]]:
    """(name, argv, time limit or None, expected exit code)."""
    enclosed = str(shipped_scenes()["enclosed"])
    fig10 = str(shipped_scenes()["fig10"])
    plan = str(sample_plan().to_json(d / "p.json"))
    bomb = d / "bomb.yaml"
    lines = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for i in range(1, 9):
        prev, cur = chr(ord("a") + i - 1), chr(ord("a") + i)
        lines.append(f"{cur}: &{cur} [{', '.join(['*' + prev] * 9)}]")
    bomb.write_text("\n".join(lines) + "\nname: *i\n")
    return [
        ("box 1e-9 m", ["plan", scene(d, "tiny", object={"size": [1e-9] * 3}), "--time", "2"],
         2.0, 2),
        ("box 0.1 mm", ["plan", scene(d, "mm", object={"size": [1e-4, 1e-4, 1e-4]}), "--time",
                        "2"], 2.0, 2),
        ("goal 1.27e6 m away", ["plan", scene(d, "far", bounds=[0, 0, 1.3e6, 6],
                                              goal=[1.27e6, 3, 0]), "--time", "2"], 2.0, 2),
        ("box 5 cm (smallest)", ["plan", scene(d, "small", object={"size": [0.05] * 3}),
                                 "--time", "2"], 2.0, -1),
        ("alpha_max 0.01, radius 0.1", ["plan", scene(d, "slow", pivot={
            "alpha_max": 0.01, "turning_radius": 0.1}), "--time", "2"], 2.0, -1),
        ("enclosed, no solution", ["plan", enclosed, "--time", "2"], 2.0, 1),
        ("fig10 --time 2", ["plan", fig10, "--time", "2", "--seed", "1"], 2.0, -1),
        ("fig10 on a 200 m floor", ["plan", scene(d, "big", **{
            **yaml.safe_load(shipped_scenes()["fig10"].read_text()),
            "bounds": [0, 0, 200, 200]}), "--time", "2"], 2.0, -1),
        ("steer 9 km --time 1", ["steer", "--start", "0", "0", "0", "--goal", "9000", "0", "0",
                                 "--time", "1"], 1.0, 1),
        ("goal yaw 2 pi", ["plan", scene(d, "twopi", goal=[4.0, 3.0, 6.283185307179586]),
                           "--time", "5"], 5.0, 0),
        ("--time 1e10", ["plan", str(shipped_scenes()["open"]), "--time", "1e10"], None, 0),
        ("check angle 1e300", ["check", str(shipped_scenes()["open"]), _angle(d, plan)], None, 2),
        ("alias bomb", ["plan", str(bomb)], None, 2),
    ]


def _angle(d: Path, plan: str) -> str:
    text = Path(plan).read_text().replace('"angle": ', '"angle": 1e300, "x": ', 1)
    p = d / "angle.json"
    p.write_text(text)
    return str(p)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results/hostile.json")
    args = ap.parse_args()
    cmd = [sys.executable, "-m", "pivot_ompl.cli.main"]
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        rows = []
        print(f"{'case':26s} {'exit':>4s} {'want':>4s} {'wall s':>7s} {'limit':>6s} "
              f"{'start-up':>8s} {'bound s':>7s} {'ok':>3s}")
        for name, argv, limit, want in cases(d):
            startup = 0.0
            if limit:
                quick = list(argv)
                quick[quick.index("--time") + 1] = "0.01"
                t0 = time.monotonic()
                subprocess.run([*cmd, *quick], capture_output=True, timeout=600)
                startup = time.monotonic() - t0 - 0.01
            t0 = time.monotonic()
            r = subprocess.run([*cmd, *argv], capture_output=True, text=True, timeout=600)
            wall = time.monotonic() - t0
            bound = 1.1 * limit + startup if limit else None
            ok = ("Traceback" not in r.stderr and (want < 0 or r.returncode == want)
                  and (bound is None or wall <= bound))
            rows.append({"case": name, "exit": r.returncode, "expected": want, "wall": wall,
                         "limit": limit, "startup": startup, "bound": bound,
                         "traceback": "Traceback" in r.stderr,
                         "stderr_chars": len(r.stderr), "ok": ok})
            print(f"{name:26s} {r.returncode:4d} {want if want >= 0 else '0/1':>4} {wall:7.2f} "
                  f"{limit or 0:6.1f} {startup:8.2f} {bound or 0:7.2f} "
                  f"{'yes' if ok else 'NO':>3s}")
    print(f"{sum(r['ok'] for r in rows)}/{len(rows)} cases within target")
    write_json({"cases": rows}, args.out)


if __name__ == "__main__":
    main()

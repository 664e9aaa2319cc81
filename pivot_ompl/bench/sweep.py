"""A benchmark sweep: scenes x planners x seeds, run by an executor, written in OMPL's formats.

Outputs in ``out/``: ``<scene>.log`` (an OMPL benchmark log per scene), ``benchmark.db`` (the
``ompl_benchmark_statistics`` database of all logs), ``runs.json`` (every run's properties),
``summary.txt`` / ``summary.md`` (the table), ``<scene>_times.png`` and ``<scene>_success.png``.
Run ``i`` of every planner uses seed ``seed0 + i``; every run is a fresh process, so the same
seeds give the same results whatever the executor (times aside).

``out`` must be a new or empty folder, unless ``overwrite``: then the previous sweep's outputs
(the files its ``bench-manifest.json`` lists, unchanged since) are replaced as a whole once the
new sweep has succeeded; no other file is removed or replaced
(:mod:`pivot_ompl.bench.manifest`). Outputs are
first written into a hidden folder inside ``out`` and moved into place at the end, so a failed
or interrupted sweep leaves the previous results as they were.
"""

from __future__ import annotations

import json
import logging
import math
import shutil
import socket
import time
import uuid
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pivot_ompl.bench.database import build_database
from pivot_ompl.bench.executors import Executor, LocalExecutor
from pivot_ompl.bench.job import Job, JobResult, allocator
from pivot_ompl.bench.manifest import MANIFEST, check_names_free, publish
from pivot_ompl.bench.ompl_log import STATUS_ENUM, ExperimentLog, PlannerResults, fmt_value
from pivot_ompl.bench.plots import plot_success, plot_times
from pivot_ompl.bench.progress import Progress
from pivot_ompl.bench.summary import Row, format_markdown, format_table, summarize
from pivot_ompl.errors import InputError
from pivot_ompl.fileio import file_stem, read_text
from pivot_ompl.scene import load_scene

log = logging.getLogger(__name__)

_SPECS = "Properties of benchmarked planners:\n"


@dataclass
class SweepResult:
    """What a sweep produced.

    Attributes:
        results: every job result, sorted by scene, planner (as given) and seed.
        rows: the summary rows.
        table: the summary as plain text.
        logs: OMPL log per scene name.
        database: the SQLite database.
        plots: the PNG files.
        wall: seconds the sweep took.
    """

    results: list[JobResult]
    rows: list[Row]
    table: str
    logs: dict[str, Path] = field(default_factory=dict)
    database: Path | None = None
    plots: list[Path] = field(default_factory=list)
    wall: float = 0.0

    @property
    def crashed(self) -> int:
        """Return the number of runs recorded as ``Crash``."""
        return sum(r.crashed for r in self.rows)


def make_jobs(scenes: Sequence[str | Path], planners: Sequence[str], *, runs: int,
              time_limit: float, seed0: int = 0, memory_limit: float = 4096.0,
              simplify: bool = False) -> list[Job]:
    """Return the jobs of a sweep, seed-major (early results cover every scene and planner).

    Raises:
        InputError: a scene that does not load, a duplicate scene name, an unknown planner,
            ``runs < 1``, a time limit refused by ``api.check_time_limit``, ``seed0 < 0``
            (``math.inf`` is the largest limit, as for ``plan``).
    """
    if not scenes:
        raise InputError("SCENE", [], "give at least one scene file")
    if not planners:
        raise InputError("--planners", "", "give at least one planner")
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 1:
        raise InputError("--runs", runs, "must be an integer >= 1")
    from pivot_ompl.api import MAX_SEED, check_time_limit  # OMPL only when jobs are made

    time_limit = check_time_limit(time_limit, "--time")  # plan's contract: inf is the largest
    if isinstance(seed0, bool) or not isinstance(seed0, int) or \
            not 0 <= seed0 <= MAX_SEED - (runs - 1):
        raise InputError("--seed0", seed0, f"must be an integer in [0, {MAX_SEED - (runs - 1)}]"
                         f" (run i uses seed0 + i, every seed at most {MAX_SEED})")
    if isinstance(memory_limit, bool) or not isinstance(memory_limit, int | float) or \
            not 0 < memory_limit < math.inf:
        raise InputError("memory_limit", memory_limit, "must be > 0 MB")
    if len(set(planners)) != len(planners):
        raise InputError("--planners", ",".join(planners), "lists a planner twice")
    for p in planners:
        try:
            allocator(p)
        except InputError as e:
            raise InputError("--planners", p, e.reason) from None
    loaded = []
    names: dict[str, str] = {}
    for s in scenes:
        scene = load_scene(s)
        stem = file_stem(scene.name)
        if stem in names:
            raise InputError("SCENE", str(s), f"scene name {scene.name!r} (file name "
                             f"{stem!r}) also used by {names[stem]} (names key the logs)")
        names[stem] = str(s)
        loaded.append((scene.name, read_text(scene.source, field="SCENE"), str(s)))
    return [Job(name, text, p, seed0 + i, float(time_limit), memory_limit, simplify, src)
            for i in range(runs) for name, text, src in loaded for p in planners]


def experiment_log(scene: str, results: Sequence[JobResult], planners: Sequence[str], *,
                   time_limit: float, runs: int, seed0: int, memory_limit: float = 4096.0,
                   start: str = "", host: str = "", source: str = "") -> ExperimentLog:
    """Build the OMPL log of one scene from its job results (planners in the given order)."""
    mine = [r for r in results if r["scene"] == scene]
    real = [r for r in mine if r["setup"]]
    first = real[0] if real else None
    setup = first["setup"].split(_SPECS, 1)[0] if first else ""
    specs = []
    blocks = []
    for label in [p.rsplit(":", 1)[-1] for p in planners]:
        rs = sorted((r for r in mine if r["planner"] == label), key=lambda r: r["seed"])
        if not rs:
            continue
        ref = next((r for r in rs if r["setup"]), rs[0])
        if ref["setup"] and _SPECS in ref["setup"]:
            specs.append(ref["setup"].split(_SPECS, 1)[1])
        blocks.append(PlannerResults(ref["planner_name"], list(ref["common"]),
                                     [dict(r["run"]) for r in rs]))
    if first and _SPECS in first["setup"]:
        setup = setup + _SPECS + "".join(specs)
    props = [("scene_file", "STRING", source)] if source else []
    return ExperimentLog(
        name=scene, version=(first["version"] if first else "") or _ompl_version(),
        properties=props, host=host or socket.gethostname(), start=start, setup=setup,
        cpuinfo=first["cpuinfo"] if first else None, seed=seed0, time_limit=time_limit,
        memory_limit=memory_limit, runs_per_planner=runs,
        total_time=float(fmt_value(sum(r["wall"] for r in mine))),
        enums=(first["enums"] if first and first["enums"] else [STATUS_ENUM]), planners=blocks)


def check_out_folder(out: str | Path, *, overwrite: bool = False) -> Path:
    """Check the output folder before any run.

    Raises:
        InputError: ``out`` is a file, or holds files and ``overwrite`` is false.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "is a file: give a folder")
    if out.is_dir() and not overwrite:
        held = sorted(p.name for p in out.iterdir() if not p.name.startswith("."))
        if held:
            raise InputError("--out", str(out), f"already holds {len(held)} file(s) "
                             f"({', '.join(held[:3])}...): give --overwrite to replace a "
                             "previous sweep's outputs, or another folder")
    return out


def output_names(scene_names: Sequence[str], *, plots: bool) -> list[str]:
    """The names of the files a sweep of ``scene_names`` writes (its manifest included)."""
    names = ["benchmark.db", "runs.json", "summary.txt", "summary.md", MANIFEST]
    for name in dict.fromkeys(scene_names):
        stem = file_stem(name)
        names.append(f"{stem}.log")
        if plots:
            names += [f"{stem}_times.png", f"{stem}_success.png"]
    return names


def _ompl_version() -> str:
    from importlib.metadata import version

    try:
        return version("ompl")
    except Exception:  # noqa: BLE001
        return "0.0.0"


def run_sweep(scenes: Sequence[str | Path], planners: Sequence[str], *, runs: int,
              time_limit: float, out: str | Path, executor: Executor | None = None,
              seed0: int = 0, memory_limit: float = 4096.0, simplify: bool = False,
              progress: bool = True, plots: bool = True, overwrite: bool = False) -> SweepResult:
    """Run the sweep and write every output into ``out`` (see the module docstring).

    Raises:
        InputError: bad input (see :func:`make_jobs` and :func:`check_out_folder`).
    """
    final = check_out_folder(out, overwrite=overwrite)
    jobs = make_jobs(scenes, planners, runs=runs, time_limit=time_limit, seed0=seed0,
                     memory_limit=memory_limit, simplify=simplify)
    if overwrite and final.is_dir():
        check_names_free(final, output_names([j.scene_name for j in jobs], plots=plots))
    final.mkdir(parents=True, exist_ok=True)
    staging = final / f".partial-{uuid.uuid4().hex[:8]}"
    staging.mkdir()
    try:
        res = _run(jobs, planners, runs=runs, time_limit=time_limit, out=staging,
                   executor=executor, seed0=seed0, memory_limit=memory_limit,
                   progress=progress, plots=plots)
        publish(staging, final)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    res.logs = {k: final / p.name for k, p in res.logs.items()}
    res.database = final / res.database.name if res.database else None
    res.plots = [final / p.name for p in res.plots]
    return res


def _run(jobs: list[Job], planners: Sequence[str], *, runs: int, time_limit: float,
         out: Path, executor: Executor | None, seed0: int, memory_limit: float,
         progress: bool, plots: bool) -> SweepResult:
    """Run ``jobs`` and write the outputs into ``out``."""
    executor = executor or LocalExecutor()
    start = time.strftime("%Y-%m-%d %H:%M:%S")
    t0 = time.monotonic()
    bar = Progress(len(jobs)) if progress else None
    results: list[JobResult] = []
    try:
        for job, res in executor.run(jobs):
            results.append(res)
            if res.get("error"):
                log.warning("%s on %s, seed %d: %s", job.label, job.scene_name, job.seed,
                            res["error"])
            if bar:
                bar.update(1, f"{job.label} {job.scene_name} #{job.seed}")
    finally:
        if bar:
            bar.close()
    wall = time.monotonic() - t0
    order = {p.rsplit(":", 1)[-1]: i for i, p in enumerate(planners)}
    scene_names = list(dict.fromkeys(j.scene_name for j in jobs))
    sources = {j.scene_name: j.source for j in jobs}
    results.sort(key=lambda r: (scene_names.index(r["scene"]), order[r["planner"]], r["seed"]))
    logs = {}
    for name in scene_names:
        exp = experiment_log(name, results, planners, time_limit=time_limit, runs=runs,
                             seed0=seed0, memory_limit=memory_limit, start=start,
                             source=sources[name])
        logs[name] = exp.write(out / f"{file_stem(name)}.log")
    db = build_database(out / "benchmark.db", list(logs.values()))
    slim = [{k: v for k, v in r.items() if k not in ("setup", "cpuinfo", "enums")}
            for r in results]
    (out / "runs.json").write_text(json.dumps(slim, indent=1) + "\n")
    rows = summarize(results)
    table = format_table(rows)
    (out / "summary.txt").write_text(table)
    (out / "summary.md").write_text(format_markdown(rows))
    pngs = []
    if plots:
        for name in scene_names:
            stem = file_stem(name)
            pngs.append(plot_times(results, name, time_limit, out / f"{stem}_times.png"))
            pngs.append(plot_success(results, name, time_limit, out / f"{stem}_success.png"))
    return SweepResult(results, rows, table, logs, db, pngs, wall)

"""One benchmark job: a (scene, planner, seed) run under ``ompl.tools.Benchmark``, own process.

:func:`execute` runs the job in the calling process: OMPL's own ``Benchmark`` with one planner
and one run, so every standard run property (``time``, ``solved``, ``status``, ``memory``,
``graph states``, ``solution length``, ``correct solution``...) is computed by OMPL itself.
Our figures are added as extra run properties (:func:`run_extras`). :func:`run_job` runs
:func:`execute` in a fresh Python subprocess (``python -m pivot_ompl.bench.worker``): OMPL's
global seed can only be set before the first random number of a process, and a planner that
segfaults or hangs then costs one run (recorded as ``Crash``), not the sweep. Both return a
plain, JSON-able :class:`JobResult` dict, so results do not depend on the executor.
"""

from __future__ import annotations

import importlib
import json
import os
import socket
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from pivot_ompl.bench.ompl_log import STATUS, fmt_value, parse_log, prop_type
from pivot_ompl.bench.processes import JobProcesses
from pivot_ompl.errors import printable

#: A job process is killed (and its run recorded as ``Crash``) after
#: ``time_limit * (1 + KILL_FACTOR) + KILL_MARGIN`` seconds (process start, setup, conversion).
KILL_FACTOR, KILL_MARGIN = 0.5, 30.0


def kill_timeout(time_limit: float) -> float:
    """Seconds after which a job process with this time limit is killed."""
    return time_limit * (1.0 + KILL_FACTOR) + KILL_MARGIN


@dataclass(frozen=True)
class Job:
    """One run to do.

    Attributes:
        scene_name: the scene's name (the experiment name).
        scene_text: the scene file's YAML text (so remote workers need no shared files).
        planner: a name of :data:`pivot_ompl.planners.PLANNERS`, or ``"module:factory"`` with
            ``factory(si, seed) -> ompl.base.Planner`` importable in the job process.
        seed: seed of the run (our planners' generator, the checker, OMPL's RNG: seed + 1).
        time_limit: planner time limit (s).
        memory_limit: OMPL's memory limit per run (MB).
        simplify: let OMPL's Benchmark simplify the solution (adds its simplification columns).
        source: the scene file path, for messages only.
    """

    scene_name: str
    scene_text: str
    planner: str
    seed: int
    time_limit: float
    memory_limit: float = 4096.0
    simplify: bool = False
    source: str = ""

    @property
    def label(self) -> str:
        """Short planner label used in tables and plots (the factory name for ``mod:f``)."""
        return self.planner.rsplit(":", 1)[-1]

    def to_dict(self) -> dict[str, Any]:
        """Return the job as a JSON-able dict."""
        return asdict(self)


#: A job result, as returned by :func:`execute` and :func:`run_job`. Keys:
#: ``scene``, ``planner`` (label), ``seed``, ``planner_name`` (OMPL's), ``common`` (common
#: property lines), ``run`` (run properties, ``"name TYPE" -> "value"``), ``setup``,
#: ``cpuinfo``, ``version``, ``host``, ``enums``, ``error`` (``None`` or the crash reason),
#: ``wall`` (s, whole job).
JobResult = dict[str, Any]


def allocator(planner: str) -> Callable[[Any, int], Any]:
    """Return the ``(problem, seed) -> planner`` allocator of a planner spec.

    A name of :data:`pivot_ompl.planners.PLANNERS`, with parameters in brackets for the
    regrasp planner (``regrasp[search.weight=1.5]``, :mod:`pivot_ompl.planners.registry`),
    or a ``module:factory`` spec naming a user factory ``(si, seed) -> planner``.

    Raises:
        InputError: unknown planner name, bad parameters or unimportable ``module:factory``.
    """
    from pivot_ompl.errors import InputError
    from pivot_ompl.planners import PLANNERS, check_planner_name, make_planner

    if ":" not in planner:
        try:
            check_planner_name(planner)
        except InputError as e:
            if planner.partition("[")[0] not in PLANNERS:
                raise InputError("planner", planner, f"unknown planner (known: "
                                 f"{sorted(PLANNERS)} or module:factory)") from None
            raise InputError("planner", planner, e.reason) from None
        return lambda problem, seed: make_planner(planner, problem, seed=seed)
    mod, _, attr = planner.partition(":")
    try:
        factory = getattr(importlib.import_module(mod), attr)
    except (ImportError, AttributeError) as e:
        raise InputError("planner", planner, f"cannot import the factory ({e})") from None
    return lambda problem, seed: factory(problem.si, seed)


def parameter_lines(planner: str) -> list[str]:
    """The common-property lines recording a planner spec's parameters (``name = value``)."""
    from pivot_ompl.planners import parse_spec

    if ":" in planner:
        return []
    return [f"{k} = {v}" for k, v in parse_spec(planner)[1].items()]


#: Clearer column names for some planner figures.
_ALIASES = {"critical": "critical configurations"}


def _flatten(prefix: str, stats: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, v in stats.items():
        name = f"{prefix}{_ALIASES.get(str(key), str(key)).replace('_', ' ')}"
        if isinstance(v, dict):
            if all(isinstance(x, int | float) and not isinstance(x, bool) for x in v.values()):
                out[name] = sum(v.values())
        elif isinstance(v, bool | int | float):
            out[name] = v
    return out


def run_extras(scene: Any, problem: Any, planner: Any, seed: int | None = None) -> dict[str, str]:
    """Our run properties for the run that just ended (call it from a post-run event).

    ``seed INTEGER``; with a solution ``pivots INTEGER``, ``regrasps INTEGER``,
    ``plan valid BOOLEAN`` (the path converts to a pivot plan) and the plan's quality block
    (``quality transfer length REAL``, ``quality pivots per m``, ``quality ideal pivots per
    m``, ``quality walking length``, ``quality duration estimate``); the planner's ``stats``
    (roadmap sizes, ``planner critical configurations``...) as ``planner <key>`` columns
    (dicts of numbers summed, e.g. ``planner manipulation nodes``); the checker's
    motion counters as ``checker <key>``.
    """
    from pivot_ompl.base.path_conversion import path_to_plan
    from pivot_ompl.base.state import read_state
    from pivot_ompl.errors import PivotError
    from pivot_ompl.quality import plan_quality

    vals: dict[str, Any] = {}
    if seed is not None:
        vals["seed"] = int(seed)
    ss = problem.setup
    if ss.haveExactSolutionPath():
        path = ss.getSolutionPath()
        states = [read_state(path.getState(i)) for i in range(path.getStateCount())]
        try:
            plan = path_to_plan(scene, problem.checker, states)
            vals.update({"pivots": plan.pivots, "regrasps": plan.regrasps, "plan valid": True})
            q = plan_quality(plan)
            vals.update({f"quality {k.replace('_', ' ')}": v for k, v in q.items()
                         if k not in ("pivots", "regrasps") and v is not None})
        except PivotError:
            vals["plan valid"] = False
    vals.update(_flatten("planner ", dict(getattr(planner, "stats", None) or {})))
    c = problem.checker.counters
    vals.update(_flatten("checker ", {"valid": c.valid, "invalid": c.invalid,
                                      "cache_hits": c.cache_hits}))
    return {f"{k} {prop_type(v)}": fmt_value(v) for k, v in vals.items()}


def crash_run(elapsed: float, seed: int) -> dict[str, str]:
    """Return the run properties of a run that crashed (no OMPL record of it)."""
    return {"time REAL": fmt_value(float(elapsed)), "solved BOOLEAN": "0",
            "status ENUM": str(STATUS["CRASH"]), "seed INTEGER": str(seed)}


def _base_result(job: Job) -> JobResult:
    return {"scene": job.scene_name, "planner": job.label, "seed": job.seed,
            "planner_name": f"geometric_{job.label}", "common": [], "run": {}, "setup": "",
            "cpuinfo": None, "version": "", "host": socket.gethostname(), "enums": [],
            "error": None, "wall": 0.0}


def execute(job: Job) -> JobResult:
    """Run ``job`` in this process under ``ompl.tools.Benchmark`` (1 planner, 1 run).

    Call it in a fresh process (:func:`run_job`): OMPL's seed is set here and takes effect only
    before the process's first random number. An exception escaping the planner (which aborts
    OMPL's ``Benchmark.benchmark``) is recorded as a ``Crash`` run.
    """
    import yaml
    from ompl import tools as ot
    from ompl import util as ou

    from pivot_ompl.base.problem import make_setup
    from pivot_ompl.errors import PlanningError
    from pivot_ompl.scene import scene_from_dict

    t_start = time.perf_counter()
    ou.RNG.setSeed(job.seed + 1)  # OMPL's seed must be > 0
    res = _base_result(job)
    scene = scene_from_dict(yaml.safe_load(job.scene_text), source=job.source or job.scene_name)
    try:
        problem = make_setup(scene, seed=job.seed)
    except PlanningError as e:  # no valid grasp at the start or goal: as OMPL would record it
        res["run"] = {"time REAL": "0", "solved BOOLEAN": "0", "seed INTEGER": str(job.seed),
                      "status ENUM": str(STATUS.get(e.status, STATUS["UNKNOWN"]))}
        res["error"] = str(e)
        res["wall"] = time.perf_counter() - t_start
        return res
    ss = problem.setup
    planner = allocator(job.planner)(problem, job.seed)
    bench = ot.Benchmark(ss, printable(job.scene_name))  # OMPL's log: one line per field
    bench.addPlanner(planner)
    extras: dict[str, str] = {}
    errors: list[str] = []

    def post(p: Any, run: Any) -> None:
        try:
            extras.update(run_extras(scene, problem, p, job.seed))
        except Exception as e:  # noqa: BLE001 - an exception here would abort the benchmark
            errors.append(f"post-run event: {type(e).__name__}: {e}")

    bench.setPostRunEvent(post)
    # saveConsoleOutput off: it writes an ompl_<host>_<date>.console file into the cwd
    req = ot.Request(float(job.time_limit), float(job.memory_limit), 1, 0.05, False, False,
                     bool(job.simplify))
    t0 = time.perf_counter()
    try:
        bench.benchmark(req)
    except Exception as e:  # noqa: BLE001 - a Python planner raised: OMPL aborted the run
        res["error"] = f"{type(e).__name__}: {e}"
    elapsed = time.perf_counter() - t0
    with tempfile.TemporaryDirectory() as d:
        log_path = os.path.join(d, "run.log")
        bench.saveResultsToFile(log_path)
        log = parse_log(Path(log_path).read_text())
    block = log.planners[0]
    res.update({"planner_name": block.name,
                "common": block.common + parameter_lines(job.planner), "setup": log.setup,
                "cpuinfo": log.cpuinfo, "version": log.version, "host": log.host,
                "enums": log.enums})
    if block.runs:
        run = dict(block.runs[0])
        run.update(extras)
    else:
        run = crash_run(elapsed, job.seed)
    if errors and res["error"] is None:
        res["error"] = errors[0]
    res["run"] = run
    res["wall"] = time.perf_counter() - t_start
    # the problem (setup, validators, projection) and the planner outlive the Benchmark
    # (it holds raw pointers)
    bench = None
    return res


def run_job(job: Job, *, python: str | None = None, timeout: float | None = None,
            env: dict[str, str] | None = None,
            processes: JobProcesses | None = None) -> JobResult:
    """Run ``job`` in a fresh Python process; a crash or a kill becomes a ``Crash`` run.

    Args:
        job: the job.
        python: interpreter (default: this one).
        timeout: seconds before the process is killed (default: :func:`kill_timeout`).
        env: environment of the process (default: this one).
        processes: the sweep's job processes (its own process group, ended with the sweep);
            default: a set of this job alone.

    Raises:
        Interrupted: ``processes`` was closed (the sweep was stopped).
    """
    processes = processes or JobProcesses()
    timeout = kill_timeout(job.time_limit) if timeout is None else timeout
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pivot-bench-") as d:
        job_path, res_path = Path(d, "job.json"), Path(d, "result.json")
        job_path.write_text(json.dumps(job.to_dict()))
        cmd = [python or sys.executable, "-m", "pivot_ompl.bench.worker", str(job_path),
               str(res_path)]
        error = None
        code, stderr = processes.run(cmd, timeout=timeout, env=env)
        if code is None:
            error = f"job process killed after {timeout:.0f} s"
        elif not res_path.exists():  # (a crash at interpreter exit after it is harmless)
            tail = stderr.decode(errors="replace").strip().splitlines()[-5:]
            error = f"job process exited with code {code}: " + " | ".join(tail)
        if error is None:
            return json.loads(res_path.read_text())
    res = _base_result(job)
    res["error"] = error
    wall = time.perf_counter() - t0
    res["run"] = crash_run(wall, job.seed)
    res["wall"] = wall
    return res

"""OMPL's benchmark log format: a reader and a byte-compatible writer.

The format is the one ``ompl::tools::Benchmark::saveResultsToStream`` writes and
``ompl_benchmark_statistics`` reads (https://ompl.kavrakilab.org/benchmark.html)::

    OMPL version 2.0.1
    Experiment <name>
    <n> experiment properties
    <name> <TYPE> = <value>                  (n lines)
    Running on <host>
    Starting at <date>
    <<<|
    <setup text>
    |>>>
    <<<|
    <cpu info>
    |>>>
    <seed> is the random seed
    <t> seconds per run
    <m> MB per run
    <r> runs per planner
    <d> seconds spent to collect the data
    1 enum type
    status|Unknown status|Invalid start|...
    <k> planners
    <planner name>
    <c> common properties
    <name> = <value>                         (c lines)
    <p> properties for each run
    <name> <TYPE>                            (p lines, sorted; REAL INTEGER BOOLEAN ENUM STRING)
    <r> runs
    v1; v2; ...; vp;                         (a missing value is empty: "; ;")
    .

Run property names carry their type (``"time REAL"``); values are strings. Numbers are
written as C++ ``std::ostream`` writes a double by default (6 significant digits).
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pivot_ompl.errors import printable

#: The status enum line OMPL 2.0.1 writes (value i is the (i+1)-th field).
STATUS_ENUM = ("status|Unknown status|Invalid start|Invalid goal|Unrecognized goal type|Timeout|"
               "Approximate solution|Exact solution|Crash|Unknown status|Unknown status")

#: ``status ENUM`` values (``ompl::base::PlannerStatus::StatusType``).
STATUS = {"UNKNOWN": 0, "INVALID_START": 1, "INVALID_GOAL": 2, "UNRECOGNIZED_GOAL_TYPE": 3,
          "TIMEOUT": 4, "APPROXIMATE_SOLUTION": 5, "EXACT_SOLUTION": 6, "CRASH": 7, "ABORT": 8}

#: ``status ENUM`` value -> OMPL's name for it.
STATUS_NAMES = {v: k for k, v in STATUS.items()}

TYPES = ("REAL", "INTEGER", "BOOLEAN", "ENUM", "STRING")


def fmt_value(v: Any) -> str:
    """Format a property value as OMPL does (``bool`` as 0/1, floats to 6 significant digits)."""
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def prop_type(v: Any) -> str:
    """Return the OMPL property type of a Python value."""
    if isinstance(v, bool):
        return "BOOLEAN"
    if isinstance(v, int):
        return "INTEGER"
    if isinstance(v, float):
        return "REAL"
    return "STRING"


@dataclass
class PlannerResults:
    """One planner's block of a log.

    Attributes:
        name: planner name as OMPL writes it (``"geometric_RRTConnect"``).
        common: common properties, ``"name = value"`` lines.
        runs: one mapping per run, ``"time REAL" -> "0.0123"``.
        progress_properties: progress property names with types (written only with data).
        progress: per run, a list of samples, each a list of values.
    """

    name: str
    common: list[str] = field(default_factory=list)
    runs: list[dict[str, str]] = field(default_factory=list)
    progress_properties: list[str] = field(default_factory=list)
    progress: list[list[list[str]]] = field(default_factory=list)

    def properties(self) -> list[str]:
        """Return every run property name (with type), sorted as ``std::map`` orders them."""
        return sorted({k for run in self.runs for k in run})


@dataclass
class ExperimentLog:
    """A whole log: the experiment header and the planners' blocks."""

    name: str
    library: str = "OMPL"
    version: str = "2.0.1"
    properties: list[tuple[str, str, str]] = field(default_factory=list)
    host: str = ""
    start: str = ""
    setup: str = ""
    cpuinfo: str | None = ""
    seed: int = 0
    time_limit: float = 0.0
    memory_limit: float = 4096.0
    runs_per_planner: int = 0
    total_time: float = 0.0
    enums: list[str] = field(default_factory=lambda: [STATUS_ENUM])
    planners: list[PlannerResults] = field(default_factory=list)

    def format(self) -> str:
        """Return the log text (what ``Benchmark::saveResultsToStream`` writes)."""
        out = io.StringIO()
        w = out.write
        w(f"{self.library} version {self.version}\n")
        w(f"Experiment {printable(self.name)}\n")  # a newline in a name would forge lines
        w(f"{len(self.properties)} experiment properties\n")
        for name, typ, value in self.properties:
            w(f"{name} {typ} = {value}\n")
        w(f"Running on {self.host}\n")
        w(f"Starting at {self.start}\n")
        w("<<<|\n" + _block(self.setup) + "|>>>\n")
        if self.cpuinfo is not None:
            w("<<<|\n" + _block(self.cpuinfo) + "|>>>\n")
        w(f"{self.seed} is the random seed\n")
        w(f"{fmt_value(float(self.time_limit))} seconds per run\n")
        w(f"{fmt_value(float(self.memory_limit))} MB per run\n")
        w(f"{self.runs_per_planner} runs per planner\n")
        w(f"{fmt_value(float(self.total_time))} seconds spent to collect the data\n")
        w(f"{len(self.enums)} enum type\n")
        for e in self.enums:
            w(e + "\n")
        w(f"{len(self.planners)} planners\n")
        for p in self.planners:
            w(p.name + "\n")
            w(f"{len(p.common)} common properties\n")
            for c in p.common:
                w(c + "\n")
            props = p.properties()
            w(f"{len(props)} properties for each run\n")
            for name in props:
                w(name + "\n")
            w(f"{len(p.runs)} runs\n")
            for run in p.runs:
                w("".join(f"{run.get(name, '')}; " for name in props) + "\n")
            if p.progress:
                w(f"{len(p.progress_properties)} progress properties for each run\n")
                for name in p.progress_properties:
                    w(name + "\n")
                w(f"{len(p.progress)} runs\n")
                for samples in p.progress:
                    w("".join("".join(f"{v}," for v in s) + ";" for s in samples) + "\n")
            w(".\n")
        return out.getvalue()

    def write(self, path: str | Path) -> Path:
        """Write the log to ``path``."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.format())
        return path


def _block(text: str) -> str:
    return text if not text or text.endswith("\n") else text + "\n"


class _Lines:
    def __init__(self, text: str) -> None:
        self.lines = text.splitlines()
        self.i = 0

    def peek(self) -> str:
        return self.lines[self.i] if self.i < len(self.lines) else ""

    def next(self) -> str:
        if self.i >= len(self.lines):
            raise ValueError("unexpected end of the benchmark log")
        line = self.lines[self.i]
        self.i += 1
        return line

    def block(self) -> str:
        if self.next() != "<<<|":
            raise ValueError(f"line {self.i}: expected '<<<|'")
        body = []
        while (line := self.next()) != "|>>>":
            body.append(line + "\n")
        return "".join(body)


def parse_log(text: str) -> ExperimentLog:
    """Read an OMPL benchmark log (the non-MoveIt format ``ompl_benchmark_statistics`` reads).

    Raises:
        ValueError: the text is not such a log.
    """
    r = _Lines(text)
    head = r.next().split()
    if len(head) < 3 or head[1] != "version":
        raise ValueError("line 1: expected '<library> version <x.y.z>'")
    log = ExperimentLog(name=r.next().split(" ", 1)[1], library=head[0], version=head[-1])
    n = int(r.next().split()[0])
    for _ in range(n):
        left, value = r.next().split(" = ", 1)
        name, typ = left.rsplit(" ", 1)
        log.properties.append((name, typ, value))
    log.host = r.next().split(" ", 2)[2]
    log.start = r.next().split(" ", 2)[2]
    log.setup = r.block()
    log.cpuinfo = r.block() if r.peek() == "<<<|" else None
    log.seed = int(r.next().split()[0])
    log.time_limit = float(r.next().split()[0])
    log.memory_limit = float(r.next().split()[0])
    if r.peek().endswith("runs per planner"):
        log.runs_per_planner = int(r.next().split()[0])
    log.total_time = float(r.next().split()[0])
    log.enums = []
    if r.peek().split()[-2:-1] == ["enum"]:
        for _ in range(int(r.next().split()[0])):
            log.enums.append(r.next())
    for _ in range(int(r.next().split()[0])):
        p = PlannerResults(r.next())
        for _ in range(int(r.next().split()[0])):
            p.common.append(r.next())
        props = [r.next() for _ in range(int(r.next().split()[0]))]
        for _ in range(int(r.next().split()[0])):
            values = r.next().split("; ")[:-1]
            p.runs.append({k: v for k, v in zip(props, values, strict=True) if v != ""})
        line = r.next()
        if line.strip() != ".":
            p.progress_properties = [r.next() for _ in range(int(line.split()[0]))]
            for _ in range(int(r.next().split()[0])):
                samples = r.next().split(";")[:-1]
                p.progress.append([s.split(",")[:-1] for s in samples])
            r.next()
        log.planners.append(p)
    return log

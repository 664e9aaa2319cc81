"""``python -m pivot_ompl.bench.worker JOB.json RESULT.json``: run one job, write its result.

Exit code 0 when the result is written (even for a crashed run), 3 when the job could not be
run at all (the message is on stderr).
"""

from __future__ import annotations

import atexit
import json
import os
import sys
from pathlib import Path


def _quiet_exit() -> None:
    # nanobind lists OMPL objects alive at exit on fd 2: harmless, and noise for the parent
    sys.stderr.flush()
    os.dup2(os.open(os.devnull, os.O_WRONLY), 2)


def main(argv: list[str] | None = None) -> int:
    """Run the job file ``argv[0]`` and write the result to ``argv[1]``."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("usage: python -m pivot_ompl.bench.worker JOB.json RESULT.json", file=sys.stderr)
        return 3
    from ompl import util as ou

    from pivot_ompl.bench.job import Job, execute

    ou.setLogLevel(ou.LogLevel.LOG_ERROR)
    atexit.register(_quiet_exit)
    job = Job(**json.loads(Path(argv[0]).read_text()))
    res = execute(job)
    tmp = Path(argv[1] + ".tmp")
    tmp.write_text(json.dumps(res))
    tmp.replace(argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main())

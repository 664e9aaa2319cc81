"""Every test module that reads a clock is marked ``timed`` (``make test`` runs those alone)."""

from __future__ import annotations

import re
from pathlib import Path

CLOCKS = re.compile(r"time\.(monotonic|perf_counter|process_time)\(\)|DeadlineWatch|"
                    r"timings\[|resource\.getrusage")


def test_every_module_that_reads_a_clock_runs_in_the_timed_pass():
    here = Path(__file__).parent
    unmarked = [str(p.relative_to(here)) for p in sorted(here.rglob("*.py"))
                if p.name.startswith("test_") and p.name != Path(__file__).name
                and CLOCKS.search(p.read_text()) and "pytest.mark.timed" not in p.read_text()]
    assert not unmarked, f"read a clock but are not marked timed: {unmarked}"

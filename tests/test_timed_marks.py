"""Every test module that reads a clock is marked ``timed`` (``make test`` runs those alone)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

CLOCKS = re.compile(r"time\.(monotonic|perf_counter|process_time)\(\)|DeadlineWatch|"
                    r"timings\[|resource\.getrusage")


def _marked_timed(source: str) -> bool:
    """Whether the module assigns ``pytestmark`` at its top level with the ``timed`` mark."""
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "pytestmark"
                                                for t in node.targets):
            return "timed" in (ast.get_source_segment(source, node.value) or "")
    return False


def test_every_module_that_reads_a_clock_runs_in_the_timed_pass():
    here = Path(__file__).parent
    unmarked = [str(p.relative_to(here)) for p in sorted(here.rglob("test_*.py"))
                if p != Path(__file__) and CLOCKS.search(p.read_text())
                and not _marked_timed(p.read_text())]
    assert not unmarked, f"read a clock but are not marked timed: {unmarked}"


def test_a_mark_inside_a_string_is_not_a_mark():
    embedded = 'CODE = """\npytestmark = pytest.mark.timed\n"""\n'
    assert not _marked_timed(embedded)
    assert _marked_timed("import pytest\n\npytestmark = pytest.mark.timed\n")
    assert _marked_timed("pytestmark = [pytest.mark.browser, pytest.mark.timed]\n")

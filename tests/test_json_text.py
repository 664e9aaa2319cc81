"""Plans as JSON text: the same document as ``json.dumps``, one record a line."""

from __future__ import annotations

import json
import math

import pytest
from factories import shipped
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.api import plan
from pivot_ompl.fileio.json_text import json_text
from pivot_ompl.planfile import plan_from_dict

_scalars = (st.none() | st.booleans() | st.integers(-10**6, 10**6)
            | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=8))
_docs = st.recursive(_scalars, lambda inner: st.lists(inner, max_size=5)
                     | st.dictionaries(st.text(max_size=6), inner, max_size=5), max_leaves=40)


@given(_docs)
def test_the_text_reads_back_as_the_document(doc):
    text = json_text(doc)
    assert text.endswith("\n")
    assert json.loads(text) == doc


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_number_json_cannot_write_is_refused(bad):
    with pytest.raises(ValueError):
        json_text({"steps": [{"angle": bad}]})
    assert json_text([bad], allow_nan=True) == json.dumps([bad]) + "\n"


def test_a_plan_s_text_has_one_line_a_pivot_step():
    """``indent=1`` put each number on a line (a 2400-pivot plan: 1.2 MB in 0.12 s)."""
    res = plan(shipped("door"), time_limit=10.0, seed=0)
    assert res.solved
    text = res.plan.to_text()
    lines = text.splitlines()
    steps = [p for p in res.plan.phases if p.type == "transfer" for p in p.steps]
    step_lines = [ln for ln in lines if ln.lstrip().startswith('{"pivot": ')]
    assert len(step_lines) == len(steps) > 0
    assert all(ln.rstrip(",").endswith("]}") for ln in step_lines)
    assert len(lines) < 2 * len(steps) + 200
    assert json.loads(text) == json.loads(json.dumps(res.plan.to_dict()))
    read = plan_from_dict(json.loads(text))
    assert [s for p in read.phases if p.type == "transfer" for s in p.steps] == steps

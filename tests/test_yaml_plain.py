"""The lean construction of plain YAML documents builds what PyYAML's safe loader builds."""

from __future__ import annotations

import math

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.errors import InputError, Interrupted
from pivot_ompl.fileio import load_yaml
from pivot_ompl.fileio.yaml_strict import parse_deadline

_SAFE = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

_scalars = (st.none() | st.booleans() | st.integers(-10**30, 10**30)
            | st.floats(allow_nan=False) | st.text(max_size=12))
_keys = st.text(max_size=8) | st.integers(-1000, 1000) | st.booleans()
_documents = st.recursive(_scalars, lambda kids: st.lists(kids, max_size=5)
                          | st.dictionaries(_keys, kids, max_size=5), max_leaves=40)


def _same(a: object, b: object) -> bool:
    """Equal, with the types and float signs PyYAML gives (1 == 1.0 == True is not enough)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, float):
        return (math.isnan(a) and math.isnan(b)) or (a == b and math.copysign(1, a)
                                                     == math.copysign(1, b))
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    return a == b


@settings(max_examples=150, deadline=None)
@given(doc=_documents, flow=st.booleans())
def test_plain_documents_read_as_pyyaml_reads_them(tmp_path_factory, doc, flow):
    p = tmp_path_factory.mktemp("y") / "a.yaml"
    text = yaml.safe_dump(doc, default_flow_style=flow, allow_unicode=True)
    p.write_text(text, encoding="utf-8")
    assert _same(load_yaml(p), yaml.load(text, Loader=_SAFE))  # noqa: S506 (the safe loader)


@pytest.mark.parametrize("text", [
    "a: 012\nb: 0x1F\nc: 1_000\nd: 0o17\ne: +12\nf: 190:20:30\n",
    "a: .inf\nb: -.Inf\nc: .nan\nd: 1.5e+3\ne: -0.0\nf: 1__0.5\ng: 6.8523015e+5\nh: 1:30.5\n",
    "a: yes\nb: Off\nc: ~\nd: null\ne: 'true'\nf: !!float '12'\ng: !!str 1.5\nh: !!int '7'\n",
    "a: !!set {x, y}\nb: 2001-12-14\nc: !!binary aGVsbG8=\n",
    "? [1, 2]\n: a\n",
    "a: &x [1, 2]\nb: [*x, *x]\n",
])
def test_other_documents_read_as_pyyaml_reads_them(tmp_path, text):
    p = tmp_path / "a.yaml"
    p.write_text(text)
    try:
        expected = yaml.load(text, Loader=_SAFE)  # noqa: S506 (the safe loader)
    except yaml.YAMLError:
        with pytest.raises(InputError, match="not valid YAML"):
            load_yaml(p)
        return
    assert _same(load_yaml(p), expected)


def test_a_merge_key_is_refused_as_before(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("base: &b {x: 1, y: 2}\nderived:\n  <<: *b\n  y: 3\n")
    with pytest.raises(InputError, match="merge"):
        load_yaml(p)


def test_an_alias_gives_the_same_object_as_pyyaml_does(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("a: &x [1, 2]\nb: [*x, *x]\n")
    doc = load_yaml(p)
    assert doc["b"][0] is doc["a"] and doc["b"][1] is doc["a"]


@pytest.mark.parametrize("text", [
    "a:\n  b: 1\n  c: [1, {d: 2, d: 3}]\n",
    "a: &a [1, 2]\nb: {x: *a, x: *a}\n",
])
def test_a_duplicate_key_anywhere_is_refused(tmp_path, text):
    p = tmp_path / "a.yaml"
    p.write_text(text)
    with pytest.raises(InputError, match="duplicate key"):
        load_yaml(p)


def test_a_long_plain_document_is_stopped_up_to_its_last_node(tmp_path):
    p = tmp_path / "a.yaml"
    p.write_text("".join(f"- {{c: [{i}.5, 2.0], s: box}}\n" for i in range(20_000)))
    with pytest.raises(Interrupted):
        load_yaml(p, should_stop=parse_deadline(0.0))
    polls: list[int] = []
    assert len(load_yaml(p, should_stop=lambda: polls.append(1) and False)) == 20_000
    assert len(polls) > 200  # composing and building both poll
    with pytest.raises(Interrupted):  # the last poll is the building's, near its end
        load_yaml(p, should_stop=lambda: polls.pop() is None or not polls)

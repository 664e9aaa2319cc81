"""A lean construction of plain YAML documents: maps, lists and the core scalars.

PyYAML's constructor spends most of a large scene's read in its generic machinery (one
generator per map and list, a method looked up per node). A scene is plain data, so
:func:`build_plain` builds it directly from the composed nodes, counting the nodes as the
aliases expand them; whatever it does not take on (another tag, a merge key, a duplicate or
unhashable key, a cycle, too many nodes) it hands back with :class:`NotPlain`, and the
caller builds that document with PyYAML's constructor instead, which keeps its checks and
its messages.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import yaml

from pivot_ompl.errors import Interrupted

_STR = "tag:yaml.org,2002:str"
_FLOAT = "tag:yaml.org,2002:float"
_INT = "tag:yaml.org,2002:int"
_BOOL = "tag:yaml.org,2002:bool"
_NULL = "tag:yaml.org,2002:null"
_SEQ = "tag:yaml.org,2002:seq"
_MAP = "tag:yaml.org,2002:map"


class NotPlain(Exception):
    """The document holds something :func:`build_plain` leaves to PyYAML's constructor."""


def build_plain(root: yaml.Node, constructor: yaml.constructor.SafeConstructor, *,
                max_nodes: int, poll_nodes: int,
                should_stop: Callable[[], bool] | None = None) -> Any:
    """The Python value of the composed document ``root``, as PyYAML's safe loader builds it.

    A node reached again through an alias gives the same object (as PyYAML's), and counts
    its nodes each time towards ``max_nodes``. ``constructor`` builds the scalars whose text
    needs YAML's own reading (ints, bools, floats such as ``.inf`` or ``1:30``).
    ``should_stop`` is polled every ``poll_nodes`` nodes built.

    Raises:
        NotPlain: a tag other than the core ones, a merge key, a duplicate or unhashable key,
            an alias cycle, or more than ``max_nodes`` nodes once aliases are expanded.
        Interrupted: ``should_stop()`` became true.
    """
    built: dict[int, tuple[Any, int]] = {}
    visiting: set[int] = set()
    count = [0]
    construct_int = constructor.construct_yaml_int
    construct_bool = constructor.construct_yaml_bool
    construct_float = constructor.construct_yaml_float
    scalar_node, sequence_node = yaml.ScalarNode, yaml.SequenceNode

    def build(node: yaml.Node) -> tuple[Any, int]:
        key = id(node)
        done = built.get(key)
        if done is not None:
            return done
        count[0] += 1
        if should_stop is not None and count[0] % poll_nodes == 0 and should_stop():
            raise Interrupted("reading the scene")
        tag = node.tag
        if isinstance(node, scalar_node):
            value = node.value
            if tag == _STR:
                out: Any = value
            elif tag == _FLOAT:
                try:
                    out = float(value)
                except ValueError:
                    out = construct_float(node)
            elif tag == _INT:
                out = construct_int(node)
            elif tag == _NULL:
                out = None
            elif tag == _BOOL:
                out = construct_bool(node)
            else:
                raise NotPlain(tag)
            done = (out, 1)
        else:
            if key in visiting:
                raise NotPlain("an alias cycle")
            visiting.add(key)
            size = 1
            if isinstance(node, sequence_node):
                if tag != _SEQ:
                    raise NotPlain(tag)
                items = []
                for child in node.value:
                    item, n = build(child)
                    items.append(item)
                    size += n
                out = items
            else:
                if tag != _MAP:
                    raise NotPlain(tag)
                mapping: dict[Any, Any] = {}
                for key_node, value_node in node.value:
                    if key_node.tag not in (_STR, _INT, _FLOAT, _BOOL, _NULL):
                        raise NotPlain(key_node.tag)  # merge keys, unhashable keys
                    k, n = build(key_node)
                    if k in mapping:
                        raise NotPlain("a duplicate key")
                    v, m = build(value_node)
                    mapping[k] = v
                    size += n + m
                out = mapping
            visiting.discard(key)
            if size > max_nodes:
                raise NotPlain("too many nodes")
            done = (out, size)
        built[key] = done
        return done

    value, size = build(root)
    if size > max_nodes:
        raise NotPlain("too many nodes")
    return value

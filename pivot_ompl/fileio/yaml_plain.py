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
#: Tags of the keys built here (others, such as the merge key ``<<``, go to PyYAML).
_KEY_TAGS = frozenset((_STR, _INT, _FLOAT, _BOOL, _NULL))


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
    builder = _Builder(constructor, max_nodes, poll_nodes, should_stop)
    value, size = builder.build(root)
    if size > max_nodes:
        raise NotPlain("too many nodes")
    return value


class _Builder:
    """:func:`build_plain`'s walk.

    A class, not a recursive closure: no reference cycle keeps what a stopped walk built
    alive until a collection.
    """

    def __init__(self, constructor: yaml.constructor.SafeConstructor, max_nodes: int,
                 poll_nodes: int, should_stop: Callable[[], bool] | None) -> None:
        self.built: dict[int, tuple[Any, int]] = {}
        self.visiting: set[int] = set()
        self.count = 0
        self.constructor = constructor
        self.max_nodes, self.poll_nodes, self.should_stop = max_nodes, poll_nodes, should_stop

    def build(self, node: yaml.Node) -> tuple[Any, int]:
        """``node``'s value and its node count, aliases expanded."""
        key = id(node)
        done = self.built.get(key)
        if done is not None:
            return done
        self.count += 1
        if self.should_stop is not None and self.count % self.poll_nodes == 0 \
                and self.should_stop():
            raise Interrupted("reading the scene")
        tag = node.tag
        if isinstance(node, yaml.ScalarNode):
            done = (self._scalar(node, tag), 1)
        else:
            if key in self.visiting:
                raise NotPlain("an alias cycle")
            self.visiting.add(key)
            out: list | dict
            if isinstance(node, yaml.SequenceNode):
                out, size = self._sequence(node, tag)
            elif isinstance(node, yaml.MappingNode):
                out, size = self._mapping(node, tag)
            else:
                raise NotPlain(tag)
            self.visiting.discard(key)
            if size > self.max_nodes:
                raise NotPlain("too many nodes")
            done = (out, size)
        self.built[key] = done
        return done

    def _scalar(self, node: yaml.ScalarNode, tag: str) -> Any:
        value = node.value
        if tag == _STR:
            return value
        if tag == _FLOAT:
            try:
                return float(value)
            except ValueError:
                return self.constructor.construct_yaml_float(node)
        if tag == _INT:
            return self.constructor.construct_yaml_int(node)
        if tag == _NULL:
            return None
        if tag == _BOOL:
            return self.constructor.construct_yaml_bool(node)
        raise NotPlain(tag)

    def _sequence(self, node: yaml.SequenceNode, tag: str) -> tuple[list, int]:
        if tag != _SEQ:
            raise NotPlain(tag)
        items, size, build = [], 1, self.build
        for child in node.value:
            item, n = build(child)
            items.append(item)
            size += n
        return items, size

    def _mapping(self, node: yaml.MappingNode, tag: str) -> tuple[dict, int]:
        if tag != _MAP:
            raise NotPlain(tag)
        mapping: dict[Any, Any] = {}
        size, build = 1, self.build
        for key_node, value_node in node.value:
            if key_node.tag not in _KEY_TAGS:
                raise NotPlain(key_node.tag)  # merge keys, unhashable keys
            k, n = build(key_node)
            if k in mapping:
                raise NotPlain("a duplicate key")
            v, m = build(value_node)
            mapping[k] = v
            size += n + m
        return mapping, size

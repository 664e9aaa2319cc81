"""Strict YAML reading: duplicate keys refused, aliases bounded, a parse that can be stopped.

See :mod:`pivot_ompl.fileio` for the limits every input is held to.
"""

from __future__ import annotations

import gc
import itertools
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

from pivot_ompl.errors import InputError, Interrupted
from pivot_ompl.fileio.reading import read_text, short_error
from pivot_ompl.fileio.yaml_plain import NotPlain, build_plain

#: Largest number of YAML nodes after alias expansion (a 64 MB file of plain data holds fewer;
#: the largest documented scene, 100 000 obstacles, about 1.6 M).
MAX_NODES = 8_000_000


#: PyYAML's safe loader on libyaml's C parser where PyYAML has it (about ten times faster on
#: large scenes; the same documents, the same errors), else the pure-Python one.
_SafeBase = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _StrictLoader(_SafeBase):  # type: ignore[valid-type,misc]
    """PyYAML's safe loader that refuses duplicate mapping keys."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            try:
                dup = key in seen
                seen.add(key)
            except TypeError:  # an unhashable key: the base class reports it
                break
            if dup:
                raise yaml.constructor.ConstructorError(
                    None, None, f"duplicate key {key!r:.60}", key_node.start_mark)
        return super().construct_mapping(node, deep=deep)


#: Nodes composed, built or counted between two polls of a parse's ``should_stop``.
POLL_NODES = 1024


def _loader(text: str, should_stop: Callable[[], bool] | None) -> _StrictLoader:
    """A :class:`_StrictLoader` of ``text`` that polls ``should_stop``.

    libyaml composes the nodes in C and calls :meth:`resolve` once per node (there is no
    other way in), the constructor calls ``construct_mapping`` and ``construct_sequence`` once
    per mapping and list: all poll every :data:`POLL_NODES` calls, so a time limit stops a
    100 000-obstacle scene's parse, and a 10 000-point polygon's. A scalar's tag depends only
    on its text and style (the safe loader has no path resolvers): each is resolved once.
    """
    calls = itertools.count(1)
    resolved: dict[tuple[str, Any], str] = {}
    base_resolve = _StrictLoader.resolve
    scalar = yaml.ScalarNode

    def poll() -> None:
        if should_stop is not None and next(calls) % POLL_NODES == 0 and should_stop():
            raise Interrupted("reading the scene")

    class _PollingLoader(_StrictLoader):
        def resolve(self, kind: Any, value: Any, implicit: Any) -> Any:
            poll()
            if kind is not scalar:
                return base_resolve(self, kind, value, implicit)
            key = (value, implicit)
            tag = resolved.get(key)
            if tag is None:
                tag = resolved[key] = base_resolve(self, kind, value, implicit)
            return tag

        def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
            poll()
            return super().construct_mapping(node, deep=deep)

        def construct_sequence(self, node: yaml.SequenceNode, deep: bool = False) -> list:
            poll()
            return super().construct_sequence(node, deep=deep)

    return _PollingLoader(text)


def _expanded_size(node: yaml.Node, memo: dict[int, int],
                   should_stop: Callable[[], bool] | None = None) -> int:
    """Number of nodes of ``node`` once aliases are expanded (shared nodes counted each time)."""
    k = id(node)
    if k in memo:
        return memo[k]
    if should_stop is not None and len(memo) % POLL_NODES == 0 and should_stop():
        raise Interrupted("reading the scene")
    memo[k] = MAX_NODES + 1  # a cycle (recursive alias) counts as too large
    n = 1
    if isinstance(node, yaml.SequenceNode):
        for child in node.value:
            n += _expanded_size(child, memo, should_stop)
            if n > MAX_NODES:
                break
    elif isinstance(node, yaml.MappingNode):
        for kn, vn in node.value:
            n += _expanded_size(kn, memo, should_stop) + _expanded_size(vn, memo, should_stop)
            if n > MAX_NODES:
                break
    memo[k] = n
    return n


def load_yaml(path: str | Path, *, error: type[InputError] = InputError,
              should_stop: Callable[[], bool] | None = None) -> Any:
    """Parse a YAML file strictly (see :mod:`pivot_ompl.fileio`).

    Python's cyclic garbage collector is paused while the document is built (millions of
    objects, none of them garbage: with it a 100 000-obstacle scene took 24 s, without 9 s),
    and resumed only once a stopped parse has let go of them (with the stop's traceback
    still holding them, the first collection after took 1.7 s).

    Raises:
        error: unreadable, not UTF-8, invalid YAML, a duplicate key, too many or too deeply
            nested nodes.
        Interrupted: ``should_stop()`` became true (polled every :data:`POLL_NODES` nodes).
    """
    src = str(path)
    text = read_text(path, error=error)
    try:
        loader = _loader(text, should_stop)  # the reader refuses control characters here
    except yaml.YAMLError as e:
        raise error("<document>", src, f"is not valid YAML ({short_error(e)})",
                    source=src) from None
    collecting = gc.isenabled()
    gc.disable()
    try:
        return _parse(loader, src, error, should_stop)
    except Interrupted:
        pass  # raised again below, once its traceback no longer holds the nodes
    finally:
        _release(loader)
        if collecting:
            gc.enable()
    raise Interrupted("reading the scene")


def _release(loader: _StrictLoader) -> None:
    """Drop what ``loader`` holds of a parse, so that reference counting frees it at once.

    A construction stopped midway leaves PyYAML's pending generators on the loader, whose
    frames hold the loader again: a cycle only the garbage collector frees, by traversing
    every node of the document (0.05 s at 60 000 nodes, not polled).
    """
    loader.dispose()
    loader.state_generators = []
    loader.constructed_objects = {}
    loader.recursive_objects = {}


#: Time that freeing what a stopped parse built takes, as a share of the time it ran (a
#: 100 000-obstacle scene: 0.07 to 0.53 s after 1 to 8 s).
UNWIND_SHARE = 0.1


def parse_deadline(deadline: float) -> Callable[[], bool]:
    """The ``should_stop`` of a parse (:func:`load_yaml`) that must be over by ``deadline``.

    ``deadline`` is a ``time.monotonic()`` time; the stop is true once the time left is less
    than freeing what the parse built takes (:data:`UNWIND_SHARE` of the time since this call).
    """
    started = time.monotonic()

    def should_stop() -> bool:
        now = time.monotonic()
        return now + UNWIND_SHARE * (now - started) >= deadline

    return should_stop


def _parse(loader: _StrictLoader, src: str, error: type[InputError],
           should_stop: Callable[[], bool] | None) -> Any:
    """The document of :func:`load_yaml`'s ``loader``."""
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        try:
            return build_plain(node, loader, max_nodes=MAX_NODES, poll_nodes=POLL_NODES,
                               should_stop=should_stop)
        except NotPlain:
            pass  # PyYAML's constructor builds it, with its own checks and messages
        if _expanded_size(node, {}, should_stop) > MAX_NODES:
            raise error("<document>", src, f"expands to more than {MAX_NODES} YAML nodes "
                        "(aliases expanded)", source=src)
        return loader.construct_document(node)
    except yaml.YAMLError as e:
        if "nesting depth" in str(e):  # libyaml's own depth limit
            raise error("<document>", src, "is nested too deeply", source=src) from None
        raise error("<document>", src, f"is not valid YAML ({short_error(e)})",
                    source=src) from None
    except RecursionError:
        raise error("<document>", src, "is nested too deeply", source=src) from None

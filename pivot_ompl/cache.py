"""One bounded cache: a least-recently-used memo, for every cache that must not grow forever."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

from pivot_ompl.errors import InputError

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")


class BoundedCache(Generic[K, V]):
    """At most ``size`` entries; the least recently used one goes first.

    Args:
        size: largest number of entries (>= 1).
    """

    def __init__(self, size: int) -> None:
        """An empty cache."""
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise InputError("size", size, "must be an integer >= 1")
        self.size = size
        self._items: OrderedDict[K, V] = OrderedDict()

    def __len__(self) -> int:
        """Number of entries."""
        return len(self._items)

    def __contains__(self, key: object) -> bool:
        """Whether ``key`` is held (does not count as a use)."""
        return key in self._items

    def get(self, key: K) -> V | None:
        """The value of ``key`` (now the most recently used), or ``None``."""
        v = self._items.get(key)
        if v is not None:
            self._items.move_to_end(key)
        return v

    def put(self, key: K, value: V) -> V:
        """Store ``value`` under ``key``, evicting the least recently used beyond ``size``."""
        self._items[key] = value
        self._items.move_to_end(key)
        while len(self._items) > self.size:
            self._items.popitem(last=False)
        return value

    def get_or_compute(self, key: K, compute: Callable[[], V]) -> V:
        """The value of ``key``, computed and stored if absent."""
        v = self.get(key)
        return v if v is not None else self.put(key, compute())

    def clear(self) -> None:
        """Forget every entry."""
        self._items.clear()

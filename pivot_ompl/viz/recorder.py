"""A server-less meshcat window that records scene-tree commands (for offline HTML export).

``meshcat.Visualizer(window=RecordingWindow())`` accepts every call a live visualizer does
(``set_object``, ``set_transform``, ``set_property``, ``set_animation``, ``delete``) without
starting a server process; :meth:`RecordingWindow.commands` replays the resulting scene tree
as packed command blobs in a safe order (objects, properties and transforms depth-first,
the animation last, as the browser needs the animated nodes first).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import meshcat
import umsgpack


class _Node(dict):
    """A scene-tree node mirroring meshcat's server tree (children in insertion order)."""

    def __init__(self) -> None:
        super().__init__()
        self.object: bytes | None = None
        self.properties: list[bytes] = []
        self.transform: bytes | None = None

    def child(self, name: str) -> _Node:
        if name not in self:
            self[name] = _Node()
        return self[name]

    def walk(self) -> Iterator[_Node]:
        yield self
        for c in self.values():
            yield from c.walk()


class RecordingWindow:
    """Stands in for ``meshcat.visualizer.ViewerWindow``; keeps the scene tree in memory.

    Attributes:
        single_precision: pack floats as 32-bit (three.js stores float32 anyway; halves size).
    """

    web_url = ""
    server_proc = None

    def __init__(self, *, single_precision: bool = True) -> None:
        self.single_precision = single_precision
        self.tree = _Node()
        self.animation: bytes | None = None
        self.sent = 0

    def _pack(self, data: dict[str, Any]) -> bytes:
        if self.single_precision:
            return umsgpack.packb(data, force_float_precision="single")
        return umsgpack.packb(data)

    def _find(self, path: str) -> _Node:
        node = self.tree
        for part in path.split("/"):
            if part:
                node = node.child(part)
        return node

    def send(self, command: Any) -> None:
        """Record one meshcat command (same tree semantics as meshcat's server)."""
        data = command.lower()
        kind = data["type"]
        self.sent += 1
        if kind == "set_animation":
            self.animation = self._pack(data)
            return
        path = data["path"]
        if kind == "delete":
            parts = [p for p in path.split("/") if p]
            if not parts:
                self.tree = _Node()
                self.animation = None
                return
            parent = self._find("/".join(parts[:-1]))
            parent.pop(parts[-1], None)
            return
        node = self._find(path)
        blob = self._pack(data)
        if kind == "set_object":
            node.object = blob
            node.properties = []
        elif kind == "set_transform":
            node.transform = blob
        elif kind == "set_property":
            node.properties.append(blob)
        else:
            raise ValueError(f"meshcat command {kind!r} cannot be recorded")

    def send_packed(self, kind: str, path: str, blob: bytes) -> None:
        """Record an already-packed command (only ``set_animation`` is supported)."""
        if kind != "set_animation":
            raise ValueError(f"packed {kind!r} commands cannot be recorded")
        self.sent += 1
        self.animation = blob

    def commands(self) -> list[bytes]:
        """The packed commands that rebuild the scene, the animation last."""
        out: list[bytes] = []
        for node in self.tree.walk():
            if node.object is not None:
                out.append(node.object)
            out.extend(node.properties)
            if node.transform is not None:
                out.append(node.transform)
        if self.animation is not None:
            out.append(self.animation)
        return out

    def paths(self) -> list[str]:
        """Every node path holding an object (``/meshcat/box``...), for checks and tests."""
        found: list[str] = []

        def rec(node: _Node, prefix: str) -> None:
            for name, c in node.items():
                p = f"{prefix}/{name}"
                if c.object is not None:
                    found.append(p)
                rec(c, p)

        rec(self.tree, "")
        return found

    def open(self) -> RecordingWindow:  # noqa: D102 - API parity with ViewerWindow
        return self

    def close(self) -> None:  # noqa: D102
        pass


def recording_visualizer(*, single_precision: bool = True) -> meshcat.Visualizer:
    """A ``meshcat.Visualizer`` backed by a :class:`RecordingWindow` (no server process)."""
    return meshcat.Visualizer(window=RecordingWindow(single_precision=single_precision))

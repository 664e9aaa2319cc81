"""Building the meshcat animation (``meshcat.animation.Animation``) from sampled transforms.

Times are stored in seconds (clip ``fps = 1``), so keys need not lie on a frame grid. Tracks
hold numpy arrays (:class:`ArrayTrack`, a ``meshcat.animation.AnimationTrack``) rather than
being filled frame by frame, and :func:`pack_set_animation` encodes the ``set_animation``
command to msgpack with numpy (float32 keys), which keeps long replays (tens of thousands of
keys per track) fast to build. Keys that linear interpolation reproduces within a tolerance
can be dropped (:func:`reduce_keys`, all tracks of one time base at once). The animation
plays with meshcat's play/pause/time panel.
"""

from __future__ import annotations

import logging
import struct
from collections.abc import Sequence
from typing import Any

import meshcat
import numpy as np
from meshcat.animation import Animation, AnimationClip, AnimationTrack

log = logging.getLogger(__name__)


def matrix_to_quat_xyzw(r: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(K, 4)`` (x, y, z, w) of rotation matrices ``(K, 3, 3)``."""
    r = np.asarray(r, dtype=float)
    k = r.shape[0]
    q = np.empty((k, 4))
    tr = r[:, 0, 0] + r[:, 1, 1] + r[:, 2, 2]
    # Robust branch per key: pick the largest of w, x, y, z.
    diag = np.stack([tr, r[:, 0, 0], r[:, 1, 1], r[:, 2, 2]], axis=1)
    best = np.argmax(diag, axis=1)
    for case in range(4):
        m = best == case
        if not np.any(m):
            continue
        rr = r[m]
        if case == 0:
            s = np.sqrt(np.maximum(tr[m] + 1.0, 1e-12)) * 2
            q[m] = np.stack([(rr[:, 2, 1] - rr[:, 1, 2]) / s, (rr[:, 0, 2] - rr[:, 2, 0]) / s,
                             (rr[:, 1, 0] - rr[:, 0, 1]) / s, 0.25 * s], axis=1)
        elif case == 1:
            s = np.sqrt(np.maximum(1.0 + rr[:, 0, 0] - rr[:, 1, 1] - rr[:, 2, 2], 1e-12)) * 2
            q[m] = np.stack([0.25 * s, (rr[:, 0, 1] + rr[:, 1, 0]) / s,
                             (rr[:, 0, 2] + rr[:, 2, 0]) / s, (rr[:, 2, 1] - rr[:, 1, 2]) / s],
                            axis=1)
        elif case == 2:
            s = np.sqrt(np.maximum(1.0 + rr[:, 1, 1] - rr[:, 0, 0] - rr[:, 2, 2], 1e-12)) * 2
            q[m] = np.stack([(rr[:, 0, 1] + rr[:, 1, 0]) / s, 0.25 * s,
                             (rr[:, 1, 2] + rr[:, 2, 1]) / s, (rr[:, 0, 2] - rr[:, 2, 0]) / s],
                            axis=1)
        else:
            s = np.sqrt(np.maximum(1.0 + rr[:, 2, 2] - rr[:, 0, 0] - rr[:, 1, 1], 1e-12)) * 2
            q[m] = np.stack([(rr[:, 0, 2] + rr[:, 2, 0]) / s, (rr[:, 1, 2] + rr[:, 2, 1]) / s,
                             0.25 * s, (rr[:, 1, 0] - rr[:, 0, 1]) / s], axis=1)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    # Keep consecutive quaternions in the same hemisphere (smooth slerp).
    if k > 1:
        dots = np.einsum("ij,ij->i", q[1:], q[:-1])
        q[1:] *= np.cumprod(np.where(dots < 0, -1.0, 1.0))[:, None]
    return q




def reduce_keys(times: np.ndarray, values: np.ndarray, tol: np.ndarray | float, *,
                max_span: int = 128) -> tuple[np.ndarray, np.ndarray]:
    """Drop keys that linear interpolation reproduces, for ``M`` tracks sharing ``times``.

    Hierarchical merging, vectorised over tracks and segments: at level ``L`` the samples
    are cut into segments of ``2**L`` intervals; a segment whose two halves were merged at
    the previous level is merged (its middle key dropped) when the straight line between its
    end samples passes within ``tol`` (per component) of every original sample inside it.
    Kept keys keep their exact sample values, so the error bound holds against the samples.

    Args:
        times: ``(K,)`` non-decreasing times (s).
        values: ``(M, K, D)`` samples.
        tol: per-track tolerance ``(M,)`` or one value; 0 keeps every key of that track.
        max_span: longest merged segment, in sample intervals (rounded down to a power of 2).

    Returns:
        ``keep`` ``(M, K)`` bool and the key values ``(M, K, D)`` (the samples).
    """
    t = np.asarray(times, dtype=float)
    v = np.asarray(values, dtype=float)
    m, k, _ = v.shape
    tol_m = np.broadcast_to(np.asarray(tol, dtype=float), (m,))
    keep = np.ones((m, k), dtype=bool)
    rows = np.flatnonzero(tol_m > 0)
    if k <= 2 or len(rows) == 0:
        return keep, v
    vv, tt = v[rows], tol_m[rows][:, None]
    ok = np.ones((len(rows), k - 1), dtype=bool)  # level 0: every single interval
    half = 1
    while 2 * half <= max_span:
        n_seg = (k - 1) // (2 * half)
        if n_seg == 0:
            break
        starts = np.arange(n_seg) * 2 * half
        ends = starts + 2 * half
        both = ok[:, 0:2 * n_seg:2] & ok[:, 1:2 * n_seg:2]  # (R, n_seg)
        if not np.any(both):
            break
        idx = starts[:, None] + np.arange(1, 2 * half)[None, :]  # inner samples
        span = np.maximum(t[ends] - t[starts], 1e-12)
        w = (t[idx] - t[starts][:, None]) / span[:, None]  # (n_seg, 2h-1)
        v0, v1 = vv[:, starts], vv[:, ends]  # (R, n_seg, D)
        line = v0[:, :, None, :] + w[None, :, :, None] * (v1 - v0)[:, :, None, :]
        err = np.abs(line - vv[:, idx]).max(axis=(2, 3))  # (R, n_seg)
        merged = both & (err <= tt)
        rr, ss = np.nonzero(merged)
        keep[rows[rr], starts[ss] + half] = False
        ok = merged
        half *= 2
    return keep, v


class ArrayTrack(AnimationTrack):
    """An ``AnimationTrack`` backed by arrays: ``times`` ``(K,)`` s, ``array`` ``(K, D)``."""

    __slots__ = ["times", "array"]

    def __init__(self, name: str, jstype: str, times: np.ndarray, array: np.ndarray) -> None:
        super().__init__(name, jstype)
        self.times = np.asarray(times, dtype=float)
        self.array = np.asarray(array, dtype=float)

    def lower(self) -> dict[str, Any]:
        """Plain Python structure (as meshcat's own tracks; used by other windows)."""
        return {"name": "." + self.name, "type": self.jstype,
                "keys": [{"time": float(t), "value": v.tolist()}
                         for t, v in zip(self.times, self.array, strict=True)]}


class _Packed:
    """Already-encoded msgpack bytes inside a structure given to :func:`_encode`."""

    __slots__ = ["data"]

    def __init__(self, data: bytes) -> None:
        self.data = data


def _pack_keys(times: np.ndarray, values: np.ndarray) -> bytes:
    """Encode ``[{"time": t, "value": [v...]}, ...]`` with float32 numbers (vectorised)."""
    k, d = values.shape
    rec = np.zeros((k, 18 + 5 * d), dtype=np.uint8)
    rec[:, 0] = 0x82
    rec[:, 1:6] = np.frombuffer(b"\xa4time", dtype=np.uint8)
    rec[:, 6] = 0xCA
    rec[:, 7:11] = times.astype(">f4").view(np.uint8).reshape(k, 4)
    rec[:, 11:17] = np.frombuffer(b"\xa5value", dtype=np.uint8)
    rec[:, 17] = 0x90 | d
    vals = values.astype(">f4").view(np.uint8).reshape(k, d, 4)
    body = rec[:, 18:].reshape(k, d, 5)
    body[:, :, 0] = 0xCA
    body[:, :, 1:] = vals
    return _array_header(k) + rec.tobytes()


def _array_header(n: int) -> bytes:
    if n < 16:
        return bytes([0x90 | n])
    if n < 1 << 16:
        return b"\xdc" + struct.pack(">H", n)
    return b"\xdd" + struct.pack(">I", n)


def _encode(obj: Any, out: list[bytes]) -> None:
    """A minimal msgpack encoder (maps, lists, str, bool, int, float, None, _Packed)."""
    if isinstance(obj, _Packed):
        out.append(obj.data)
    elif obj is None:
        out.append(b"\xc0")
    elif isinstance(obj, bool):
        out.append(b"\xc3" if obj else b"\xc2")
    elif isinstance(obj, int):
        if 0 <= obj < 128:
            out.append(bytes([obj]))
        elif -32 <= obj < 0:
            out.append(struct.pack("b", obj))
        else:
            out.append(b"\xd3" + struct.pack(">q", obj))
    elif isinstance(obj, float):
        out.append(b"\xcb" + struct.pack(">d", obj))
    elif isinstance(obj, str):
        b = obj.encode("utf-8")
        n = len(b)
        if n < 32:
            out.append(bytes([0xA0 | n]) + b)
        elif n < 256:
            out.append(b"\xd9" + bytes([n]) + b)
        elif n < 1 << 16:
            out.append(b"\xda" + struct.pack(">H", n) + b)
        else:
            out.append(b"\xdb" + struct.pack(">I", n) + b)
    elif isinstance(obj, dict):
        n = len(obj)
        out.append(bytes([0x80 | n]) if n < 16 else b"\xde" + struct.pack(">H", n))
        for key, val in obj.items():
            _encode(str(key), out)
            _encode(val, out)
    elif isinstance(obj, list | tuple):
        out.append(_array_header(len(obj)))
        for val in obj:
            _encode(val, out)
    else:
        raise TypeError(f"cannot encode {type(obj).__name__}")


def pack_set_animation(animation: Animation, *, play: bool = True,
                       repetitions: int = 1) -> bytes:
    """Encode meshcat's ``set_animation`` command to msgpack (array tracks packed fast)."""
    anims = []
    for path, clip in animation.clips.items():
        tracks = []
        for tr in clip.tracks.values():
            if isinstance(tr, ArrayTrack):
                keys: Any = _Packed(_pack_keys(tr.times, tr.array))
            else:
                keys = tr.lower()["keys"]
            tracks.append({"name": "." + tr.name, "type": tr.jstype, "keys": keys})
        anims.append({"path": path.lower(),
                      "clip": {"fps": clip.fps, "name": clip.name, "tracks": tracks}})
    cmd = {"type": "set_animation", "animations": anims,
           "options": {"play": bool(play), "repetitions": int(repetitions)}, "path": ""}
    out: list[bytes] = []
    _encode(cmd, out)
    return b"".join(out)


class AnimationBuilder:
    """Collects per-node tracks and produces one ``meshcat.animation.Animation``.

    Args:
        vis: the visualizer whose paths the animated nodes live under.
    """

    def __init__(self, vis: meshcat.Visualizer) -> None:
        self.vis = vis
        self.animation = Animation(default_framerate=1)
        self.duration = 0.0
        self._pending: list[tuple[AnimationClip, str, str, np.ndarray, np.ndarray, float]] = []
        self.keys = 0

    def _clip(self, node: str) -> AnimationClip:
        path = self.vis.path.append(node)
        if path not in self.animation.clips:
            self.animation.clips[path] = AnimationClip(fps=1)
        return self.animation.clips[path]

    def add_transforms(self, node: str, times: Sequence[float], transforms: np.ndarray, *,
                       position: bool = True, rotation: bool = True,
                       position_tol: float = 0.0, rotation_tol: float = 0.0) -> None:
        """Animate node ``node`` (relative to ``vis``) through ``transforms`` ``(K, 4, 4)``.

        ``position=False`` or ``rotation=False`` skips a track that does not change (the
        node keeps its ``set_transform`` value for it). With tolerances > 0 (m, and
        quaternion components ~ half-angles in rad), keys that linear interpolation
        reproduces are dropped when the animation is built (:func:`reduce_keys`).
        """
        tr = np.asarray(transforms, dtype=float)
        t = np.asarray(times, dtype=float)
        clip = self._clip(node)
        if position:
            self._pending.append((clip, "position", "vector3", t, tr[:, :3, 3], position_tol))
        if rotation:
            self._pending.append((clip, "quaternion", "quaternion", t,
                                  matrix_to_quat_xyzw(tr[:, :3, :3]), rotation_tol))
        if len(t):
            self.duration = max(self.duration, float(t[-1]))

    def build(self) -> Animation:
        """Reduce the pending tracks (grouped by time base) into the animation's clips."""
        groups: dict[tuple[int, bytes], list[int]] = {}
        for n, (_, _, _, t, _, _) in enumerate(self._pending):
            groups.setdefault((len(t), t.tobytes()), []).append(n)
        for members in groups.values():
            t = self._pending[members[0]][3]
            vals = np.zeros((len(members), len(t), 4))
            for row, n in enumerate(members):
                a = self._pending[n][4]
                vals[row, :, :a.shape[1]] = a
            tols = np.array([self._pending[n][5] for n in members])
            keep, out = reduce_keys(t, vals, tols)
            for row, n in enumerate(members):
                clip, name, jstype, _, a, _ = self._pending[n]
                sel = keep[row]
                clip.tracks[name] = ArrayTrack(name, jstype, t[sel], out[row, sel, :a.shape[1]])
                self.keys += int(sel.sum())
        self._pending.clear()
        return self.animation

    def send(self, *, play: bool = True, repetitions: int = 1) -> Animation:
        """Send the animation to ``vis`` (it starts playing when loaded if ``play``).

        Recording and zmq (live server) windows get the fast-packed command; any other
        window gets ``vis.set_animation``.
        """
        from pivot_ompl.viz.recorder import RecordingWindow

        anim = self.build()
        log.debug("animation: %d clips, %d keys, %.1f s", len(anim.clips), self.keys,
                  self.duration)
        window = self.vis.window
        if isinstance(window, RecordingWindow):
            window.send_packed("set_animation", "",
                               pack_set_animation(anim, play=play, repetitions=repetitions))
        elif hasattr(window, "zmq_socket"):
            window.zmq_socket.send_multipart(
                [b"set_animation", b"", pack_set_animation(anim, play=play,
                                                           repetitions=repetitions)])
            window.zmq_socket.recv()
        else:
            self.vis.set_animation(anim, play=play, repetitions=repetitions)
        return anim

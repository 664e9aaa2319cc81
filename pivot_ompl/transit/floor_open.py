"""Which grid positions of a block the walking body fits at some yaw: cheap answers first.

A position is open when the body fits there at one of the open yaws at least. Two cheap
facts decide most positions before the obstacle pieces' sums with the body are rasterised
at every yaw:

* **Closed at every yaw**: the grown body at any yaw holds the disk of its inscribed radius
  ``rho`` round its reference point (:func:`inscribed_radius`), so a position nearer than
  ``rho`` to an obstacle piece puts the body on the piece at every yaw, and lies inside that
  piece's sum by ``rho`` less its distance (:func:`surely_closed`). Only positions inside
  by more than :data:`DEEP` are taken: the sums' float rasterisation (rounding far below a
  micrometre at a building's coordinates) then finds them inside too.
* **Open once one yaw fits**: the yaws are tried a block at a time, spread round the circle
  (:data:`YAW_BLOCKS`), and each block sums and rasterises only the pieces that can reach a
  position still undecided. Whether a piece's sum holds a position depends on that piece
  alone, so the undecided positions get the same answers as from every piece near the block.
"""

from __future__ import annotations

import numpy as np

#: Margin (m) by which a position must lie inside a piece's sum to be taken as closed
#: without rasterising it.
DEEP = 1e-6


def _spread(n: int) -> list[int]:
    """``0 .. n - 1`` in bit-reversed order (each prefix spread evenly round the circle)."""
    bits = max(1, (n - 1).bit_length())
    return sorted(range(n), key=lambda i: int(f"{i:0{bits}b}"[::-1], 2))


def yaw_blocks(n: int, size: int = 4) -> list[list[int]]:
    """The yaw indices below ``n`` in blocks of ``size``, each block spread round the circle."""
    order = _spread(n)
    return [order[i:i + size] for i in range(0, n, size)]


def inscribed_radius(bodies: list[np.ndarray]) -> float:
    """The radius of the disk round the origin inside every convex body of ``bodies``.

    The least distance from the origin to an edge's line; 0 when the origin is not strictly
    inside a body.
    """
    best = np.inf
    for body in bodies:
        a, b = body, np.roll(body, -1, axis=0)
        e = b - a
        length = np.hypot(e[:, 0], e[:, 1])
        if not (length > 0.0).all():
            return 0.0
        side = (a[:, 0] * e[:, 1] - a[:, 1] * e[:, 0]) / length  # origin's side, signed
        if not ((side > 0.0).all() or (side < 0.0).all()):
            return 0.0
        best = min(best, float(np.abs(side).min()))
    return 0.0 if not np.isfinite(best) else best


def piece_distances(pieces: list[np.ndarray], boxes: np.ndarray, xs: np.ndarray,
                    ys: np.ndarray, cap: float) -> np.ndarray:
    """Distance (m) from each position of the grid ``xs`` x ``ys`` to the nearest piece.

    ``pieces``: convex polygons; ``boxes``: their bounding boxes (``x0, y0, x1, y1``).
    Inside a piece is distance 0, elsewhere the distance to its nearest edge segment. Exact
    where at most ``cap``; farther positions hold a value above ``cap`` (the distance to a
    piece whose bounding box grown by ``cap`` holds them, else ``inf``).
    """
    out = np.full((len(xs), len(ys)), np.inf)
    if not len(pieces) or not len(xs) or not len(ys):
        return out
    i0 = np.searchsorted(xs, boxes[:, 0] - cap, side="left")
    i1 = np.searchsorted(xs, boxes[:, 2] + cap, side="right")
    j0 = np.searchsorted(ys, boxes[:, 1] - cap, side="left")
    j1 = np.searchsorted(ys, boxes[:, 3] + cap, side="right")
    sizes = np.array([len(p) for p in pieces])
    for k in np.unique(sizes).tolist():
        idx = np.flatnonzero(sizes == k)
        wi, wj = np.maximum(i1[idx] - i0[idx], 0), np.maximum(j1[idx] - j0[idx], 0)
        count = wi * wj
        if not count.sum():
            continue
        owner = np.repeat(np.arange(len(idx)), count)
        local = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
        pi = i0[idx][owner] + local // wj[owner]
        pj = j0[idx][owner] + local % wj[owner]
        a = np.stack([pieces[i] for i in idx.tolist()])[owner]  # (pairs, k, 2)
        e = np.roll(a, -1, axis=1) - a
        px, py = xs[pi][:, None] - a[..., 0], ys[pj][:, None] - a[..., 1]
        cross = e[..., 0] * py - e[..., 1] * px
        area = (a[..., 0] * e[..., 1] - a[..., 1] * e[..., 0]).sum(axis=1)
        inside = (np.where(area[:, None] > 0.0, -cross, cross) <= 0.0).all(axis=1)
        ee = (e * e).sum(axis=-1)
        t = np.clip(np.divide(px * e[..., 0] + py * e[..., 1], ee, out=np.zeros_like(ee),
                              where=ee > 0.0), 0.0, 1.0)
        d = np.where(inside, 0.0, np.hypot(px - t * e[..., 0], py - t * e[..., 1]).min(axis=1))
        np.minimum.at(out, (pi, pj), d)
    return out


def body_disks(body: np.ndarray, resolution: float) -> tuple[np.ndarray, np.ndarray]:
    """Grid offsets strictly inside a convex ``body`` and the disk round each inside it.

    Returns the offsets ``(n, 2)`` (grid steps) and each disk's radius (m) less
    :data:`DEEP`, largest first; a disk inside a larger one is left out.
    """
    reach = int(np.ceil(np.abs(body).max() / resolution))
    steps = np.arange(-reach, reach + 1)
    oi, oj = (a.ravel() for a in np.meshgrid(steps, steps, indexing="ij"))
    radii = np.array([inscribed_radius([body - resolution * np.array([i, j])])
                      for i, j in zip(oi.tolist(), oj.tolist(), strict=True)]) - DEEP
    keep = np.flatnonzero(radii > 0.0)
    keep = keep[np.argsort(-radii[keep], kind="stable")]
    kept: list[int] = []
    for i in keep.tolist():
        if not any(resolution * np.hypot(oi[i] - oi[j], oj[i] - oj[j]) + radii[i] <= radii[j]
                   for j in kept):
            kept.append(i)
    keep = np.asarray(kept, dtype=np.int64)
    return np.stack([oi[keep], oj[keep]], axis=1), radii[keep]


def closed_by_disks(dist: np.ndarray, pad: int, offsets: np.ndarray, radii: np.ndarray
                    ) -> np.ndarray:
    """Positions where a disk of ``body_disks`` reaches nearer than its radius to a piece.

    ``dist``: :func:`piece_distances` over the block grown by ``pad`` positions each side
    (``pad`` at least the largest offset). The body there then meets the piece, inside its
    sum by more than :data:`DEEP`.
    """
    nx, ny = dist.shape[0] - 2 * pad, dist.shape[1] - 2 * pad
    out = np.zeros((nx, ny), dtype=bool)
    for (i, j), r in zip(offsets.tolist(), radii.tolist(), strict=True):
        out |= dist[pad + i:pad + i + nx, pad + j:pad + j + ny] < r
    return out


def undecided_near(undecided: np.ndarray, boxes: np.ndarray, xs: np.ndarray, ys: np.ndarray,
                   reach: float) -> np.ndarray:
    """Per box (``x0, y0, x1, y1``) grown by ``reach``: whether it holds an undecided position."""
    table = np.zeros((len(xs) + 1, len(ys) + 1), dtype=np.int64)
    table[1:, 1:] = np.cumsum(np.cumsum(undecided, axis=0), axis=1)
    i0 = np.searchsorted(xs, boxes[:, 0] - reach, side="left")
    i1 = np.searchsorted(xs, boxes[:, 2] + reach, side="right")
    j0 = np.searchsorted(ys, boxes[:, 1] - reach, side="left")
    j1 = np.searchsorted(ys, boxes[:, 3] + reach, side="right")
    return (table[i1, j1] - table[i0, j1] - table[i1, j0] + table[i0, j0]) > 0

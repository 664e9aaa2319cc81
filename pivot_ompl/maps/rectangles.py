"""Blocked cells of a grid as few rectangles that cover exactly them.

Each row's blocked cells fall into maximal runs; a run is stacked onto the run of the row
above when both span the same columns, and a stack is one rectangle. The same is done on
columns (the transposed grid), and the decomposition with fewer rectangles is kept. The
rectangles never overlap and their union is exactly the blocked cells. Two rectangles of
one decomposition never share a whole side either (each row's runs are maximal and a stack
ends where the run below differs), so :func:`~pivot_ompl.validity.merge.merge_boxes` finds
nothing to merge in them.

Everything is vectorised with numpy (a sort of the runs): a 4000 x 4000 map of walls takes
well under a second; memory is a few bytes per cell and 32 bytes per run.
"""

from __future__ import annotations

import numpy as np


def _row_rectangles(blocked: np.ndarray) -> np.ndarray:
    """Rectangles ``[row0, col0, row1, col1]`` (end-exclusive) of stacked row runs."""
    h, w = blocked.shape
    padded = np.zeros((h, w + 2), dtype=np.int8)
    padded[:, 1:-1] = blocked
    steps = np.diff(padded, axis=1)
    del padded
    rows, starts = np.nonzero(steps == 1)
    _, ends = np.nonzero(steps == -1)  # row-major order: the k-th end closes the k-th start
    del steps
    if rows.size == 0:
        return np.zeros((0, 4), dtype=np.int64)
    order = np.lexsort((rows, ends, starts))
    rows, starts, ends = rows[order], starts[order], ends[order]
    new = np.ones(rows.size, dtype=bool)
    new[1:] = ((starts[1:] != starts[:-1]) | (ends[1:] != ends[:-1])
               | (rows[1:] != rows[:-1] + 1))
    first = np.flatnonzero(new)
    last = np.append(first[1:], rows.size) - 1
    return np.stack([rows[first], starts[first], rows[last] + 1, ends[first]], axis=1)


def cell_rectangles(blocked: np.ndarray) -> np.ndarray:
    """Disjoint rectangles covering exactly the true cells of the 2-D boolean ``blocked``.

    Returns:
        an ``(n, 4)`` int64 array of ``[row0, col0, row1, col1]``: rows ``row0 .. row1 - 1``
        and columns ``col0 .. col1 - 1``; sorted by row, then column.
    """
    blocked = np.asarray(blocked, dtype=bool)
    by_rows = _row_rectangles(blocked)
    by_cols = _row_rectangles(blocked.T)[:, [1, 0, 3, 2]]
    best = by_cols if len(by_cols) < len(by_rows) else by_rows
    return best[np.lexsort((best[:, 1], best[:, 0]))]

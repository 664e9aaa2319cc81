"""Text labels of a matplotlib figure placed so that no two of them overlap.

Each label points at a spot of the plot (a regrasp position, a walk's middle) with a thin
leader line. :func:`place_labels` tries offsets around the spot, nearest first in rings of
growing radius, and keeps the first whose text box (in display pixels, after the axes' limits
are final) meets no label placed before it and stays inside the figure. When every candidate
is taken (a very dense plan), the least overlapping one is kept: a label is never dropped.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Any

from matplotlib.text import Text

log = logging.getLogger(__name__)

#: Offsets tried around a spot: ring radii in points and directions per ring.
RING_RADII_PT = (10.0, 22.0, 36.0, 52.0, 72.0, 96.0, 124.0)
DIRECTIONS = 12
#: The text frame's margin around the glyphs (pixels at the figure's dpi).
FRAME_PAD_PX = 3.0


@dataclass(frozen=True)
class Label:
    """A label to place.

    Attributes:
        xy: the spot it points at (data coordinates, m).
        text: what it says.
        colour: text, frame and leader colour.
    """

    xy: tuple[float, float]
    text: str
    colour: str


def _offsets() -> list[tuple[float, float]]:
    """Candidate offsets (points), up-right first, ring by ring."""
    out = []
    for r in RING_RADII_PT:
        for k in range(DIRECTIONS):
            a = math.pi / 4 + 2 * math.pi * k / DIRECTIONS
            out.append((r * math.cos(a), r * math.sin(a)))
    return out


def _overlap(a: Any, b: Any) -> float:
    """Area (pixels²) shared by two matplotlib ``Bbox`` es."""
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return max(w, 0.0) * max(h, 0.0)


def text_box(ann: Any, renderer: Any) -> Any:
    """The display box of an annotation's text with its frame (the leader line left out)."""
    ann.update_positions(renderer)  # the offset applied, as a draw would
    return Text.get_window_extent(ann, renderer).padded(FRAME_PAD_PX)


def _annotate(ax: Any, label: Label, offset: tuple[float, float]) -> Any:
    return ax.annotate(
        label.text, label.xy, xytext=offset, textcoords="offset points", fontsize=8,
        color=label.colour, fontweight="bold", zorder=6,
        ha="left" if offset[0] >= 0 else "right", va="bottom" if offset[1] >= 0 else "top",
        bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": label.colour, "alpha": 0.9},
        arrowprops={"arrowstyle": "-", "color": label.colour, "lw": 0.8})


def place_labels(fig: Any, ax: Any, labels: list[Label]) -> list[Any]:
    """Annotate ``ax`` with ``labels``, no two text boxes overlapping where room allows.

    Call it last, once the axes' limits are set (placement is in display pixels). Returns the
    annotations in the order of ``labels``.
    """
    fig.draw_without_rendering()  # the aspect and limits as they will be drawn
    renderer = fig.canvas.get_renderer()
    frame = fig.bbox
    placed: list[Any] = []
    out = []
    for label in labels:
        best: tuple[float, Any] | None = None
        for offset in _offsets():
            ann = _annotate(ax, label, offset)
            box = text_box(ann, renderer)
            clash = sum(_overlap(box, other) for other in placed)
            outside = box.width * box.height - _overlap(box, frame)
            score = clash + outside
            if best is None or score < best[0]:
                if best is not None:
                    best[1].remove()
                best = (score, ann)
            else:
                ann.remove()
            if score == 0.0:
                break
        assert best is not None  # noqa: S101 - _offsets() is never empty
        if best[0] > 0:
            log.debug("label %r overlaps others: no free place within %g pt", label.text,
                      RING_RADII_PT[-1])
        placed.append(text_box(best[1], renderer))
        out.append(best[1])
    return out

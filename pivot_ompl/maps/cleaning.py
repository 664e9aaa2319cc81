"""Optional cleaning of a map's blocked cells (occupied or unknown) before they become boxes.

Two operations, both off by default, each turning some blocked cells into free floor (never
the reverse); the counts of what each removed go into the scene's header:

- **specks** (area ``A`` m²): a connected group of blocked cells (8-connected) of at most
  ``A`` m² that does not touch the floor area's border is made free: isolated laser hits,
  dust, unseen pockets a few cells wide. Real small obstacles (a table leg, a bin) go with
  them: pick ``A`` below the smallest obstacle that matters.
- **streaks** (length ``L`` m): a one-cell-wide line of blocked cells that hangs into free
  space, held at most at one end, is made free when it has at most ``L / resolution``
  cells: the spurious lines a laser leaves along glass and at grazing angles. A cell is
  *thin* when no 2 x 2 square of blocked cells holds it; a streak is a connected group of
  thin cells (8-connected) whose cells next to thick blocked cells form at most one
  connected group (it touches the rest of the map at one place or not at all). A thin wall
  joining two walls, or joining one wall at both ends, touches at two places and stays. A
  one-cell-thick wall's free end (a door jamb) is also such a line: on maps whose walls are
  one cell thick, ``L`` must stay below the shortest wall stub that matters.

- **gaps** (width ``W`` m): the reverse, on the free cells, before the floor area is cut:
  a free cell that no free square of ``W / resolution`` cells a side (rounded down; below 2
  nothing is done) holds is made blocked: the fans of free rays a laser leaves through doors
  and glass into unseen space, and free slivers between obstacles. The floor area shrinks to
  what remains and the boxes get fewer (the Willow Garage map at 0.3 m: 5314 boxes to 3642).
  No body narrower than ``W`` is lost, with one exception: a box's corner can no longer poke
  into such a gap, and a gap running at 45 degrees closes below ``W * sqrt(2)``. Keep ``W``
  below the box's and the robot's smallest side.

All three use :mod:`scipy.ndimage` (labelling and binary morphology).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

logger = logging.getLogger(__name__)

_EIGHT = np.ones((3, 3), dtype=bool)
#: Width of the blocked ring put round the grid (cells): two, so that it is thick.
_RING = 2


@dataclass(frozen=True)
class MapCleaning:
    """What :func:`clean_blocked` removes (0 turns an operation off).

    Attributes:
        specks: largest area (m²) of a group of blocked cells made free.
        streaks: longest one-cell-wide dangling line (m) made free.
        gaps: free cells held by no free square of this side (m) are made blocked.
    """

    specks: float = 0.0
    streaks: float = 0.0
    gaps: float = 0.0


@dataclass(frozen=True)
class CleaningReport:
    """What :func:`clean_blocked` changed.

    Attributes:
        specks: groups of cells removed as specks.
        speck_cells: their cells.
        streaks: lines removed as streaks.
        streak_cells: their cells.
        gap_cells: free cells made blocked as gaps.
    """

    specks: int = 0
    speck_cells: int = 0
    streaks: int = 0
    streak_cells: int = 0
    gap_cells: int = 0


def _remove_specks(blocked: np.ndarray, max_cells: int) -> tuple[int, int]:
    """Free the groups of at most ``max_cells`` blocked cells off the border (in place)."""
    labels, count = ndimage.label(blocked, structure=_EIGHT)
    if count == 0:
        return 0, 0
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    small = sizes <= max_cells
    small[0] = False
    small[labels[0, 0]] = False  # the blocked ring round the grid (see clean_blocked)
    gone = small[labels]
    blocked[gone] = False
    return int(np.count_nonzero(small)), int(np.count_nonzero(gone))


def _remove_streaks(blocked: np.ndarray, max_cells: int) -> tuple[int, int]:
    """Free the dangling one-cell-wide lines of at most ``max_cells`` cells (in place)."""
    thick = ndimage.binary_opening(blocked, structure=np.ones((2, 2), dtype=bool))
    thin = blocked & ~thick
    labels, count = ndimage.label(thin, structure=_EIGHT)
    if count == 0:
        return 0, 0
    contact = thin & ndimage.binary_dilation(thick, structure=_EIGHT)
    places, n_places = ndimage.label(contact, structure=_EIGHT)
    touches = np.zeros(count + 1, dtype=np.int64)
    if n_places:
        where = places > 0
        pairs = np.unique(np.stack([labels[where], places[where]]), axis=1)
        touches += np.bincount(pairs[0], minlength=count + 1)
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    streak = (touches <= 1) & (sizes <= max_cells)
    streak[0] = False
    gone = streak[labels]
    blocked[gone] = False
    return int(np.count_nonzero(streak)), int(np.count_nonzero(gone))


def close_gaps(free: np.ndarray, width: float, resolution: float) -> int:
    """Block the free cells of ``free`` no free square of side ``width`` (m) holds (in place).

    Returns:
        how many cells were made blocked (0 when ``width`` is below two cells).
    """
    side = int(width / resolution + 1e-9)
    if side < 2:
        return 0
    kept = ndimage.binary_opening(free, structure=np.ones((side, side), dtype=bool))
    closed = int(np.count_nonzero(free)) - int(np.count_nonzero(kept))
    free[...] = kept
    if closed:
        logger.info("closed %d free cells in gaps narrower than %g m", closed, width)
    return closed


def clean_blocked(blocked: np.ndarray, cleaning: MapCleaning, resolution: float
                  ) -> CleaningReport:
    """Apply ``cleaning`` to the boolean grid ``blocked`` in place (streaks, then specks).

    The grid is read as surrounded by blocked cells (beyond a map's floor area every cell
    is blocked): a group touching the grid's border is never a speck, and a line touching
    it touches there. ``resolution`` (m per cell) turns the areas and lengths into cell
    counts (rounded down).
    """
    streaks = streak_cells = specks = speck_cells = 0
    if cleaning.streaks <= 0 and cleaning.specks <= 0:
        return CleaningReport()
    grid = np.pad(blocked, _RING, constant_values=True)
    if cleaning.streaks > 0:
        streaks, streak_cells = _remove_streaks(
            grid, int(cleaning.streaks / resolution + 1e-9))
    if cleaning.specks > 0:
        specks, speck_cells = _remove_specks(
            grid, int(cleaning.specks / resolution**2 + 1e-9))
    blocked[...] = grid[_RING:-_RING, _RING:-_RING]
    report = CleaningReport(specks, speck_cells, streaks, streak_cells)
    if streaks or specks:
        logger.info("cleaned %d specks (%d cells) and %d streaks (%d cells)", specks,
                    speck_cells, streaks, streak_cells)
    return report

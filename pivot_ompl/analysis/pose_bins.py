"""The held assembly's free regions per yaw bin and grasp, each built from what is known.

:func:`~pivot_ompl.analysis.pose_cells.free_region` takes the union of every obstacle
piece's sum with the bin's cores: a few milliseconds of GEOS per bin and grasp, most of the
held poses' proof (:mod:`~pivot_ompl.analysis.pose_proof`). :class:`BinRegions` gives an
over-approximation as sound (never missing a valid pose) and no looser (a halved bin's lies
inside its parent's too) for less, in two ways, besides summing only the pieces whose sums'
bounding boxes meet a region's part, joining only the sums that meet it, and joining the
box's sums (every grasp holds the box) once per bin:

- **The half-turn twin.** Where every grasp's bodies turned by a half turn are another
  grasp's (the box is a rectangle about its centre; a grasp on the opposite face holds it the
  other way round: :func:`half_turn_twins`), the assembly at yaw ``t + pi`` and grasp ``g'``
  covers what it covers at ``t`` and ``g``, so the bin ``[a + pi, b + pi]`` has the regions of
  ``[a, b]``, grasps swapped: nothing to compute.
- **The parent bin.** A halved bin lies inside its parent, whose region over-approximates
  every valid position at every yaw of the half too; so the half's region is the parent's
  less the half's own sums, and only the sums that meet the parent's region can take
  anything from it (in the TurtleBot3 arena about a quarter of them): a small union, and a
  difference from a small region.

Bins are matched to within :data:`SAME_YAW` rad (edges made by halving carry round-off): a
bin that far off another moves no body point by more than ``SAME_YAW`` times its reach (under
2e-9 m for a reach of 2 m), far inside the clearance's
:data:`~pivot_ompl.analysis.pose_cells.ROUND_OFF`.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_cells import convex_sums, rotation_core

#: Bins whose edges are this close (rad) are one bin (see the module docstring).
SAME_YAW = 1e-9
#: Tolerance (m) of the half-turn twins' check (body vertices inside the twin's body).
TWIN_TOLERANCE = 1e-9

Key = tuple[int, int]


def _inside(points: np.ndarray, body: np.ndarray, tolerance: float) -> bool:
    """Whether every point lies inside the convex counter-clockwise polygon ``body``."""
    e = np.roll(body, -1, axis=0) - body
    normals = np.stack([e[:, 1], -e[:, 0]], axis=1)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    depth = np.einsum("pvd,vd->pv", points[:, None, :] - body[None], normals)
    return bool((depth <= tolerance).all())


def _covers(outer: list[np.ndarray], inner: list[np.ndarray]) -> bool:
    """Whether every body of ``inner`` lies inside some body of ``outer``."""
    return all(any(_inside(b, c, TWIN_TOLERANCE) for c in outer) for b in inner)


def half_turn_twins(bodies: list[list[np.ndarray]]) -> list[int] | None:
    """Per grasp ``g``, the grasp whose bodies are ``g``'s turned by a half turn (or ``None``).

    ``bodies``: per grasp, its convex bodies (counter-clockwise) about the box's centre. A
    grasp's twin holds, at yaw ``t + pi``, exactly the floor its grasp holds at ``t``;
    ``None`` when some grasp has no twin (then no bin borrows another's regions).
    """
    out = []
    for bs in bodies:
        turned = [-b for b in bs]  # a half turn about the centre: still counter-clockwise
        twin = next((h for h, cs in enumerate(bodies)
                     if _covers(cs, turned) and _covers(turned, cs)), None)
        if twin is None:
            return None
        out.append(twin)
    return out if sorted(out) == list(range(len(bodies))) else None


def _key(a: float, b: float) -> Key:
    return round(a / SAME_YAW), round(b / SAME_YAW)


class BinRegions:
    """Per yaw bin ``[a, b]`` (``0 <= a < b <= 2 pi``), each grasp's free region, kept.

    A subclass may take other bodies per bin (:meth:`_cores`), where a half's region is not
    inside its parent's, none from a parent (:attr:`from_parents`), and where its regions
    may lose positions, the floor's coarse pieces (:attr:`coarse`, read by
    :class:`~pivot_ompl.analysis.pose_proof.HeldParts`).

    Args:
        grown: the grown obstacle pieces stacked by vertex count
            (:func:`~pivot_ompl.analysis.pose_cells.by_size`).
        bodies: per grasp, the assembly's convex bodies
            (:func:`~pivot_ompl.analysis.pose_cells.held_bodies`).
        area: where the box centre may be at all.
    """

    #: whether a halved bin's regions are built from its parent's (see the module docstring)
    from_parents = True
    #: whether the regions may be built from pieces holding the obstacles' (an
    #: under-approximation of the free set: :mod:`~pivot_ompl.analysis.pose_coarse`)
    coarse = False

    def __init__(self, grown: dict[int, np.ndarray], bodies: list[list[np.ndarray]],
                 area: BaseGeometry) -> None:
        """Nothing computed yet."""
        self.grown, self.area = grown, area
        #: every piece's bounding box, and per stack each tree entry's row (-1: another's)
        flat = [shapely.polygons(stack) for stack in grown.values()]
        self.tree = shapely.STRtree(np.concatenate(flat) if flat else [])
        self.index: dict[int, np.ndarray] = {}
        start = 0
        total = sum(len(f) for f in flat)
        for k, stack in grown.items():
            row = np.full(total, -1)
            row[start:start + len(stack)] = np.arange(len(stack))
            self.index[k], start = row, start + len(stack)
        #: the bodies every grasp has (the box), and each grasp's others (the robot)
        self.shared = [b for b in bodies[0]
                       if all(any(np.array_equal(b, c) for c in bs) for bs in bodies)]
        self.own = [[b for b in bs if not any(np.array_equal(b, c) for c in self.shared)]
                    for bs in bodies]
        self.twins = half_turn_twins(bodies)
        self.known: dict[Key, list[BaseGeometry]] = {}
        self.cores: dict[tuple[int, int], list[np.ndarray]] = {}
        #: bins whose regions were computed (the others were a twin's)
        self.computed = 0

    def regions(self, a: float, b: float) -> list[BaseGeometry]:
        """Per grasp, what of the area a box centre may stand on at the bin ``[a, b]``."""
        known = self._lookup(a, b)
        if known is not None:
            return known
        w = b - a
        parent = (self._lookup(a, a + 2.0 * w) or self._lookup(b - 2.0 * w, b)
                  if self.from_parents else None)
        half, mid = 0.5 * w, 0.5 * (a + b)
        c, s = math.cos(mid), math.sin(mid)
        turn = np.array([[c, -s], [s, c]]).T
        shared = [core @ turn for core in self._cores(-1, self.shared, half)]
        if parent is None:  # the box's region first: once for every grasp
            room = _less(self.area, self._sums(shared, [self.area]))
            parent = [room] * len(self.own)
        else:  # the box's sums joined once, for the pieces near any grasp's region
            box = _joined(self._sums(shared, parent), parent)
            parent = [p if box is None else p.difference(box) for p in parent]
        out = [_less(parent[g], self._sums([core @ turn for core in self._cores(g, own, half)],
                                           [parent[g]]))
               for g, own in enumerate(self.own)]
        self.known[_key(a, b)] = out
        self.computed += 1
        return out

    def _cores(self, which: int, bodies: list[np.ndarray], half: float) -> list[np.ndarray]:
        """The bodies' rotation cores for bins ``2 half`` wide (kept: bins share widths)."""
        key = (which, round(half / SAME_YAW))
        if key not in self.cores:
            self.cores[key] = [c for c in (rotation_core(body, half) for body in bodies)
                               if c is not None]
        return self.cores[key]

    def _lookup(self, a: float, b: float) -> list[BaseGeometry] | None:
        """The regions of ``[a, b]`` if known, or its half-turn twin's, grasps swapped."""
        if (hit := self.known.get(_key(a, b))) is not None:
            return hit
        if self.twins is None:
            return None
        shift = -math.pi if a >= math.pi - SAME_YAW else math.pi
        twin = self.known.get(_key(a + shift, b + shift))
        if twin is None:
            return None
        return [twin[self.twins[g]] for g in range(len(twin))]

    def _sums(self, bodies: list[np.ndarray], regions: list[BaseGeometry]) -> np.ndarray:
        """The positions where a turned core keeps no clearance, near the regions (polygons).

        Those positions are each piece's sum with the core reflected; only the pieces whose
        sums' bounding boxes meet a region part's are summed.
        """
        parts = [p for r in regions for p in getattr(r, "geoms", [r]) if not p.is_empty]
        if not parts or not bodies:
            return np.empty(0, dtype=object)
        boxes = shapely.bounds(np.asarray(parts, dtype=object))
        sums = []
        for body in bodies:
            lo, hi = body.min(axis=0) - 1e-6, body.max(axis=0) + 1e-6
            grown = boxes + np.concatenate([lo, hi])
            near = np.unique(self.tree.query(shapely.box(*grown.T))[1])
            for k, stack in self.grown.items():
                mine = self.index[k][near]
                mine = mine[mine >= 0]
                if len(mine):
                    sums.append(shapely.polygons(convex_sums(stack[mine], -body)))
        return np.concatenate(sums) if sums else np.empty(0, dtype=object)


def _joined(sums: np.ndarray, regions: list[BaseGeometry]) -> BaseGeometry | None:
    """The union of the ``sums`` that meet some of ``regions`` (``None``: none meets one)."""
    if len(sums) == 0:
        return None
    hit = np.zeros(len(sums), dtype=bool)
    for region in regions:
        if not region.is_empty:
            shapely.prepare(region)  # used as the predicate's first argument only
            hit |= shapely.intersects(region, sums)
            shapely.destroy_prepared(region)  # kept regions: no index held for every bin
    return shapely.union_all(sums[hit]) if hit.any() else None


def _less(region: BaseGeometry, sums: np.ndarray) -> BaseGeometry:
    """``region`` less the union of ``sums``: only those that meet it are joined."""
    if region.is_empty or len(sums) == 0:
        return region
    shapely.prepare(region)  # used as the predicate's first argument only
    hit = sums[shapely.intersects(region, sums)]
    return region.difference(shapely.union_all(hit)) if len(hit) else region

"""Contact and grip forces read from a MuJoCo step: the box's contacts, the hands' welds.

The model uses elliptic friction cones: a contact's rows of ``efc_force`` are its normal force
then its tangential forces, in the contact frame (``contact.frame``: normal, then the two
tangent axes). Summing contacts as world vectors gives the force the floor exerts near a
point (a pivot corner): the friction it *needs* there is the ratio of the horizontal to the
vertical part, which cannot exceed the contact's friction coefficient; a ratio at the
coefficient means the corner slides.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.physics.model import PhysicsModel

#: Contacts within this distance (m) of a corner belong to it.
CORNER_RADIUS = 0.03
#: A ratio at least this share of the friction coefficient is at the cone's limit (sliding).
LIMIT_SHARE = 0.98


@dataclass(frozen=True)
class BoxContacts:
    """The box's contacts at one instant (K of them).

    Attributes:
        pos: contact points (K x 3).
        force: world force the other geom (floor, obstacle) exerts on the box (K x 3, N).
        other: the other geom's index (K,).
        depth: penetration (K,, m; negative: a gap within the contact margin).
    """

    pos: np.ndarray
    force: np.ndarray
    other: np.ndarray
    depth: np.ndarray


_NONE = BoxContacts(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, dtype=int), np.zeros(0))


def box_contacts(pm: PhysicsModel) -> BoxContacts:
    """The box's contacts now."""
    d = pm.data
    n = int(d.ncon)
    if n == 0:
        return _NONE
    con = d.contact
    geom = np.asarray(con.geom[:n])
    mine = (geom == pm.box_geom).any(axis=1) & (np.asarray(con.efc_address[:n]) >= 0)
    if not mine.any():
        return _NONE
    idx = np.flatnonzero(mine)
    addr = np.asarray(con.efc_address[:n])[idx]
    dim = np.asarray(con.dim[:n])[idx]
    f = np.zeros((len(idx), 3))
    f[:, 0] = d.efc_force[addr]
    has_t = dim >= 3
    f[has_t, 1] = d.efc_force[addr[has_t] + 1]
    f[has_t, 2] = d.efc_force[addr[has_t] + 2]
    frame = np.asarray(con.frame[:n])[idx].reshape(-1, 3, 3)  # rows: normal, t1, t2
    world = np.einsum("ki,kij->kj", f, frame)  # force on geom2 from geom1
    g1, g2 = geom[idx, 0], geom[idx, 1]
    sign = np.where(g2 == pm.box_geom, 1.0, -1.0)
    other = np.where(g2 == pm.box_geom, g1, g2)
    return BoxContacts(np.asarray(con.pos[:n])[idx], world * sign[:, None], other,
                       -np.asarray(con.dist[:n])[idx])


def corner_force(pos: np.ndarray, force: np.ndarray, corner: np.ndarray) -> np.ndarray:
    """The summed world force (3,) of the contacts within :data:`CORNER_RADIUS` of ``corner``."""
    if not len(pos):
        return np.zeros(3)
    near = np.linalg.norm(pos - corner, axis=1) <= CORNER_RADIUS
    return force[near].sum(axis=0)


def weld_forces(pm: PhysicsModel, mj: object) -> tuple[float, float]:
    """The force (N) each hand's weld applies now (0 when off)."""
    d = pm.data
    n = int(d.nefc)
    if n == 0:
        return 0.0, 0.0
    typ = np.asarray(d.efc_type[:n])
    eq = np.flatnonzero(typ == int(mj.mjtConstraint.mjCNSTR_EQUALITY))  # type: ignore[attr-defined]
    if not len(eq):
        return 0.0, 0.0
    ids = np.asarray(d.efc_id[:n])[eq]
    out = []
    for w in pm.welds:
        rows = eq[ids == w]
        out.append(float(np.linalg.norm(d.efc_force[rows[:3]])) if len(rows) else 0.0)
    return out[0], out[1]


@dataclass
class PivotMeasure:
    """What one pivot rotation needed and did (filled sample by sample).

    Only the samples whose normal force at the corner is at least ``min_normal`` N count for
    the friction (an unloaded corner's ratio means nothing).

    Attributes:
        min_normal: normal force below which a sample's ratio is not counted (N).
        normal_max: the largest normal force at the corner (N).
        corner_slip: the largest distance of the simulated corner from where it was at the
            rotation's start (m).
        ratios: the horizontal/vertical force ratio at the corner of each counted sample.
    """

    min_normal: float
    normal_max: float = 0.0
    corner_slip: float = 0.0
    ratios: list[float] = field(default_factory=list, repr=False)
    start: np.ndarray | None = field(default=None, repr=False)

    def add(self, corner: np.ndarray, force: np.ndarray) -> None:
        """Count one sample: the corner's world position and the force there."""
        if self.start is None:
            self.start = corner.copy()
        self.corner_slip = max(self.corner_slip,
                               float(np.linalg.norm((corner - self.start)[:2])))
        fn = float(force[2])
        self.normal_max = max(self.normal_max, fn)
        if fn >= self.min_normal:
            self.ratios.append(float(np.hypot(force[0], force[1])) / fn)

    def friction(self, mu: float) -> tuple[float, float, float]:
        """The median and largest counted ratio, and the share of them at the limit ``mu``."""
        if not self.ratios:
            return 0.0, 0.0, 0.0
        r = np.asarray(self.ratios)
        return (float(np.median(r)), float(r.max()),
                float(np.mean(r >= LIMIT_SHARE * mu)))

"""Perturbations of a simulated run: friction patches, a mass offset, slips at pivots.

Each is written as a short text (the ``--perturb`` option, repeatable):

* ``slip`` or ``slip:N`` -- N (3 by default) slips at pivot rotations drawn from the seed
  (a numpy ``Generator``): each at a rotation drawn among the plan's, the box shifted on the
  floor by 2 to 5 cm in a drawn direction and turned by up to 2 deg;
* ``slip@K:DX,DY[,DYAW]`` -- a slip at rotation ``K`` (0 = the run's first): shift (m) and
  turn (rad);
* ``patch:X,Y,R,MU`` -- a disc of floor (centre, radius, m) where the friction is ``MU``
  while the box's centre is over it;
* ``mass:DX,DY,DZ`` -- the box's centre of mass moved by that much (m, box frame).

A slip is the grip slipping on the box while it turns: the hands' hold moves by the shift
(the weld's anchor jumps), and the box follows through its contact with the floor. The hands
keep the new hold until they let go: the box drifts from the plan.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import InputError

#: Slips drawn by a bare ``slip``; their shift (m) and largest turn (rad).
DEFAULT_SLIPS = 3
SLIP_SHIFT = (0.02, 0.05)
SLIP_TURN = math.radians(2.0)
#: Largest shift (m) and turn (rad) of a slip given explicitly.
MAX_SHIFT, MAX_TURN = 0.5, math.radians(30.0)


@dataclass(frozen=True)
class Slip:
    """The grip slips at pivot rotation ``pivot``: the box shifted by (dx, dy) m, turned by dyaw."""

    pivot: int
    dx: float
    dy: float
    dyaw: float = 0.0


@dataclass(frozen=True)
class FrictionPatch:
    """A disc of floor (centre ``x, y``, ``radius``, m) with friction coefficient ``mu``."""

    x: float
    y: float
    radius: float
    mu: float

    def covers(self, x: float, y: float) -> bool:
        """Whether the point (x, y) is on the patch."""
        return (x - self.x) ** 2 + (y - self.y) ** 2 <= self.radius ** 2


@dataclass(frozen=True)
class Perturbations:
    """The perturbations of one run (see the module docstring).

    Attributes:
        slips: slips by rotation index.
        patches: friction patches.
        com_offset: the box's centre-of-mass offset (m, box frame).
        specs: the texts they came from.
    """

    slips: tuple[Slip, ...] = ()
    patches: tuple[FrictionPatch, ...] = ()
    com_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    specs: tuple[str, ...] = field(default=())

    def slip_at(self, pivot: int) -> Slip | None:
        """The slip at rotation ``pivot``, if any."""
        for s in self.slips:
            if s.pivot == pivot:
                return s
        return None

    def friction_at(self, x: float, y: float, nominal: float) -> float:
        """The floor's friction at (x, y): the last patch covering it, else ``nominal``."""
        mu = nominal
        for p in self.patches:
            if p.covers(x, y):
                mu = p.mu
        return mu


def _numbers(text: str, spec: str, n: tuple[int, ...]) -> list[float]:
    try:
        v = [float(x) for x in text.split(",")]
    except ValueError:
        v = []
    if len(v) not in n or not all(math.isfinite(x) for x in v):
        raise InputError("--perturb", spec, f"needs {' or '.join(map(str, n))} numbers "
                         "separated by commas")
    return v


def parse_perturbations(specs: Sequence[str], *, pivots: int,
                        rng: np.random.Generator) -> Perturbations:
    """The perturbations of ``specs`` (random slips drawn with ``rng`` among ``pivots``).

    Raises:
        InputError: a spec that is not one of the module docstring's forms, naming it.
    """
    slips: list[Slip] = []
    patches: list[FrictionPatch] = []
    com = (0.0, 0.0, 0.0)
    for spec in specs:
        kind, _, rest = str(spec).strip().partition(":")
        if kind == "slip":
            n = DEFAULT_SLIPS if not rest else int(_numbers(rest, spec, (1,))[0])
            if not 0 <= n <= 1000:
                raise InputError("--perturb", spec, "needs 0..1000 slips")
            slips += draw_slips(n, pivots=pivots, rng=rng)
        elif kind.startswith("slip@"):
            try:
                k = int(kind[5:])
            except ValueError:
                raise InputError("--perturb", spec, "slip@K needs a whole rotation index K"
                                 ) from None
            v = _numbers(rest, spec, (2, 3))
            if k < 0 or math.hypot(v[0], v[1]) > MAX_SHIFT or (len(v) == 3
                                                               and abs(v[2]) > MAX_TURN):
                raise InputError("--perturb", spec, f"needs K >= 0, a shift <= {MAX_SHIFT} m "
                                 f"and a turn <= {MAX_TURN:.3g} rad")
            slips.append(Slip(k, v[0], v[1], v[2] if len(v) == 3 else 0.0))
        elif kind == "patch":
            x, y, r, mu = _numbers(rest, spec, (4,))
            if r <= 0 or not 0 < mu <= 5:
                raise InputError("--perturb", spec, "needs a radius > 0 and 0 < MU <= 5")
            patches.append(FrictionPatch(x, y, r, mu))
        elif kind == "mass":
            v = _numbers(rest, spec, (3,))
            com = (v[0], v[1], v[2])
        else:
            raise InputError("--perturb", spec, "must be slip, slip:N, slip@K:DX,DY[,DYAW], "
                             "patch:X,Y,R,MU or mass:DX,DY,DZ")
    return Perturbations(tuple(sorted(slips, key=lambda s: s.pivot)), tuple(patches), com,
                         tuple(str(s) for s in specs))


def draw_slips(n: int, *, pivots: int, rng: np.random.Generator) -> list[Slip]:
    """``n`` slips at distinct rotations among ``pivots`` (fewer if there are fewer)."""
    if pivots <= 0 or n <= 0:
        return []
    at = rng.choice(pivots, size=min(n, pivots), replace=False)
    out = []
    for k in sorted(int(a) for a in at):
        r = rng.uniform(*SLIP_SHIFT)
        a = rng.uniform(-math.pi, math.pi)
        out.append(Slip(k, r * math.cos(a), r * math.sin(a), rng.uniform(-SLIP_TURN,
                                                                          SLIP_TURN)))
    return out

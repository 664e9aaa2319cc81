"""Motion samples between solver ticks: the quadratic B-spline of the solver's configurations.

With one QP every ``m`` samples (:attr:`~pivot_ompl.wholebody.settings.WalkSettings.substeps`),
the samples are those of the uniform quadratic B-spline whose control points are the values
at the solver ticks (``K`` knots ``P_k`` a tick ``h`` apart, the first and last repeated):
a curve made of parabolas, continuous in value and speed, whose acceleration over each tick
is exactly the solver's discrete acceleration ``(P_{k+1} - 2 P_k + P_{k-1}) / h²``. So the
samples' finite-difference accelerations are averages of the solver's own (a bound such as
:class:`~pivot_ompl.wholebody.joint_damper.JointDamper`'s holds for the samples too), their
speeds averages of its speeds, and every sample lies in the convex hull of three
neighbouring knots (joint limits hold). Interpolating through the knots instead would
multiply the acceleration: a linear interpolation by ``m`` at every knot, a Catmull-Rom
cubic by up to 3 where the acceleration reverses. A sample at a tick is ``P_k + (P_{k+1} -
2 P_k + P_{k-1}) / 8``: within a few micrometres of the solver's configuration on the demo.

Sample ``i = m k + j`` (``0 <= j < m``) is at ``t_k + j h / m``; there are ``m (K - 1) + 1``.
With ``m = 1`` the samples are the knots themselves.
"""

from __future__ import annotations

import numpy as np

__all__ = ["blend", "blend_quaternions", "sample_labels", "sample_support"]


def _weights(u: float) -> tuple[float, float, float]:
    """Uniform quadratic B-spline basis at ``u`` in [0, 1] (previous, centre, next)."""
    return 0.5 * (1.0 - u) ** 2, 0.5 + u - u * u, 0.5 * u * u


def blend(knots: np.ndarray, m: int) -> np.ndarray:
    """Samples (``m (K - 1) + 1`` rows) of the quadratic B-spline of ``knots`` (K rows)."""
    P = np.asarray(knots, dtype=float)
    if m <= 1 or len(P) < 2:
        return P.copy()
    K = len(P)
    pad = np.concatenate((P[:1], P, P[-1:]))  # pad[c + 1] is knot c
    out = np.empty((m * (K - 1) + 1, *P.shape[1:]))
    for j in range(m):  # samples m k + j, k = 0, 1, ..., n - 1
        n = K if j == 0 else K - 1
        if 2 * j <= m:  # on the parabola centred on knot k
            c, u = 0, j / m + 0.5
        else:  # on the next one, centred on knot k + 1
            c, u = 1, j / m - 0.5
        a, b, d = _weights(u)
        out[j::m] = a * pad[c:c + n] + b * pad[c + 1:c + 1 + n] + d * pad[c + 2:c + 2 + n]
    return out


def blend_quaternions(quats: np.ndarray, m: int, *, positive_w: bool = False) -> np.ndarray:
    """:func:`blend` of unit quaternions (K x 4, x y z w), renormalised.

    The knots' signs are made continuous first (``q`` and ``-q`` are one rotation);
    ``positive_w`` returns every sample with ``w >= 0``.
    """
    Q = np.array(quats, dtype=float)
    if len(Q) > 1:
        flip = np.cumsum(np.einsum("ij,ij->i", Q[1:], Q[:-1]) < 0) % 2 == 1
        Q[1:][flip] *= -1.0
    out = blend(Q, m)
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    if positive_w:
        out[out[:, 3] < 0] *= -1.0
    return out


def sample_labels(labels: np.ndarray, m: int) -> np.ndarray:
    """A per-tick label (phase, step, ...) for every sample: the tick's at or before it."""
    L = np.asarray(labels)
    if m <= 1 or len(L) < 2:
        return L.copy()
    return np.concatenate((np.repeat(L[:-1], m, axis=0), L[-1:]))


def sample_support(codes: np.ndarray, m: int) -> np.ndarray:
    """Support codes of the samples (0 double, 1 left, 2 right) from the ticks' codes.

    A sample between two ticks of one code has that code; between a double and a single
    support, the single support's (only the foot that stays down counts as in contact).
    """
    C = np.asarray(codes, dtype=int)
    if m <= 1 or len(C) < 2:
        return C.copy()
    out = sample_labels(C, m)
    between = np.maximum(C[:-1], C[1:])  # 0 with 0 -> 0; 0 with s -> s; s with s -> s
    for j in range(1, m):
        out[j:-1:m] = between
    return out

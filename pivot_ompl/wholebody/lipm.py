"""The linear inverted pendulum (LIPM) of walking: gravity, natural frequency and the ZMP."""

from __future__ import annotations

import math

import numpy as np

#: Gravitational acceleration (m/s^2).
GRAVITY = 9.81


def omega(com_height: float) -> float:
    """LIPM natural frequency sqrt(g / com_height) (1/s)."""
    return math.sqrt(GRAVITY / com_height)


def lipm_zmp(t: np.ndarray, com: np.ndarray) -> np.ndarray:
    """LIPM ZMP (N x 2) of a CoM trajectory by central second differences (ends copied).

    ``zmp = c_xy - c_z / g * c''_xy``.
    """
    acc = np.zeros((len(t), 2))
    dt = np.diff(t)
    h0, h1 = dt[:-1], dt[1:]
    c = com[:, :2]
    acc[1:-1] = 2 * ((c[2:] - c[1:-1]) / h1[:, None] - (c[1:-1] - c[:-2]) / h0[:, None]) \
        / (h0 + h1)[:, None]
    acc[0], acc[-1] = acc[1], acc[-2]
    return c - (com[:, 2:3] / GRAVITY) * acc

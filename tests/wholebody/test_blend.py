"""The samples between solver ticks (quadratic B-spline of the ticks' values)."""

from __future__ import annotations

import numpy as np
import pytest

from pivot_ompl.wholebody.blend import blend, blend_quaternions, sample_labels, sample_support


@pytest.mark.parametrize("m", [2, 3, 4])
def test_acceleration_is_the_knots_own(m: int) -> None:
    """Samples' second differences never exceed the knots' (no interpolation overshoot)."""
    rng = np.random.default_rng(0)
    h = 0.01
    knots = np.cumsum(np.cumsum(rng.uniform(-1, 1, (300, 5)), axis=0), axis=0) * h * h
    out = blend(knots, m)
    assert out.shape == (m * (len(knots) - 1) + 1, 5)
    knot_acc = np.abs(np.diff(knots, 2, axis=0)).max(axis=0) / h**2
    # the first and last knots are repeated: inside, away from those ends
    sample_acc = np.abs(np.diff(out[m:-m], 2, axis=0)).max(axis=0) / (h / m) ** 2
    assert np.all(sample_acc <= knot_acc * (1 + 1e-9))
    # speeds are averages of the knots' speeds; values in the knots' range
    knot_v = np.abs(np.diff(knots, axis=0)).max(axis=0) / h
    assert np.all(np.abs(np.diff(out, axis=0)).max(axis=0) / (h / m) <= knot_v * (1 + 1e-9))
    assert np.all(out.min(axis=0) >= knots.min(axis=0) - 1e-12)
    assert np.all(out.max(axis=0) <= knots.max(axis=0) + 1e-12)


@pytest.mark.parametrize("m", [2, 4])
def test_a_parabola_is_kept_up_to_its_offset(m: int) -> None:
    """Knots on a parabola: the samples on it shifted by a h^2 / 8, with its acceleration."""
    h, a = 0.02, 3.0
    tk = np.arange(50) * h
    out = blend((0.5 * a * tk**2)[:, None], m)[:, 0]
    ts = np.arange(len(out)) * h / m
    inner = slice(2 * m, -2 * m)  # away from the clamped ends
    assert np.allclose(out[inner], 0.5 * a * ts[inner] ** 2 + a * h * h / 8, atol=1e-12)
    acc = np.diff(out, 2) / (h / m) ** 2
    assert np.allclose(acc[2 * m:-2 * m], a, atol=1e-6)


def test_one_substep_gives_the_knots() -> None:
    """With one sample a tick the samples are the solver's values."""
    knots = np.random.default_rng(1).normal(size=(20, 3))
    assert np.array_equal(blend(knots, 1), knots)
    assert np.array_equal(sample_support(np.array([0, 1, 0]), 1), [0, 1, 0])


def test_quaternion_signs() -> None:
    """Knots given with alternating signs blend as one rotation path; w >= 0 on request."""
    ang = np.linspace(0.0, 2.0 * np.pi, 40)  # yaw through pi: w changes sign
    q = np.stack([0 * ang, 0 * ang, np.sin(ang / 2), np.cos(ang / 2)], axis=1)
    q[q[:, 3] < 0] *= -1.0  # canonical sign: a jump at yaw = pi
    out = blend_quaternions(q, 2, positive_w=True)
    assert np.allclose(np.linalg.norm(out, axis=1), 1.0)
    assert np.all(out[:, 3] >= 0)
    yaw = np.unwrap(2 * np.arctan2(out[:, 2], out[:, 3]))
    assert np.all(np.diff(yaw) > 0)  # monotonic: no detour through the flipped sign


def test_labels_and_support() -> None:
    """Labels repeat the tick before; a sample between double and single support is single."""
    assert sample_labels(np.array([0, 0, 1]), 2).tolist() == [0, 0, 0, 0, 1]
    assert sample_support(np.array([0, 1, 1, 0, 2]), 2).tolist() == [0, 1, 1, 1, 1, 1, 0, 2, 2]


def test_batch_quaternions_match_the_single_ones() -> None:
    """``quats_xyzw`` (recording, vectorised) equals ``quat_xyzw`` matrix by matrix."""
    from pivot_ompl.wholebody.box import quat_xyzw, quats_xyzw, rot_y, rot_z

    rng = np.random.default_rng(3)
    A = rng.normal(size=(300, 3, 3))
    Rs = [np.linalg.qr(a)[0] * np.sign(np.linalg.det(np.linalg.qr(a)[0])) for a in A]
    Rs += [np.eye(3), rot_z(np.pi), rot_y(np.pi), rot_z(3.0) @ rot_y(-0.087)]
    q = quats_xyzw(np.array(Rs))
    ref = np.array([quat_xyzw(R) for R in Rs])
    assert np.all(q[:, 3] >= 0)
    assert np.allclose(np.minimum(np.abs(q - ref).max(1), np.abs(q + ref).max(1)), 0,
                       atol=1e-12)

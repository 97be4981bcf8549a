"""hipsim.physics.orientation pinned by hand: R, T(q), Ṫ and σ_min/σ_max at angles whose sines are known.

Each expected value is written out from the spec's formulas (§2, §3) at
angles of 30°, 60° and 90°, or built another way (the product of the three
elementary rotations; a matrix made from chosen singular values).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hipsim.physics import orientation

R3 = np.sqrt(3.0)


def elementary(axis, angle):
    """The rotation about one coordinate axis, written out."""
    c, s = np.cos(angle), np.sin(angle)
    if axis == "x":
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == "y":
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_rotation_about_each_axis_by_a_quarter_turn():
    q = np.array([[np.pi / 2, 0.0, 0.0], [0.0, np.pi / 2, 0.0], [0.0, 0.0, np.pi / 2]])
    R = orientation.rotation_matrix(q)
    assert R.shape == (3, 3, 3)
    # Rx(90°): y → z, z → −y.
    np.testing.assert_allclose(R[0], [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-15)
    # Ry(90°): z → x, x → −z.
    np.testing.assert_allclose(R[1], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-15)
    # Rz(90°): x → y, y → −x.
    np.testing.assert_allclose(R[2], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_rotation_is_z_then_y_then_x_in_that_product_order():
    q = np.array([[0.3, -0.7, 1.1], [-1.2, 0.4, -2.5]])
    expected = [elementary("z", g) @ elementary("y", b) @ elementary("x", a) for a, b, g in q]
    np.testing.assert_allclose(orientation.rotation_matrix(q), expected, atol=1e-14)
    # The components-first form: (3, 3, N) from cosines and sines (3, N).
    components = orientation.rotation_matrix_components(np.cos(q.T), np.sin(q.T))
    np.testing.assert_allclose(np.moveaxis(components, -1, 0), expected, atol=1e-14)


def test_angular_velocity_map_at_sixty_and_thirty_degrees():
    # β = 60°, γ = 30°: cβ = 1/2, sβ = √3/2, cγ = √3/2, sγ = 1/2; α does not enter T.
    # T = [[cβcγ, −sγ, 0], [cβsγ, cγ, 0], [−sβ, 0, 1]] (spec §2, ω = T·q̇).
    T = orientation.angular_velocity_map(np.array([[0.9, np.pi / 3, np.pi / 6]]))
    expected = [[R3 / 4, -0.5, 0.0], [0.25, R3 / 2, 0.0], [-R3 / 2, 0.0, 1.0]]
    np.testing.assert_allclose(T[0], expected, atol=1e-15)


def test_angular_velocity_map_rate_by_hand():
    # d/dt of each entry of T at β = 60°, γ = 30°, with β̇ = 2, γ̇ = 3 (α̇ = 5 does not enter):
    #   d(cβcγ) = −sβcγ·β̇ − cβsγ·γ̇ = −(3/4)·2 − (1/4)·3 = −2.25
    #   d(−sγ)  = −cγ·γ̇ = −(√3/2)·3
    #   d(cβsγ) = −sβsγ·β̇ + cβcγ·γ̇ = −(√3/4)·2 + (√3/4)·3 = √3/4
    #   d(cγ)   = −sγ·γ̇ = −1.5
    #   d(−sβ)  = −cβ·β̇ = −1
    Td = orientation.angular_velocity_map_rate(np.array([[0.9, np.pi / 3, np.pi / 6]]), np.array([[5.0, 2.0, 3.0]]))
    expected = [[-2.25, -1.5 * R3, 0.0], [R3 / 4, -1.5, 0.0], [-1.0, 0.0, 0.0]]
    np.testing.assert_allclose(Td[0], expected, atol=1e-14)


@pytest.mark.parametrize("singular_values", [(4.0, 2.0, 1.0), (1.0, 4.0, 2.0), (2.0, 1.0, 4.0), (3.0, 3.0, 0.75)])
def test_inverse_condition_number_of_a_diagonal_matrix(singular_values):
    # σ_min/σ_max = 1/4 whatever the order on the diagonal.
    J = np.diag(singular_values)
    assert orientation.inverse_condition_number(J) == pytest.approx(0.25, rel=1e-12)


def test_inverse_condition_number_of_rotated_matrices():
    # J = U·diag(σ)·Vᵀ with rotations U, V has the singular values σ: σ_min/σ_max = 0.5/3 = 1/6,
    # then 2/5 and, with equal extremes around a middle one, 1 (an isotropic J).
    U = elementary("z", 0.4) @ elementary("x", -1.1)
    V = elementary("y", 0.7) @ elementary("z", 2.0)
    J = np.array([U @ np.diag(s) @ V.T for s in [(3.0, 1.2, 0.5), (2.0, 5.0, 3.0), (1.7, 1.7, 1.7)]])
    np.testing.assert_allclose(orientation.inverse_condition_number(J), [1 / 6, 2 / 5, 1.0], rtol=1e-10)


@pytest.mark.parametrize(("singular_values", "expected"), [((2.0, 2.0, 1.0), 0.5), ((2.0, 1.0, 1.0), 0.5)])
def test_inverse_condition_number_with_a_repeated_singular_value(singular_values, expected):
    # Two equal singular values put cos 3φ = det(B)/2 at exactly −1 or +1, where round-off may
    # step past ±1: the ratio must stay 1/2 (no NaN) under any rotation.
    rng = np.random.default_rng(5)
    for angles in rng.uniform(-np.pi, np.pi, (40, 4)):
        U = elementary("z", angles[0]) @ elementary("x", angles[1])
        V = elementary("y", angles[2]) @ elementary("z", angles[3])
        J = U @ np.diag(singular_values) @ V.T
        assert orientation.inverse_condition_number(J) == pytest.approx(expected, rel=1e-7)


def test_inverse_condition_number_of_small_and_isotropic_matrices_quietly():
    # Small singular values (JᵀJ's spread below 1): 0.1/0.4 = 1/4. An isotropic J (2·I: spread exactly
    # 0) is 1, with no warning from the 0/0 it meets on the way; a NaN J is NaN, also quietly.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert orientation.inverse_condition_number(np.diag([0.1, 0.2, 0.4])) == pytest.approx(0.25, rel=1e-12)
        assert orientation.inverse_condition_number(2.0 * np.eye(3)) == 1.0
        assert np.isnan(orientation.inverse_condition_number(np.full((3, 3), np.nan)))
        singular = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
        assert orientation.inverse_condition_number(singular) == 0.0


def test_inverse_condition_number_of_a_singular_a_nan_and_a_batch():
    # Rank 2: σ_min = 0. A NaN matrix gives NaN. Batch shapes stay: (2, 2, 3, 3) → (2, 2).
    singular = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])
    assert orientation.inverse_condition_number(singular) == pytest.approx(0.0, abs=1e-7)
    assert np.isnan(orientation.inverse_condition_number(np.full((3, 3), np.nan)))
    batch = np.broadcast_to(np.diag([2.0, 1.0, 8.0]), (2, 2, 3, 3))
    np.testing.assert_allclose(orientation.inverse_condition_number(batch), np.full((2, 2), 0.125), rtol=1e-12)
    # The components-first form takes J by its rows (xyz, row, ...).
    components = np.moveaxis(batch, (-1, -2), (0, 1))
    np.testing.assert_allclose(orientation.inverse_condition_number_components(components), 0.125, rtol=1e-12)

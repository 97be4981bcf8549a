"""hipsim.analytic.chain_kinematics on a machine written here: the carriage readings at the home attitude by hand
(L = g_z − √(l² − g_x² − g_y²)), a lever too short flagged NaN, J and L̈ against central differences of L."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from hipsim.analytic.chain_kinematics import chain_accelerations, chain_jacobian, chain_positions_per_sample

#: Platform joints r⁰ in platform axes, rotation centre minus U-joint centre o − c, lever lengths l; all in [m].
R0 = np.array([[[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [-0.1, 0.0, 0.0]]])
OFFSETS = np.array([[[0.0, 0.0, 0.3], [0.05, 0.0, 0.2], [0.0, 0.0, 0.25]]])
LEVERS = np.array([[0.5, 0.5, 0.2]])


def positions(p):
    p = np.atleast_2d(np.asarray(p, dtype=float))
    n = len(p)
    return chain_positions_per_sample(np.repeat(R0, n, 0), np.repeat(OFFSETS, n, 0), np.repeat(LEVERS, n, 0), p)


def test_readings_at_home_by_hand():
    L, r, d = positions([0.0, 0.0, 0.0])
    # g = r⁰ + (o − c): (0.1, 0, 0.3), (0.05, 0.1, 0.2), (−0.1, 0, 0.25).
    expected = [0.3 - math.sqrt(0.25 - 0.01), 0.2 - math.sqrt(0.25 - 0.0025 - 0.01), 0.25 - math.sqrt(0.04 - 0.01)]
    assert_allclose(L[0], expected, rtol=1e-15)
    assert_allclose(r[0], R0[0], rtol=0, atol=0)
    assert_allclose(d[0, 1], [0.05, 0.1, math.sqrt(0.2375)], rtol=1e-15)
    assert_allclose(np.linalg.norm(d[0], axis=1), LEVERS[0], rtol=1e-15)  # |d| = l on every leg


def test_a_lever_that_cannot_reach_is_nan():
    n = 1
    short = np.array([[0.5, 0.5, 0.09]])  # leg 3 needs at least |g_xy| = 0.1
    L, _, d = chain_positions_per_sample(R0, OFFSETS, short, np.zeros((n, 3)))
    assert np.isnan(L[0, 2]) and np.isnan(d[0, 2, 2])
    assert np.isfinite(L[0, :2]).all()


def test_the_jacobian_and_accelerations_against_central_differences():
    h = 1e-6
    L, r, d = positions([0.0, 0.0, 0.0])
    J = chain_jacobian(r, d)[0]
    # At the home attitude p = ε·e_k turns about axis k: ω = ε·e_k.
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        column = (positions(step)[0][0] - positions(-step)[0][0]) / (2 * h)
        assert_allclose(J[:, k], column, rtol=1e-8, atol=1e-10)
    # Turning about x at w rad/s from home: L̈ = w²·d²L/dα² (ω constant, ω̇ = 0).
    w, h2 = 2.0, 1e-4
    Ldd = chain_accelerations(r, d, np.array([[w, 0.0, 0.0]]), np.zeros((1, 3)))[0]
    second = (positions([h2, 0, 0])[0][0] - 2 * L[0] + positions([-h2, 0, 0])[0][0]) / h2**2
    assert_allclose(Ldd, w**2 * second, rtol=1e-5, atol=1e-8)
    # ω̇ adds J·ω̇.
    both = chain_accelerations(r, d, np.array([[w, 0.0, 0.0]]), np.array([[0.0, 3.0, 0.0]]))[0]
    assert_allclose(both - Ldd, J[:, 1] * 3.0, rtol=1e-12)

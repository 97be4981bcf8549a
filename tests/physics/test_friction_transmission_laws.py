"""hipsim.physics.friction, .transmission, .units and the array helpers of .vectors, pinned by hand.

The friction numbers use 3-4-5 and 5-12-13 triangles so that the smooth sign
ŝ(w) = w/√(|w|² + ε²) (spec §7.3) comes out in fractions; the central chain's
moment is spec §4.3 written out: r_h·μ_h·|F_e| + r_t·μ_t·|F_e + m_m·g| along ŝ(ω).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError
from hipsim.machine.parameter_set import Friction
from hipsim.physics import friction, laws, transmission, units, vectors


def coefficients(**changes):
    values: dict[str, Any] = dict(
        epsilon=12.0,
        hip_radius=0.02,
        hip_mu=0.1,
        thrust_radius=0.05,
        thrust_mu=0.2,
        screw_coulomb=0.0,
        screw_viscous=0.0,
        guide_coulomb=0.0,
        guide_viscous=0.0,
        ujoint_coulomb=0.0,
        ujoint_viscous=0.0,
        sjoint_coulomb=0.0,
        sjoint_viscous=0.0,
    )
    values.update(changes)
    return Friction(**values)


def test_smooth_sign_of_speeds_and_of_a_vector():
    # Scalar: ŝ(3) with ε = 4 is 3/5, ŝ(−5) with ε = 12 is −5/13.
    np.testing.assert_allclose(friction.smooth_sign(np.array([3.0]), 4.0), [0.6])
    np.testing.assert_allclose(friction.smooth_sign(np.array([-5.0]), 12.0), np.array([-5 / 13]))
    # Vector: w = (3, 4, 0), |w|² = 25, ε = 12: √(25 + 144) = 13, so ŝ = (3, 4, 0)/13; last axis xyz.
    w = np.array([[3.0, 4.0, 0.0], [0.0, 0.0, -5.0]])
    np.testing.assert_allclose(friction.smooth_sign(w, 12.0, vector=True), [[3 / 13, 4 / 13, 0.0], [0, 0, -5 / 13]])
    # Any leading shape: (2, 2, 3), the vector still along the last axis.
    w3 = np.stack([w, w[::-1]])
    expected = [[[3 / 13, 4 / 13, 0.0], [0, 0, -5 / 13]], [[0, 0, -5 / 13], [3 / 13, 4 / 13, 0.0]]]
    np.testing.assert_allclose(friction.smooth_sign(w3, 12.0, vector=True), expected)


def test_central_chain_friction_of_the_publication_form():
    # F_e = 100 N, weight 30 N: hip 0.02·0.1·100 = 0.2 N·m, thrust 0.05·0.2·130 = 1.3 N·m;
    # ω = (5, 0, 0) with ε = 12: ŝ = (5/13, 0, 0); τ = 1.5·5/13 along x.
    # A negative load (lifting) enters as |F_e| and |F_e + m·g|: F_e = −100: 0.2 + 0.05·0.2·70 = 0.9.
    omega = np.array([[5.0, 0.0, 0.0], [0.0, -5.0, 0.0]])
    tau = friction.central_chain_friction(coefficients(), 30.0, omega, np.array([100.0, -100.0]))
    np.testing.assert_allclose(tau, [[1.5 * 5 / 13, 0, 0], [0, -0.9 * 5 / 13, 0]], rtol=1e-14)


def test_central_chain_friction_with_an_axial_only_thrust_bearing():
    # The bearing resists only rotation about the platform's z axis: with R = I, z = (0, 0, 1),
    # ω = (3, 0, 4): hip 0.2·ŝ(ω) = 0.2·(3, 0, 4)/13, thrust 1.3·ŝ(ω·z = 4)·z = 1.3·4/√(16 + 144)·z.
    F = coefficients(thrust_bearing_axial_only=True)
    omega = np.array([[3.0, 0.0, 4.0]])
    tau = friction.central_chain_friction(F, 30.0, omega, np.array([100.0]), R=np.eye(3)[None])
    thrust = 1.3 * 4.0 / math.sqrt(160.0)
    np.testing.assert_allclose(tau, [[0.2 * 3 / 13, 0.0, 0.2 * 4 / 13 + thrust]], rtol=1e-14)
    with pytest.raises(
        ArgumentError,
        match=r"^R: expected the platform rotations \(N, 3, 3\): the axial-only thrust bearing's friction needs them, got None$",
    ):
        friction.central_chain_friction(F, 30.0, omega, np.array([100.0]))


def test_friction_record_keeps_switches_and_makes_floats():
    record = laws.friction_record(coefficients(hip_mu=1, thrust_bearing_axial_only=True))
    assert type(record.hip_mu) is float and record.hip_mu == 1.0
    assert record.thrust_bearing_axial_only is True


def test_screw_transmission_by_hand():
    # Lead 10 mm: half a lead of travel is half a turn, π rad; the ratio is 2π/0.01 = 200π rad/m.
    assert transmission.angle_from_travel(0.005, 0.01) == pytest.approx(math.pi, rel=1e-15)
    assert transmission.radians_per_travel(0.01) == pytest.approx(200 * math.pi, rel=1e-15)
    assert transmission.travel_per_radian(0.01) == pytest.approx(0.01 / (2 * math.pi), rel=1e-15)
    assert transmission.lead_from_ratio(200 * math.pi) == pytest.approx(0.01, rel=1e-15)
    assert transmission.TWO_PI == pytest.approx(6.283185307179586, rel=1e-15)


def test_rpm_factors():
    # 60 rpm is one turn a second, 2π rad/s.
    assert 60.0 * units.RAD_S_PER_RPM == pytest.approx(2 * math.pi, rel=1e-15)
    assert 2 * math.pi * units.RPM_PER_RAD_S == pytest.approx(60.0, rel=1e-15)


def test_cross_array_broadcasts_either_side():
    # x × y = z; one side per sample (2 samples), the other a single vector: both orders give (3, 2).
    a = (np.array([1.0, 2.0]), np.array([0.0, 0.0]), np.array([0.0, 0.0]))
    y = (0.0, 1.0, 0.0)
    np.testing.assert_allclose(vectors.cross_array(a, y), [[0, 0], [0, 0], [1, 2]])
    np.testing.assert_allclose(vectors.cross_array(y, a), [[0, 0], [0, 0], [-1, -2]])


def test_stack_and_per_leg():
    np.testing.assert_allclose(vectors.stack((1.0, np.array([2.0, 3.0]), 4.0)), [[1, 1], [2, 3], [4, 4]])
    rows = np.arange(9.0).reshape(3, 3)
    legs = vectors.per_leg(rows)
    assert legs.shape == (3, 3, 1)
    assert legs[1, 2, 0] == rows[2, 1]

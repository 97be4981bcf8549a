"""hipsim/stations/sensitivity.py's edges by hand: the 3x3 inverse of singular matrices (inf and NaN, silently), the
shape of both platforms' Jacobian, the random poses' and the structure's default seed, and a definition's coefficient
on its tolerance."""

from __future__ import annotations

import warnings

import numpy as np

from hipsim.analytic.stations import carriages_for_platform
from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations import sensitivity as sensitivity_module
from hipsim.stations.commands import attitudes
from hipsim.stations.sensitivity import (
    POSES,
    Structure,
    attitude_jacobian,
    inverse3,
    platform_attitude_jacobian,
    random_poses,
    structure,
)


def test_a_singular_matrix_inverts_to_inf_and_nan_without_a_warning():
    """diag(1, 1, 0): det 0, so the cofactor 1 of (3, 3) gives 1/0 = inf and the zero cofactors 0/0 = NaN, both
    silently (a singular sample is refused later by name, not warned about here); diag(2, 4, 0.5) by hand."""
    P = np.array([np.diag([1.0, 1.0, 0.0]), np.diag([2.0, 4.0, 0.5])])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inverse = inverse3(P)
    assert np.isinf(inverse[0, 2, 2]) and np.isnan(inverse[0, 0, 0])
    np.testing.assert_array_equal(inverse[1], np.diag([0.5, 0.25, 2.0]))


def test_m_1_away_from_m_2_moves_as_its_own_jacobian_says():
    """Levers 11 and 12 off by 3 and −2 mm and a seat: at the carriages that put m_2 at Q, m_1 stands about 1° away.
    Its ∂q_1/∂δ is taken at its own attitude (the seat's column at m_2's), against central differences of ±1 µm."""
    names = dv.names()
    delta = np.zeros(dv.COUNT)
    for name, value in (("lever_11", 3e-3), ("lever_12", -2e-3), ("spline_x_1", 2e-3), ("spline_z_1", 1e-3)):
        delta[names.index(name)] = value
    params = dv.machine(load_parameters(), delta)
    Q = np.radians(np.array([[10.0, 4.0, -6.0], [-8.0, -3.0, 12.0]]))
    L = carriages_for_platform(params, Q, 2)
    q = attitudes(params, L, np.stack([Q, Q], axis=1))
    assert np.degrees(np.abs(q[:, 0] - Q)).max() > 1.0
    J = platform_attitude_jacobian(params, q[:, 0], 1, Q)
    for name in ("lever_13", "joint_y_12", "spline_y_1"):
        k = names.index(name)

        def moved(step, k=k):
            return attitudes(dv.machine(params, delta + step * (np.arange(dv.COUNT) == k)), L, q)[:, 0]

        column = list(dv.platform_columns(1)).index(k)
        np.testing.assert_allclose(J[:, :, column], (moved(1e-6) - moved(-1e-6)) / 2e-6, rtol=0, atol=1e-7)


def test_both_platforms_jacobian_has_one_row_block_a_platform():
    q = np.radians(np.array([[[5.0, -3.0, 8.0], [-6.0, 4.0, -2.0]]]))
    params = dv.machine(load_parameters(), np.zeros(dv.COUNT))
    assert attitude_jacobian(params, q).shape == (1, 2, 3, dv.COUNT)


def test_the_default_seed_is_zero(monkeypatch):
    assert np.array_equal(random_poses(), random_poses(POSES, 0))
    seeds = []

    def poses(samples, seed=0):
        seeds.append((samples, seed))
        return random_poses(12, seed)  # 12 poses: enough for the rank, cheap

    monkeypatch.setattr(sensitivity_module, "random_poses", poses)
    drawing = load_parameters()
    default, third = structure(drawing, offsets=False), structure(drawing, offsets=False, seed=3)
    assert seeds == [(POSES, 0), (POSES, 3)]
    assert default.rank == third.rank and np.array_equal(default.independent, third.independent)


def test_a_coefficient_on_the_tolerance_is_left_out():
    names = dv.names()
    k = [names.index(n) for n in ("slider_11", "centre_z_1", "centre_x_2")]
    seen = Structure(1, np.array(k[:1]), np.array(k[1:]), np.array([[1e-6, 0.0]]), False)
    assert seen.definitions() == []
    assert seen.definitions(tol=0.0) == ["slider_11 + 1e-06·centre_z_1"]

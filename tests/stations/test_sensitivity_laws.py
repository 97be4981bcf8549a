"""hipsim/stations/sensitivity.py's edges by hand: the 3x3 inverse of singular matrices (inf and NaN, silently), the
shape of both platforms' Jacobian, the random poses' and the structure's default seed, and a definition's coefficient
on its tolerance."""

from __future__ import annotations

import warnings

import numpy as np

from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations import sensitivity as sensitivity_module
from hipsim.stations.sensitivity import POSES, Structure, attitude_jacobian, inverse3, random_poses, structure


def test_a_singular_matrix_inverts_to_inf_and_nan_without_a_warning():
    """diag(1, 1, 0): det 0, so the cofactor 1 of (3, 3) gives 1/0 = inf and the zero cofactors 0/0 = NaN, both
    silently (a singular sample is refused later by name, not warned about here); diag(2, 4, 0.5) by hand."""
    P = np.array([np.diag([1.0, 1.0, 0.0]), np.diag([2.0, 4.0, 0.5])])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inverse = inverse3(P)
    assert np.isinf(inverse[0, 2, 2]) and np.isnan(inverse[0, 0, 0])
    np.testing.assert_array_equal(inverse[1], np.diag([0.5, 0.25, 2.0]))


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

"""The learning law (hipsim.learning.law): what it accepts, its gains, the update and its convergence figures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from learning_synthetic import drive
from stations_synthetic import deviated

from hipsim.exceptions import ArgumentError
from hipsim.learning.law import (
    HARMONIC_FLOOR,
    LearningLaw,
    data_spectral_radius,
    gain_matrices,
    model_spectral_radius,
    update,
)
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations.sensitivity import inverse3, reading_rate


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def desired():
    return iso14242(rate=100.0)


@pytest.fixture(scope="module")
def geometry():
    return deviated(seed=3, size_mm=0.3)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("control", "3"),
        ("weights", (0.0, 0.0)),
        ("weights", (-1.0, 1.0)),
        ("weights", (math.nan, 1.0)),
        ("weights", (1.0, 1.0, 1.0)),
        ("gain", 0.0),
        ("gain", math.inf),
        ("q_cutoff", 0.0),
        ("q_cutoff", math.inf),
        ("drive_lag", -1e-12),
        ("drive_lag", math.nan),
    ],
)
def test_a_law_refuses_a_bad_field_by_its_name(field, value):
    with pytest.raises(ArgumentError, match=field):
        LearningLaw(**{field: value})


def test_a_law_at_the_edges_of_its_ranges():
    law = LearningLaw("both", weights=(0, 1), gain=1e-9, q_cutoff=None, drive_lag=0.0)
    assert law.weights == (0.0, 1.0) and isinstance(law.weights[0], float)
    assert law.platforms == (1, 2)
    assert LearningLaw("1").platforms == (1,) and LearningLaw("2").platforms == (2,)


def test_gain_inverts_the_controlled_platforms_map(drawing, desired, geometry):
    model = drawing.replace(geometry=geometry)
    K = gain_matrices(model, desired.q[:50], LearningLaw("1"))
    A = inverse3(reading_rate(model, desired.q[:50], 1))
    assert np.matmul(K[:, 0], A) == pytest.approx(np.broadcast_to(np.eye(3), (50, 3, 3)), abs=1e-12)
    assert np.all(K[:, 1] == 0.0)


def test_both_on_the_drawing_splits_by_the_weights(drawing, desired):
    K = gain_matrices(drawing, desired.q[:20], LearningLaw("both", weights=(1.0, 3.0)))
    D = reading_rate(drawing, desired.q[:20], 2)  # both platforms alike: K_j = w_j/(w_1 + w_2)·∂L/∂q
    assert K[:, 0] == pytest.approx(0.25 * D, rel=1e-9, abs=1e-15)
    assert K[:, 1] == pytest.approx(0.75 * D, rel=1e-9, abs=1e-15)


def test_model_figure_is_one_minus_the_gain():
    assert model_spectral_radius(LearningLaw(gain=0.5)) == 0.5
    assert model_spectral_radius(LearningLaw(gain=2.5)) == 1.5


def test_update_of_a_constant_error_is_gamma_k_e():
    n = 64
    K = np.zeros((n, 2, 3, 3))
    K[:, 1] = 2.0 * np.eye(3)
    errors = np.full((n, 2, 3), np.nan)
    errors[:, 1] = [0.1, -0.2, 0.3]
    learned = update(np.full((n, 3), 1e-3), errors, K, LearningLaw("2", gain=0.5, drive_lag=0.02), 1.0)
    # Q(0) = 1 and G_m⁻¹(0) = 1: u + γ·K·e = 1e-3 + 0.5·2·e, at every sample
    assert learned == pytest.approx(np.broadcast_to([0.101, -0.199, 0.301], (n, 3)), abs=1e-15)


def test_the_models_lag_makes_the_drive_figure_small():
    n, period = 1000, 1.0
    t = np.arange(n) / n
    commands = np.stack([np.cos(2 * np.pi * k * t) for k in (1, 2, 3)], axis=1)
    encoders = drive(commands, 1.0 / n, lag_s=0.05)  # a discrete lag, stepped: not the law's DFT
    blind, at = data_spectral_radius(commands, encoders, LearningLaw("2"), period)
    # |1 − G| at 3 Hz of a 50 ms lag: ωτ/√(1 + ω²τ²) = 0.686; Q(3 Hz) ≈ 1
    assert blind == pytest.approx(0.686, abs=0.01) and at == 3.0
    known, _ = data_spectral_radius(commands, encoders, LearningLaw("2", drive_lag=0.05), period)
    assert known < 0.02  # what is left: the discrete filter's half-step against the continuous lag


def test_both_with_one_weight_zero_is_that_platforms_own_gain(drawing, desired, geometry):
    model = drawing.replace(geometry=geometry)
    K = gain_matrices(model, desired.q[:10], LearningLaw("both", weights=(1.0, 0.0)))
    assert K[:, 0] == pytest.approx(reading_rate(model, desired.q[:10], 1), rel=1e-9, abs=1e-15)
    assert np.all(K[:, 1] == 0.0)


def test_the_model_figure_is_zero_at_gain_one_and_one_at_gain_two():
    assert model_spectral_radius(LearningLaw(gain=1.0)) == 0.0
    assert model_spectral_radius(LearningLaw(gain=2.0)) == 1.0  # the edge: learning_step refuses it


def test_q_halves_a_correction_at_its_cutoff_and_nan_errors_count_zero():
    n = 64
    t = np.arange(n) / n
    K = np.zeros((n, 2, 3, 3))
    K[:, 1] = np.eye(3)
    K[:, 0] = 7.0 * np.eye(3)  # platform 1's gain is set but its errors are NaN: no contribution
    errors = np.full((n, 2, 3), np.nan)
    errors[:, 1] = np.stack([np.cos(2 * np.pi * 10 * t), 0 * t, 0 * t], axis=1)
    u = update(np.zeros((n, 3)), errors, K, LearningLaw("2", q_cutoff=10.0), 1.0)
    assert u[:, 0] == pytest.approx(0.5 * np.cos(2 * np.pi * 10 * t), abs=1e-14)  # Q(f_c) = 1/2
    assert u[:, 1:] == pytest.approx(np.zeros((n, 2)), abs=1e-15)


def test_the_models_lag_is_inverted_as_a_lead():
    n, tau = 50, 0.03
    t = np.arange(n) / n
    w = 2 * np.pi
    K = np.zeros((n, 2, 3, 3))
    K[:, 0] = np.eye(3)
    errors = np.zeros((n, 2, 3))
    errors[:, 0, 2] = np.sin(w * t)
    u = update(np.zeros((n, 3)), errors, K, LearningLaw("1", q_cutoff=None, drive_lag=tau), 1.0)
    # G_m⁻¹ = 1 + iωτ on sin ωt: sin ωt + ωτ·cos ωt
    assert u[:, 2] == pytest.approx(np.sin(w * t) + w * tau * np.cos(w * t), abs=1e-14)


def test_the_drive_figure_is_not_measurable_without_a_harmonic():
    law = LearningLaw("2")
    two = np.zeros((2, 3))  # two samples: one bin beyond DC, the Nyquist one, which holds no phase
    assert all(math.isnan(x) for x in data_spectral_radius(two, two, law, 1.0))
    constant = np.ones((10, 3))  # only the mean: no harmonic at all
    assert all(math.isnan(x) for x in data_spectral_radius(constant, constant, law, 1.0))


def test_a_harmonic_below_the_floor_is_not_measured():
    n = 101
    t = np.arange(n) / n
    law = LearningLaw("2", q_cutoff=None)

    def figure(weak):
        commands = np.stack([np.cos(2 * np.pi * t) + weak * np.cos(4 * np.pi * t)] * 3, axis=1)
        encoders = np.stack([np.cos(2 * np.pi * t)] * 3, axis=1)  # the drive passes 1 Hz exactly, 2 Hz not at all
        return data_spectral_radius(commands, encoders, law, 1.0)

    # above the floor the 2 Hz harmonic counts: G_d = 0 there, |1 − 0| = 1
    assert figure(1.001 * HARMONIC_FLOOR) == pytest.approx((1.0, 2.0), abs=1e-9)
    # below it only 1 Hz is measured, where G_d = 1: |1 − 1| = 0
    assert figure(0.999 * HARMONIC_FLOOR) == pytest.approx((0.0, 1.0), abs=1e-9)

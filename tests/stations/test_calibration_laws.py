"""hipsim/stations/calibration.py's laws on tiny logs: one value estimated (lever_21, the structure given), logs of the
hand-built machine of tests/stations_synthetic.py with ±0.01° of alternating noise, so the fit lands on the truth; each log's sensor
offsets; the noise over the right count of samples; the confounded offsets' R² and weights by hand; the refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from stations_synthetic import hand_calibration, synthetic_log

from hipsim.exceptions import ArgumentError
from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations.calibration import (
    CONFOUNDED,
    Calibration,
    CalibrationLog,
    calibrate,
    confounded_pairs,
    prediction_errors,
)
from hipsim.stations.sensitivity import Structure, attitude_jacobian

LEVER_21 = dv.names().index("lever_21")
ONE = Structure(1, np.array([LEVER_21]), np.array([dv.names().index("centre_x_2")]), np.array([[0.0]]), False)


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def truth():
    """lever_21 0.3 mm long, all else drawn."""
    x = np.zeros(dv.COUNT)
    x[LEVER_21] = 3e-4
    return ChainGeometry.from_vector(x)


def _log(drawing, truth, name: str, n: int, seed: int, offsets_deg=None, wobble_deg: float = 0.0) -> CalibrationLog:
    t, L, _, sensors = synthetic_log(drawing, truth, n, seed=seed, noise_deg=0.0, offsets_deg=offsets_deg)
    sensors = np.array(sensors)
    # ±0.01° on every angle, ±wobble on m_1's α (no value of m_1 is estimated: nothing fits it); a fit whose residuals
    # are round-off has no noise to stop at.
    sensors += np.radians(0.01) * (-1.0) ** np.arange(n)[:, None, None]
    sensors[:, 0, 0] += np.radians(wobble_deg - 0.01) * (-1.0) ** np.arange(n)
    return CalibrationLog(name, t, L, sensors)


def test_one_value_from_two_logs_and_the_noise_over_every_sample(drawing, truth):
    """m_1 has no estimated value, so its α residual stays the wobble: 0.02° on 60 samples, 0.01° on 40; the noise is
    √((60·0.02² + 40·0.01²)/100)."""
    logs = [_log(drawing, truth, "a", 60, 1, wobble_deg=0.02), _log(drawing, truth, "b", 40, 2, wobble_deg=0.01)]
    fit = calibrate(logs, drawing, structure_of=ONE)
    assert fit.theta[LEVER_21] == pytest.approx(3e-4, abs=1e-7)
    assert np.count_nonzero(fit.theta) == 1 and fit.structure is ONE
    assert fit.theta_std[LEVER_21] < 1e-5 and fit.theta_std[0] == fit.prior == 5e-4
    assert fit.determined[LEVER_21] and np.count_nonzero(fit.determined) == 1
    assert fit.covariance.shape == (1, 1) and fit.covariance[0, 0] == pytest.approx(fit.theta_std[LEVER_21] ** 2)
    assert math.degrees(fit.noise[0, 0]) == pytest.approx(math.sqrt((60 * 0.02**2 + 40 * 0.01**2) / 100), rel=1e-6)
    assert math.degrees(fit.residual_rms[0, 0, 0]) == pytest.approx(0.02, rel=1e-6)
    assert math.degrees(fit.residual_rms[1, 0, 0]) == pytest.approx(0.01, rel=1e-6)
    assert np.degrees(fit.residual_rms[:, 1]) == pytest.approx(np.full((2, 3), 0.01), rel=1e-3)  # m_2 to its noise
    assert fit.start_rms[0, 1].max() > 5 * fit.residual_rms[0, 1].max()  # the drawing missed the lever
    assert fit.logs == ("a", "b") and fit.samples == 100 and 1 < fit.iterations < 10
    assert np.all(fit.offsets == 0.0) and fit.offsets.shape == (2, 2, 3) and fit.confounded == ()
    assert dv.deviation(fit.machine)[LEVER_21] == fit.theta[LEVER_21] and fit.start is drawing
    assert fit.unseen == ["centre_x_2"] and fit.weak == []


@pytest.mark.parametrize(
    ("offsets_deg", "iterations"),
    [(None, 3), ([0.3, -0.2, 0.1, 0.05, 0.4, -0.3], 5)],
)
def test_a_noise_free_log_stops_at_the_absolute_floor_on_the_truth(drawing, truth, offsets_deg, iterations):
    """Noise-free, the posterior spread falls to round-off (~1e-13 m) and no step is 1e-4 of it: the fit stops at
    the first step below 0.1 nm (1e-10 rad an offset). Lever alone: steps ~3e-4, 6e-7, 4e-12 m (quadratic), so the
    third; with offsets: 3e-6, 3e-4, 3e-6, 5e-9 m (offsets 3e-8 rad), 3e-15 m, so the fifth. Both on the truth."""
    t, L, _, sensors = synthetic_log(drawing, truth, 40, seed=1, noise_deg=0.0, offsets_deg=offsets_deg)
    fit = calibrate([CalibrationLog("a", t, L, sensors)], drawing, offsets=offsets_deg is not None, structure_of=ONE)
    assert fit.iterations == iterations
    assert fit.theta[LEVER_21] == pytest.approx(3e-4, abs=1e-14)
    assert np.degrees(fit.offsets).ravel() == pytest.approx(offsets_deg or np.zeros(6), abs=1e-11)
    assert fit.noise.max() <= 3e-11  # round-off, or the noise's floor of 1e-12 rad


def test_each_logs_sensor_offsets(drawing, truth):
    a = [0.3, -0.2, 0.1, 0.05, 0.4, -0.3]
    b = [-0.1, 0.0, 0.2, -0.25, 0.1, 0.15]
    logs = [_log(drawing, truth, "a", 300, 3, offsets_deg=a), _log(drawing, truth, "b", 300, 4, offsets_deg=b)]
    fit = calibrate(logs, drawing, offsets=True, structure_of=ONE)
    assert fit.theta[LEVER_21] == pytest.approx(3e-4, abs=1e-5)
    np.testing.assert_allclose(np.degrees(fit.offsets).reshape(2, 6), [a, b], atol=1e-3)
    _, offsets, _ = prediction_errors(fit.machine, logs[1], True)
    np.testing.assert_allclose(np.degrees(offsets).ravel(), b, atol=1e-3)


def test_a_fixture_pins_a_logs_offsets(drawing, truth):
    """Platform 2 held at a known attitude on ten rows: its offsets are the sensor minus the known attitude there."""
    log = _log(drawing, truth, "a", 50, 5, offsets_deg=[0.0, 0.0, 0.0, 0.2, -0.1, 0.3])
    known = np.full((50, 2, 3), np.nan)
    true = np.array(log.sensors) - np.radians([0.0, 0.0, 0.0, 0.2, -0.1, 0.3]).reshape(2, 3)  # the wobble kept
    known[:10, 1] = true[:10, 1]
    fixture = CalibrationLog("a", log.t, log.carriages, log.sensors, known)
    fit = calibrate([fixture], drawing, offsets=True, structure_of=ONE)
    np.testing.assert_allclose(np.degrees(fit.offsets[0, 1]), [0.2, -0.1, 0.3], atol=1e-3)


def test_confounded_offsets_by_hand():
    """Two values (variances 1 and 4) and six offsets: α_1 covaries 0.6 and 1.6 with them (R² = 0.36 + 0.64 = 1:
    weights 0.6 and 0.8, scaled 0.75 and 1); β_1 R² exactly 0.9, 3²/10 (confounded); γ_1 0.81 (not); the others none."""
    p = 2
    S = np.eye(8)
    S[0, 0], S[1, 1] = 1.0, 4.0
    S[2, :2] = S[:2, 2] = [0.6, 1.6]
    S[3, 3], S[3, :2], S[:2, 3] = 10.0, [3.0, 0.0], [3.0, 0.0]  # 9/10
    S[4, :2] = S[:2, 4] = [0.9, 0.0]
    S[7, :2] = S[:2, 7] = [0.0, -2 * math.sqrt(0.95)]  # γ_2: weight −1 alone
    names = dv.names()
    independent = np.array([names.index("lever_11"), names.index("joint_x_12")])
    found = confounded_pairs(S, independent, p)
    assert [c.sensor for c in found] == ["alpha_1", "beta_1", "gamma_2"]
    alpha, beta, gamma = found
    assert alpha.explained == pytest.approx(1.0) and alpha.values == ("joint_x_12", "lever_11")
    assert alpha.weights == (1.0, 0.75)
    assert beta.explained == pytest.approx(CONFOUNDED) and beta.values == ("lever_11",) and beta.weights == (1.0,)
    assert gamma.values == ("joint_x_12",) and gamma.weights == (-1.0,) and gamma.explained == pytest.approx(0.95)
    assert alpha.to_json() == {
        "sensor": "alpha_1",
        "explained": pytest.approx(1.0),
        "values": ["joint_x_12", "lever_11"],
        "weights": [1.0, 0.75],
        "separated_by": alpha.separated_by,
    }


def test_a_value_under_a_quarter_of_the_largest_weight_is_not_named():
    S = np.eye(8)
    S[2, :2] = S[:2, 2] = [0.96, 0.24]  # weights 0.96 and 0.24: 1 and 0.25 scaled
    (found,) = confounded_pairs(S, np.array([0, 1]), 2)
    assert found.weights == (1.0, 0.25)
    S[2, :2] = S[:2, 2] = [0.96, 0.2399]
    (found,) = confounded_pairs(S, np.array([0, 1]), 2)
    assert found.weights == (1.0,)


def test_no_log_or_no_prior_is_refused(drawing, truth):
    with pytest.raises(ArgumentError, match=r"logs: expected at least one calibration log, got \[\]"):
        calibrate([], drawing)
    log = _log(drawing, truth, "a", 20, 6)
    for prior in (0.0, -1e-3, math.nan, math.inf):
        with pytest.raises(ArgumentError, match="prior: expected a positive standard deviation in m"):
            calibrate([log], drawing, prior=prior, structure_of=ONE)


def test_the_predictions_spread_by_hand(drawing):
    """lever_11 estimated (σ = 0.1 mm), lever_12 folded into it by c = 0.5 and kept at its prior (0.5 mm): the spread
    is √(J₁₁²σ² + prior²·(J₁₂ − c·J₁₁)²) per angle; about its mean over the samples with ``up_to_constant``."""
    names = dv.names()
    k11, k12 = names.index("lever_11"), names.index("lever_12")
    seen = Structure(1, np.array([k11]), np.array([k12]), np.array([[0.5]]), False)
    base = hand_calibration()
    calibration = Calibration(**{**base.__dict__, "structure": seen, "covariance": np.array([[1e-8]])})
    q = np.radians(np.array([[[10.0, 4.0, -6.0]] * 2, [[-5.0, 2.0, 8.0]] * 2]))
    J = attitude_jacobian(calibration.machine, q)
    a, b = J[..., k11], J[..., k12]
    expected = np.sqrt(a**2 * 1e-8 + 25e-8 * (b - 0.5 * a) ** 2)
    np.testing.assert_allclose(calibration.prediction_std(q), expected, rtol=1e-12)
    a0, b0 = a - a.mean(axis=0), b - b.mean(axis=0)
    centred = np.sqrt(a0**2 * 1e-8 + 25e-8 * (b0 - 0.5 * a0) ** 2)
    np.testing.assert_allclose(calibration.prediction_std(q, up_to_constant=True), centred, rtol=1e-9, atol=1e-18)
    assert base.weak == ["lever_21"] and base.unseen == ["centre_x_1"]


@pytest.mark.parametrize(
    ("shapes", "message"),
    [
        ({"carriages": (2, 2), "sensors": (2, 2, 3)}, "carriages: expected shape (2, 3), got shape (2, 2)"),
        ({"carriages": (2, 3), "sensors": (2, 3)}, "sensors: expected shape (2, 2, 3), got shape (2, 3)"),
        (
            {"carriages": (2, 3), "sensors": (2, 2, 3), "known": (2, 3)},
            "known: expected shape (2, 2, 3), got shape (2, 3)",
        ),
    ],
)
def test_a_log_of_the_wrong_shape_is_refused_by_name(shapes, message):
    """Two samples: carriages (2, 3), each platform's attitude (2, 2, 3); the array named with its shape and the one expected."""
    with pytest.raises(ArgumentError) as error:
        CalibrationLog("a.csv", np.zeros(2), **{key: np.zeros(shape) for key, shape in shapes.items()})
    assert str(error.value) == message

"""hipsim/stations/calibration_check.py: the gates on a calibration written by hand (no fit): each sensor's difference
noise by hand and its floor, the residual gate at 3 times the noise, the chains' moves at 5 prior standard deviations,
held-out logs, and the slip of a column named on a log of the drawing's own attitudes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from stations_synthetic import LEVER_11, LEVER_21, hand_calibration

from hipsim.analytic.stations import carriages_for_platform
from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations.calibration import Calibration, CalibrationLog
from hipsim.stations.calibration_check import SENSOR_COLUMNS, SENSOR_FLOOR_DEG, check_calibration, sensor_noise

#: The difference noise of ±a alternating: its fourth differences are ±16a, so 1.4826·16a/√70.
ALTERNATING = 1.4826 * 16 / math.sqrt(70)


def _log(name: str = "log.csv", n: int = 40, sensors=None) -> CalibrationLog:
    """The drawing's carriages along a slow motion and both sensors reading it exactly (or ``sensors``)."""
    t = np.arange(n) * 0.01
    q = np.radians(np.stack([5 * np.sin(t), 3 * np.cos(2 * t) - 3, 4 * np.sin(3 * t)], axis=1))
    L = carriages_for_platform(load_parameters(), q, 2)
    return CalibrationLog(name, t, L, np.stack([q, q], axis=1) if sensors is None else sensors)


def test_the_noise_of_each_sensor_by_hand_and_its_floor():
    sensors = np.zeros((8, 2, 3))
    sensors[:, 0, 1] = np.radians(0.01) * (-1.0) ** np.arange(8)  # ±0.01°
    sensors[:, 1, 2] = np.radians(1.0) * (-1.0) ** np.arange(8)  # ±1°
    sensors[:, 1, 0] = np.radians(2.0 + 0.5 * np.arange(8))  # a ramp: no noise
    noise = sensor_noise(CalibrationLog("n", np.arange(8.0), np.zeros((8, 3)), sensors))
    assert noise == pytest.approx(
        [SENSOR_FLOOR_DEG, 0.01 * ALTERNATING, SENSOR_FLOOR_DEG, SENSOR_FLOOR_DEG, SENSOR_FLOOR_DEG, ALTERNATING]
    )
    short = sensor_noise(CalibrationLog("s", np.arange(4.0), np.zeros((4, 3)), np.ones((4, 2, 3))))
    assert short == pytest.approx([SENSOR_FLOOR_DEG] * 6)  # too few samples to tell: the floor
    assert SENSOR_COLUMNS == ("alpha_1", "beta_1", "gamma_1", "alpha_2", "beta_2", "gamma_2")


def _with(calibration: Calibration, **changes) -> Calibration:
    return Calibration(**{**calibration.__dict__, **changes})


def test_a_plausible_calibration_has_no_findings():
    """Residuals of 0.015° against the floor's 0.005°: exactly 3 times, which passes; moves of 0.4σ and 0.1σ."""
    log = _log()
    residual = np.radians(np.full((1, 2, 3), 3 * SENSOR_FLOOR_DEG))
    check = check_calibration(_with(hand_calibration(), residual_rms=residual), [log])
    assert check.fit == "calibrate" and check.findings == ()


def test_residuals_beyond_three_times_the_noise_are_named_per_log():
    log, other = _log("a.csv"), _log("b.csv")
    residual = np.radians(np.full((2, 2, 3), 3 * SENSOR_FLOOR_DEG))
    residual[1, 1, 2] = np.radians(0.0155)  # 3.1 times
    check = check_calibration(_with(hand_calibration(), residual_rms=residual), [log, other])
    assert check.findings == ("b.csv: residuals beyond 3 times the noise: gamma_2 0.0155 ° (3.1×)",)


def test_chains_moved_beyond_five_prior_deviations():
    """lever_11 moved 2.5 mm (5σ: passes), lever_21 −2.6 mm (5.2σ) from the start's zero, prior 0.5 mm."""
    calibration = hand_calibration()
    theta = np.array(calibration.theta)
    theta[LEVER_11], theta[LEVER_21] = 2.5e-3, -2.6e-3
    residual = np.zeros((1, 2, 3))
    check = check_calibration(_with(calibration, theta=theta, residual_rms=residual), [_log()])
    assert check.findings == (
        "per-chain values beyond 5 prior standard deviations: lever_21 -2.6 mm (5.2σ): they absorb something else "
        "(a sensor offset or column?)",
    )


def test_held_out_logs_are_held_to_their_own_noise():
    calibration = _with(hand_calibration(), residual_rms=np.zeros((1, 2, 3)))
    held = [_log("h1.csv"), _log("h2.csv")]
    rms = [np.zeros((2, 3)), np.radians(np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0]]))]
    check = check_calibration(calibration, [_log()], held, rms)
    assert check.findings == (
        "held-out h2.csv is not predicted: residuals beyond 3 times the noise: alpha_2 0.02 ° (4×)",
    )


def test_a_sign_the_fit_absorbs_is_named_and_a_bad_residual_gets_its_cause():
    log = _log()
    flipped = np.array(log.sensors)
    flipped[:, 0, 2] *= -1.0  # gamma_1 logged with its sign flipped
    slipped = CalibrationLog("slip.csv", log.t, log.carriages, flipped)
    quiet = _with(hand_calibration(), residual_rms=np.zeros((1, 2, 3)))
    (finding,) = check_calibration(quiet, [slipped]).findings
    assert (
        finding
        == "slip.csv: the fit absorbs a slip of the columns (likely cause in slip.csv: column gamma_1 looks sign-flipped)"
    )
    loud = _with(hand_calibration(), residual_rms=np.radians(np.full((1, 2, 3), 1.0)))
    (finding,) = check_calibration(loud, [slipped]).findings
    assert finding.startswith("slip.csv: residuals beyond 3 times the noise: alpha_1 1 ° (200×)")
    assert finding.endswith(" (likely cause in slip.csv: column gamma_1 looks sign-flipped)")
    theta = np.array(quiet.theta)
    theta[LEVER_11] = 5e-3
    (_, moved) = check_calibration(_with(quiet, theta=theta), [slipped]).findings
    assert moved.endswith("they absorb something else (likely cause in slip.csv: column gamma_1 looks sign-flipped)")


def test_a_log_the_start_cannot_reach_names_no_cause():
    log = _log()
    far = CalibrationLog("far.csv", log.t, log.carriages + 0.5, log.sensors)
    loud = _with(hand_calibration(), residual_rms=np.radians(np.full((1, 2, 3), 1.0)))
    (finding,) = check_calibration(loud, [far]).findings
    assert finding.endswith("(200×)")  # the prediction fails: no likely cause to add


def _slipped(name: str, change) -> CalibrationLog:
    log = _log(name)
    sensors = np.array(log.sensors)
    change(sensors)
    return CalibrationLog(name, log.t, log.carriages, sensors)


def _swap(s: np.ndarray) -> None:
    s[:, 0, [0, 1]] = s[:, 0, [1, 0]]


def _offset(s: np.ndarray) -> None:
    s[:, 0, 0] += np.radians(3.0)


def test_a_swap_is_looked_for_whatever_the_residual_but_an_offset_only_when_it_is_loud():
    quiet = _with(hand_calibration(), residual_rms=np.zeros((1, 2, 3)))
    (finding,) = check_calibration(quiet, [_slipped("swap.csv", _swap)]).findings
    assert (
        finding
        == "swap.csv: the fit absorbs a slip of the columns (likely cause in swap.csv: columns alpha_1 and beta_1 look swapped)"
    )
    assert check_calibration(quiet, [_slipped("zero.csv", _offset)]).findings == ()  # a zero the chains may mimic
    loud = _with(hand_calibration(), residual_rms=np.radians(np.full((1, 2, 3), 1.0)))
    (finding,) = check_calibration(loud, [_slipped("zero.csv", _offset)]).findings
    assert finding.endswith("(likely cause in zero.csv: column alpha_1 looks offset by +3 ° (a zero?))")


def test_moves_are_from_the_start_and_the_cause_from_the_first_log():
    """The start has lever_11 at 3 mm: 3.2 mm is 0.4σ from it; lever_21 moved 2.6 mm (5.2σ) from its zero. The first
    log is clean, the second slipped: the cause is looked for in the first alone."""
    delta = np.zeros(dv.COUNT)
    delta[LEVER_11] = 3e-3
    base = hand_calibration()
    start = dv.machine(base.start, delta)
    theta = np.array(delta)
    theta[LEVER_11], theta[LEVER_21] = 3.2e-3, 2.6e-3
    calibration = _with(base, start=start, theta=theta, residual_rms=np.zeros((2, 2, 3)))
    logs = [_log("clean.csv"), _slipped("slip.csv", _offset)]
    findings = check_calibration(calibration, logs).findings
    assert findings[-1] == (
        "per-chain values beyond 5 prior standard deviations: lever_21 +2.6 mm (5.2σ): they absorb something else "
        "(a sensor offset or column?)"
    )

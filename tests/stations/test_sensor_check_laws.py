"""hipsim/stations/sensor_check.py by hand: each entry at its platform and angle, the covariance a calibrated file
records (its estimated values' block, or its standard deviations when it has no block, none for a table of the wrong
length), and the spread RMS over the samples."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.machine.chains import ChainGeometry
from hipsim.machine.parameters import load_parameters
from hipsim.stations.sensor_check import calibration_covariance, compare_sensors, prediction_std

NAMES = ChainGeometry.names()


def test_each_entry_is_its_platform_and_angle():
    """Measured − predicted is 10·platform + angle index (degrees): entry (j, a) must read exactly that."""
    t = np.array([0.0, 0.5])
    measured = np.radians(np.array([[[0.0, 1.0, 2.0], [10.0, 11.0, 12.0]]] * 2))
    comparison = compare_sensors(load_parameters(), t, np.zeros((2, 2, 3)), measured, uncertainty="ignored")
    for j in (1, 2):
        for k, angle in enumerate(("alpha", "beta", "gamma")):
            entry = comparison.entry(j, angle)
            assert (entry.platform, entry.angle) == (j, angle)
            assert entry.mean_deg == pytest.approx(10 * (j - 1) + k) and entry.peak_at_s == 0.0
    assert comparison.samples == 2 and comparison.uncertainty == "none"


def test_the_covariance_a_file_records():
    estimated = {"kind": "kinematic calibration", "estimated": ["lever_21"], "std_mm": [0.1] * len(NAMES)}
    fallback = calibration_covariance(estimated)  # no block: the standard deviations, independent
    assert fallback is not None and np.diag(fallback) == pytest.approx(np.full(len(NAMES), 1e-8))
    assert calibration_covariance({"kind": "kinematic calibration", "std_mm": [0.1]}) is None
    assert calibration_covariance({"kind": "kinematic calibration", "covariance_mm2": [[1.0]], "std_mm": "0.1"}) is None
    block = calibration_covariance(
        {"kind": "kinematic calibration", "estimated": ["lever_21", "slider_12"], "covariance_mm2": [[4, 1], [1, 9]]}
    )
    assert block is not None and block.shape == (len(NAMES), len(NAMES))
    i, k = NAMES.index("lever_21"), NAMES.index("slider_12")
    assert (block[i, i], block[i, k], block[k, k]) == pytest.approx((4e-6, 1e-6, 9e-6))
    assert np.count_nonzero(block) == 4


def test_the_spread_is_the_rms_over_the_samples():
    """One value uncertain: the spread at two poses, then its RMS over them."""
    params = load_parameters()
    q = np.radians(np.array([[[10.0, 4.0, -6.0]] * 2, [[-5.0, 2.0, 8.0]] * 2]))
    covariance = np.zeros((len(NAMES), len(NAMES)))
    k = NAMES.index("lever_12")
    covariance[k, k] = 1e-8

    std = np.degrees(prediction_std(params, q, covariance))
    comparison = compare_sensors(params, np.array([0.0, 1.0]), q, q, covariance, "calibrated.toml")
    assert comparison.uncertainty == "calibrated.toml"
    assert comparison.entry(1, "beta").prediction_std_deg == pytest.approx(np.sqrt(np.mean(std[:, 0, 1] ** 2)))
    assert comparison.entry(2, "beta").prediction_std_deg == 0.0  # lever_12 does not move m_2


def test_a_covariance_given_without_its_origin_is_named_so():
    """No uncertain value: a spread of exactly 0 on every entry (not None: the prediction carries one)."""
    q = np.zeros((2, 2, 3))
    comparison = compare_sensors(load_parameters(), np.array([0.0, 1.0]), q, q, np.zeros((len(NAMES), len(NAMES))))
    assert comparison.uncertainty == "the covariance given"
    assert [entry.prediction_std_deg for entry in comparison.entries] == [0.0] * 6

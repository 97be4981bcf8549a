"""hipsim.rig.logs.smoothing: the zero-phase low-pass of measured signals, and the smoothed motion's derivatives."""

import math

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.rig.logs.smoothing import edge_samples, lowpass, minimum_samples, smooth_motion


def test_the_low_pass_has_no_delay_and_cuts_noise():
    rate, cutoff = 1000.0, 20.0
    t = np.arange(4000) / rate
    signal = np.sin(2 * np.pi * 2.0 * t)  # 2 Hz: well inside the band
    noise = np.random.default_rng(0).normal(0, 0.1, t.size)
    out = lowpass(signal + noise, rate, cutoff)
    inside = slice(edge_samples(rate, cutoff), -edge_samples(rate, cutoff))
    # Zero phase: the filtered clean sine lies on the sine (no shift), to the filter's passband gain.
    clean = lowpass(signal, rate, cutoff)
    assert np.abs(clean[inside] - signal[inside]).max() < 1e-4
    # White noise keeps about (2·cutoff/rate)^½ of its RMS.
    residual = np.std(out[inside] - clean[inside])
    assert 0.1 * math.sqrt(0.5 * 2 * cutoff / rate) < residual < 0.1 * math.sqrt(2 * 2 * cutoff / rate)


def test_too_short_to_filter_and_cutoff_above_nyquist():
    with pytest.raises(TrajectoryError, match=r"too short to filter at 20 Hz: at least \d+"):
        lowpass(np.zeros(minimum_samples(1000.0, 20.0) - 1), 1000.0, 20.0, "short.csv")
    with pytest.raises(TrajectoryError, match="not below the Nyquist frequency 50 Hz"):
        lowpass(np.zeros(1000), 100.0, 60.0)


def test_derivatives_of_the_smoothed_motion():
    t = np.arange(3000) / 1000.0
    w = 2 * np.pi * 1.5
    q = np.column_stack([0.3 * np.sin(w * t), 0.1 * np.cos(w * t), 0.05 * np.sin(2 * w * t)])
    trajectory = smooth_motion(t, q, np.full(t.size, 500.0), 20.0)
    inside = slice(edge_samples(1000.0, 20.0), -edge_samples(1000.0, 20.0))
    qdd = np.column_stack(
        [-0.3 * w**2 * np.sin(w * t), -0.1 * w**2 * np.cos(w * t), -0.05 * 4 * w**2 * np.sin(2 * w * t)]
    )
    assert np.abs(trajectory.qdd[inside] - qdd[inside]).max() < 1e-3 * np.abs(qdd).max()
    np.testing.assert_allclose(trajectory.Fe, 500.0)

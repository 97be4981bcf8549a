"""hipsim.rig.logs.smoothing: the zero-phase low-pass of measured signals, and the smoothed motion's derivatives."""

import math

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.rig.logs.smoothing import edge_samples, lowpass, minimum_samples, reversal_half, smooth_motion


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


# --- smooth_motion's laws on small synthetic signals, by hand -----------------------------------------------------


def test_without_a_filter_a_quintic_is_differentiated_exactly():
    # The interpolating quintic spline reproduces a polynomial of degree 5: its derivatives are exact.
    t = 0.3 + np.arange(12) / 10.0
    p = np.polynomial.Polynomial([0.1, -0.2, 0.3, 0.05, -0.4, 0.2])
    q = np.column_stack([p(t), 2 * p(t), -p(t)])
    trajectory = smooth_motion(t, q, np.full(t.size, -5.0), None, name="poly.csv")
    np.testing.assert_allclose(trajectory.q, q, rtol=0, atol=0)
    np.testing.assert_allclose(trajectory.qd[:, 0], p.deriv(1)(t), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(trajectory.qdd[:, 2], -p.deriv(2)(t), rtol=1e-9, atol=1e-9)
    # No filter: the load as given, negative or not, and the trajectory named as the log.
    np.testing.assert_array_equal(trajectory.Fe, -5.0)
    assert trajectory.name == "poly.csv"
    assert smooth_motion(t, q, np.zeros(t.size), None).name == "log"


def test_the_quintic_splines_response_to_one_sample_shrinks_by_its_root():
    # One angle 1 at sample 30 of 81, else 0: the interpolating quintic spline's rates at the samples alternate in
    # sign and shrink by 0.4305753… a sample, the root of largest modulus below 1 of the quintic's Euler–Frobenius
    # polynomial z⁴ + 26z³ + 66z² + 26z + 1 (a cubic spline's would shrink by 2 − √3 = 0.268).
    root = np.roots([1, 26, 66, 26, 1])
    decay = float(np.max(np.abs(root[np.abs(root) < 1])))
    assert decay == pytest.approx(0.4305753470999737, rel=1e-12)
    t = np.arange(81) / 100.0
    q = np.zeros((81, 3))
    q[30, 0] = 1.0
    qd = smooth_motion(t, q, np.zeros(81), None).qd[:, 0]
    # Away from the sample (the other root, 0.043, has died out) and from the ends.
    ratios = qd[38:55] / qd[37:54]
    np.testing.assert_allclose(ratios, -decay, rtol=1e-6)


def test_six_samples_are_the_fewest_to_differentiate():
    t = np.arange(6) / 10.0
    assert len(smooth_motion(t, np.zeros((6, 3)), np.zeros(6), None)) == 6
    with pytest.raises(TrajectoryError) as refused:
        smooth_motion(t[:5], np.zeros((5, 3)), np.zeros(5), None, name="five.csv")
    assert str(refused.value) == "five.csv: 5 samples; at least 6 are needed to differentiate"


@pytest.mark.parametrize("start", [0.0, 2.0])
def test_a_sine_at_the_cutoff_keeps_half_its_amplitude(start):
    # Forward and backward through an order-4 Butterworth: |H(f)|² = 1/(1 + (f/f_c)⁸), 1/2 at f_c = 10 Hz. The rate
    # is the times' own ((N − 1)/(t_N − t_1) = 100 Hz, whatever the start): a rate 0.25 % off moves the gain 0.5 %.
    # The load, a sine of amplitude 50 N about 20 N at the cutoff too, becomes 20 + 25·sin: negative at times, and
    # a magnitude: cut at 0.
    t = start + np.arange(400) / 100.0
    wave = np.sin(2 * np.pi * 10.0 * t + 0.3)
    q = np.column_stack([wave, 0.5 * wave, np.zeros(400)])
    trajectory = smooth_motion(t, q, 20.0 + 50.0 * wave, 10.0, name="sine.csv")
    inside = slice(150, 250)
    np.testing.assert_allclose(trajectory.q[inside, 0], 0.5 * wave[inside], atol=2e-4)
    np.testing.assert_allclose(trajectory.q[inside, 1], 0.25 * wave[inside], atol=1e-4)
    np.testing.assert_allclose(trajectory.Fe[inside], np.maximum(20.0 + 25.0 * wave[inside], 0.0), atol=1e-2)
    assert trajectory.Fe.min() == 0.0
    # A rate given by the caller is used instead of the times': at 50 Hz the same samples are a 5 Hz sine. The
    # digital Butterworth (bilinear, warped to the cutoff) passes it with 1/(1 + (tan(π·5/50)/tan(π·10/50))⁸) =
    # 0.99840 (its analogue prototype's 1/(1 + 2⁻⁸) = 0.99611 at the ratio 1/2 of the frequencies).
    half = smooth_motion(t, q, np.full(400, 20.0), 10.0, rate=50.0)
    gain = 1.0 / (1.0 + (math.tan(math.pi * 5 / 50) / math.tan(math.pi * 10 / 50)) ** 8)
    np.testing.assert_allclose(half.q[inside, 0], gain * wave[inside], atol=2e-4)


def test_a_log_too_short_to_filter_is_named():
    t = np.arange(20) / 100.0
    with pytest.raises(TrajectoryError, match=r"^short\.csv: 20 samples \(0\.2 s\) are too short to filter at 10 Hz"):
        smooth_motion(t, np.zeros((20, 3)), np.zeros(20), 10.0, name="short.csv")


def test_the_reversal_window_by_hand():
    # 1.5 periods of the cutoff either side: 1 kHz, 20 Hz → 75 samples; 250 Hz, 20 Hz → ⌈18.75⌉ = 19.
    assert reversal_half(1000.0, 20.0) == 75
    assert reversal_half(250.0, 20.0) == 19

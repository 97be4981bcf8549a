"""hipsim.motion.filtering pinned by hand: the filter's gain at and around the cut-off, its edges and its limits.

The digital Butterworth low-pass of order n at cut-off f_c, sampled at f_s
(bilinear transform, pre-warped so that f_c is exact) has the magnitude
|H(f)|² = 1/(1 + (tan(πf/f_s)/tan(πf_c/f_s))^(2n)); run forwards and
backwards its gain is |H(f)|², so 1/2 at the cut-off (−6 dB). Each test
below compares the filtered amplitude of a sine with that formula.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.motion.filtering import (
    EDGE_PERIODS,
    FILTER_ORDER,
    check_cutoff,
    edge_samples,
    filter_halo,
    lowpass,
    lowpass_periodic,
    lowpass_record,
    minimum_samples,
)


def butterworth_gain(f, rate, cutoff, order=4):
    """|H(f)|² of the digital Butterworth low-pass: the forward-backward filter's gain at f [Hz]."""
    ratio = math.tan(math.pi * f / rate) / math.tan(math.pi * cutoff / rate)
    return 1.0 / (1.0 + ratio ** (2 * order))


def amplitude(y, f, rate):
    """The amplitude of the sine of frequency f in y, by least squares on sin and cos."""
    t = np.arange(y.size) / rate
    basis = np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)])
    (a, b), *_ = np.linalg.lstsq(basis, y, rcond=None)
    return math.hypot(a, b)


def test_the_constants():
    assert FILTER_ORDER == 4 and EDGE_PERIODS == 4.0


@pytest.mark.parametrize(("f", "expected"), [(20.0, 0.5), (40.0, None), (10.0, None), (2.0, None)])
def test_the_gain_at_and_around_the_cutoff(f, expected):
    # 1 kHz, cut-off 20 Hz: the gain at 20 Hz is 1/2; at 40 Hz 1/(1 + 2.008⁸) ≈ 1/264; at 10 Hz
    # 1/(1 + 0.498⁸) ≈ 0.9962; at 2 Hz 1 − 1e-8. Measured away from the dropped edges.
    rate, cutoff = 1000.0, 20.0
    t = np.arange(4000) / rate
    y = lowpass(np.sin(2 * np.pi * f * t), rate, cutoff)
    n = edge_samples(rate, cutoff)
    gain = amplitude(y[n:-n], f, rate)
    assert gain == pytest.approx(butterworth_gain(f, rate, cutoff), rel=1e-4, abs=1e-7)
    if expected is not None:
        assert gain == pytest.approx(expected, rel=1e-4)


def test_the_filter_runs_along_the_first_axis_of_many_columns():
    # Two columns, 5 Hz and 30 Hz, through one call: each has its own gain (and a constant passes).
    rate, cutoff = 200.0, 10.0
    t = np.arange(2000) / rate
    x = np.stack([np.sin(2 * np.pi * 5.0 * t), 3.0 + np.sin(2 * np.pi * 30.0 * t)], axis=1)
    y = lowpass(x, rate, cutoff)
    n = edge_samples(rate, cutoff)
    assert amplitude(y[n:-n, 0], 5.0, rate) == pytest.approx(butterworth_gain(5.0, rate, cutoff), rel=1e-4)
    assert amplitude(y[n:-n, 1] - 3.0, 30.0, rate) == pytest.approx(butterworth_gain(30.0, rate, cutoff), rel=1e-3)
    assert np.mean(y[n:-n, 1]) == pytest.approx(3.0, abs=1e-3)


def test_edge_and_minimum_samples_by_hand():
    # Four periods of the cut-off: 4·1000/20 = 200 samples; 4·60/7 = 34.3 → 35 (rounded up).
    assert edge_samples(1000.0, 20.0) == 200
    assert edge_samples(60.0, 7.0) == 35
    # At least both edges and as many again between them: 4 × 200.
    assert minimum_samples(1000.0, 20.0) == 800
    assert minimum_samples(60.0, 7.0) == 140


def test_a_log_too_short_to_filter_and_one_just_long_enough():
    x = np.zeros(799)
    with pytest.raises(TrajectoryError, match="799 samples .* too short to filter at 20 Hz: at least 800"):
        lowpass(x, 1000.0, 20.0, source="run.csv")
    assert lowpass(np.ones(800), 1000.0, 20.0) == pytest.approx(np.ones(800))


@pytest.mark.parametrize("cutoff", [0.0, -3.0, float("nan"), float("inf"), True, "20"])
def test_cutoffs_that_are_not_positive_frequencies(cutoff):
    with pytest.raises(TrajectoryError, match="must be a positive frequency in Hz"):
        check_cutoff(100.0, cutoff, "run.csv")


def test_the_cutoff_must_be_below_the_nyquist_frequency():
    # At 100 Hz the Nyquist frequency is 50 Hz: 50 is refused, 49.9 accepted.
    with pytest.raises(TrajectoryError, match="not below the Nyquist frequency 50 Hz of a 100 Hz log"):
        check_cutoff(100.0, 50.0, None)
    check_cutoff(100.0, 49.9, None)
    check_cutoff(100.0, 3, None)
    check_cutoff(100.0, 0.5, None)  # below 1 Hz is a frequency too


def test_the_filter_halo_is_where_the_impulse_response_falls_below_round_off():
    # Another route to the same response: the filter's second-order sections run on an impulse as
    # their difference equations (transposed direct form II), written out here; the halo is one past
    # the last sample above 2⁻⁵³ of the peak.
    from scipy.signal import butter

    for rate, cutoff in [(1000.0, 20.0), (60.0, 6.0), (100.0, 30.0)]:
        x = np.zeros(4096)
        x[0] = 1.0
        for b0, b1, b2, _, a1, a2 in butter(FILTER_ORDER, cutoff, fs=rate, output="sos"):
            y, z1, z2 = np.zeros_like(x), 0.0, 0.0
            for k, xk in enumerate(x):
                y[k] = b0 * xk + z1
                z1 = b1 * xk - a1 * y[k] + z2
                z2 = b2 * xk - a2 * y[k]
            x = y
        above = np.flatnonzero(np.abs(x) > 2.0**-53 * np.abs(x).max())
        assert filter_halo(rate, cutoff) == above[-1] + 1
    with pytest.raises(TrajectoryError):
        filter_halo(100.0, 60.0)


def test_a_periodic_record_is_filtered_as_an_endless_repetition():
    # Three whole periods of 4 Hz and 12 Hz at 96 Hz: with no edges each is scaled by its gain exactly.
    rate, cutoff = 96.0, 8.0
    t = np.arange(72) / rate
    x = np.sin(2 * np.pi * 4.0 * t) + np.cos(2 * np.pi * 12.0 * t)
    expected = butterworth_gain(4.0, rate, cutoff) * np.sin(2 * np.pi * 4.0 * t) + butterworth_gain(
        12.0, rate, cutoff
    ) * np.cos(2 * np.pi * 12.0 * t)
    np.testing.assert_allclose(lowpass_periodic(x, rate, cutoff), expected, atol=1e-9)
    # lowpass_record with periodic: the last sample repeats the first, and stays equal to it.
    closed = np.append(x, x[0])
    y = lowpass_record(closed, rate, cutoff, periodic=True)
    np.testing.assert_allclose(y[:-1], expected, atol=1e-9)
    assert y[-1] == y[0]
    # Columns along the first axis: each its own periodic signal.
    both = lowpass_periodic(np.stack([x, -2.0 * x], axis=1), rate, cutoff)
    np.testing.assert_allclose(both, np.stack([expected, -2.0 * expected], axis=1), atol=1e-9)
    with pytest.raises(TrajectoryError, match="^loop.csv: .*cutoff"):
        lowpass_periodic(x, rate, 48.0, source="loop.csv")


def test_the_ends_of_an_open_record_carry_its_quadratic_trend():
    # A Butterworth response is maximally flat: Σ h(k)·kᵖ = 0 for p = 1..7, so it passes a quadratic
    # unchanged; the ends, extended along the quadratic, leave only the filter's decayed start (< 1e-4).
    t = np.arange(300) / 60.0
    x = 1.0 + 2.0 * t - 0.5 * t**2
    y = lowpass_record(x, 60.0, 6.0)
    assert y.shape == x.shape
    assert np.abs(y - x).max() < 1e-4
    # Two columns at once: the same per column.
    both = lowpass_record(np.stack([x, -x], axis=1), 60.0, 6.0)
    np.testing.assert_allclose(both[:, 1], -y, atol=1e-12)
    with pytest.raises(TrajectoryError, match="cutoff"):
        lowpass_record(x, 60.0, 30.0)


def refusal(call, *args, **kwargs) -> str:
    """The whole message of the TrajectoryError that ``call`` raises."""
    with pytest.raises(TrajectoryError) as refused:
        call(*args, **kwargs)
    return str(refused.value)


@pytest.mark.parametrize("cutoff", [0.0, -3.0, float("nan"), True, "20"])
def test_a_refused_cutoff_names_the_log_and_the_value(cutoff):
    assert refusal(check_cutoff, 100.0, cutoff, "run.csv") == (
        f"run.csv: the low-pass cutoff must be a positive frequency in Hz, got {cutoff!r}"
    )


def test_a_cutoff_at_the_nyquist_frequency_names_the_log_and_both_frequencies():
    # 200 Hz samples: the Nyquist frequency is 100 Hz; a 100 Hz cutoff is refused, a 99.5 Hz one is not.
    assert refusal(check_cutoff, 200.0, 100.0, "run.csv") == (
        "run.csv: the low-pass cutoff 100 Hz is not below the Nyquist frequency 100 Hz of a 200 Hz log"
    )
    check_cutoff(200.0, 99.5, "run.csv")
    # Each entry point names the record it was given.
    for call in (lowpass, lowpass_periodic, lowpass_record):
        assert refusal(call, np.zeros(900), 200.0, 150.0, source="walk.csv").startswith(
            "walk.csv: the low-pass cutoff 150 Hz is not below"
        )
    assert refusal(lowpass_record, np.zeros(901), 200.0, 0.0, True, "loop.csv").startswith("loop.csv: ")


def test_a_log_too_short_names_itself_its_length_and_what_is_needed():
    # 500 Hz, cut-off 10 Hz: edges of 4·500/10 = 200 samples, so 800 are needed (1.6 s); 300 are 0.6 s.
    assert refusal(lowpass, np.zeros(300), 500.0, 10.0, source="run.csv") == (
        "run.csv: 300 samples (0.6 s) are too short to filter at 10 Hz: at least 800 (1.6 s) are needed, "
        "4/cutoff at each end being dropped"
    )


def test_the_minimum_is_the_filters_own_padding_when_the_edges_are_shorter():
    # Edges of ⌈4·10/40⌉ = 1 sample (a cut-off above the sample rate, which lowpass refuses): four of
    # them are fewer than SciPy's own odd extension, 3·(2·2 sections + 1) = 15 samples, plus one.
    assert edge_samples(10.0, 40.0) == 1
    assert minimum_samples(10.0, 40.0) == 16
    assert minimum_samples(10.0, 10.0) == 16  # edges of 4: 4 × 4 = 16 as well
    assert minimum_samples(100.0, 10.0) == 160


@pytest.mark.parametrize("n", [2, 3, 5, 7])
def test_a_record_of_a_few_samples_gets_an_odd_extension_as_long_as_it_allows(n):
    # Fewer than 8 samples: too few to fit the ends' quadratic, so each end is extended by its odd
    # reflection, n − 1 samples long (the 4/cutoff = 40 samples do not fit), and filtered forwards and
    # backwards: SciPy's sosfiltfilt with padlen n − 1, column by column.
    from scipy.signal import butter, sosfiltfilt

    rate, cutoff = 100.0, 10.0
    x = np.array([0.0, 3.0, -1.0, 2.0, 5.0, 4.0, -2.0])[:n]
    columns = np.stack([x, 2.0 * x[::-1] + 1.0], axis=1)
    sos = butter(4, cutoff, fs=rate, output="sos")
    expected = np.stack([sosfiltfilt(sos, c, padlen=n - 1) for c in columns.T], axis=1)
    np.testing.assert_allclose(lowpass_record(columns, rate, cutoff), expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(lowpass_record(x, rate, cutoff), expected[:, 0], rtol=1e-12, atol=1e-12)


def quadratic(k):
    return 1.0 + 0.5 * k - 0.2 * k**2


@pytest.mark.parametrize("n", [8, 12])
def test_from_eight_samples_on_the_ends_carry_the_quadratic(n):
    # 100 Hz, cut-off 30 Hz: edges of ⌈4·100/30⌉ = 14 samples, so each end is extended by
    # min(14, n − 1) samples. On a quadratic the extension is the quadratic itself (its fit is exact):
    # the record filtered is q(k) for k = −pad … n − 1 + pad, with no further padding.
    from scipy.signal import butter, sosfiltfilt

    rate, cutoff, pad = 100.0, 30.0, min(14, n - 1)
    k = np.arange(n, dtype=float)
    extended = quadratic(np.arange(-pad, n + pad, dtype=float))
    expected = sosfiltfilt(butter(4, cutoff, fs=rate, output="sos"), extended, padlen=0)[pad : pad + n]
    np.testing.assert_allclose(lowpass_record(quadratic(k), rate, cutoff), expected, rtol=1e-9, atol=1e-9)
    both = lowpass_record(np.stack([quadratic(k), -quadratic(k)], axis=1), rate, cutoff)
    np.testing.assert_allclose(both, np.stack([expected, -expected], axis=1), rtol=1e-9, atol=1e-9)


def test_the_ends_quadratic_is_fitted_to_one_period_of_the_cutoff():
    # 100 Hz, cut-off 5 Hz: edges of 80 samples, the quadratic fitted to one period, 100/5 = 20 samples.
    # The record is a quadratic p plus a residual r: a bump in the middle and, on the first and on
    # the last 20 samples, a cubic with no part along 1, j, j² there (so a 20-sample least-squares
    # fit is p exactly; 19 or 21 samples would not be). Each end is then carried on along p, plus
    # the residual reflected oddly about the end sample: x(end + i) = p(end + i) + 2·r(end) − r(end − i).
    from scipy.signal import butter, sosfiltfilt

    rate, cutoff, n, pad = 100.0, 5.0, 200, 80
    j = np.arange(20, dtype=float)
    basis = np.stack([np.ones(20), j, j**2], axis=1)
    cubic = j**3 - basis @ np.linalg.lstsq(basis, j**3, rcond=None)[0]
    cubic *= 0.05 / np.abs(cubic).max()
    k = np.arange(-pad, n + pad, dtype=float)
    p = 2.0 - 0.01 * k + 3e-4 * k**2
    r = np.zeros(n)
    r[20:-20] = np.sin(np.pi * np.arange(1, n - 39) / (n - 39)) ** 2
    r[-20:] += cubic
    r[:20] += cubic[::-1]
    inside = slice(pad, pad + n)
    extended = p.copy()
    extended[inside] += r
    extended[:pad] += 2.0 * r[0] - r[pad:0:-1]  # r(start + i) reflected, i = pad … 1
    extended[pad + n :] += 2.0 * r[-1] - r[-2 : -pad - 2 : -1]  # r(end − i), i = 1 … pad
    expected = sosfiltfilt(butter(4, cutoff, fs=rate, output="sos"), extended, padlen=0)[inside]
    np.testing.assert_allclose(lowpass_record(p[inside] + r, rate, cutoff), expected, rtol=1e-9, atol=1e-9)


def test_a_short_records_ends_follow_the_quadratic_through_its_last_three_samples():
    # 10 samples at 100 Hz, cut-off 30 Hz: each end is extended by min(14, 9) = 9 samples, and a quarter
    # of that is under three, so the quadratic is the one through the last three samples, a, b, c at
    # −2, −1, 0: p(s) = c + s·(c − b) + s·(s + 1)/2·(c − 2b + a) (Newton's differences). Carried on with
    # the odd reflection of what it leaves (it leaves nothing at its own three samples):
    # x(end + i) = p(i) + p(−i) − x(end − i).
    from scipy.signal import butter, sosfiltfilt

    rate, cutoff, n, pad = 100.0, 30.0, 10, 9
    x = (np.arange(n, dtype=float) - 3.0) ** 3 / 50.0

    def after(y):
        a, b, c = y[-3:]
        i = np.arange(1, pad + 1, dtype=float)

        def p(s):
            return c + s * (c - b) + s * (s + 1) / 2 * (c - 2 * b + a)

        return p(i) + p(-i) - y[-1 - np.arange(1, pad + 1)]

    extended = np.concatenate([after(x[::-1])[::-1], x, after(x)])
    expected = sosfiltfilt(butter(4, cutoff, fs=rate, output="sos"), extended, padlen=0)[pad : pad + n]
    np.testing.assert_allclose(lowpass_record(x, rate, cutoff), expected, rtol=1e-9, atol=1e-9)

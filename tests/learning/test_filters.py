"""The periodic filters of one cycle (hipsim.learning.filters): Q, the drive's lag, derivatives, all by the DFT."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError
from hipsim.learning.filters import apply_response, frequencies, lag_response, periodic_derivatives, q_response


def test_the_bins_of_a_period_are_multiples_of_its_frequency():
    assert frequencies(8, 2.0) == pytest.approx([0.0, 0.5, 1.0, 1.5, 2.0])  # n//2 + 1 bins, 1/T apart
    assert frequencies(7, 0.5) == pytest.approx([0.0, 2.0, 4.0, 6.0])


def test_q_is_a_fourth_order_butterworth_forwards_and_backwards():
    f = np.array([0.0, 10.0, 20.0, 5.0])
    # 1/(1 + (f/fc)^8): 1, 1/2 at the cutoff, 1/257 an octave above, 256/257 an octave below
    assert q_response(f, 10.0) == pytest.approx([1.0, 0.5, 1.0 / 257.0, 256.0 / 257.0], rel=1e-15)
    assert np.all(q_response(f, None) == 1.0)


def test_a_lag_on_a_sine_is_the_hand_computed_sine():
    n, period, tau = 400, 2.0, 0.05
    t = np.arange(n) * period / n
    w = 2 * np.pi * 3 / period  # the third harmonic
    out = apply_response(np.sin(w * t), lag_response(frequencies(n, period), tau))
    # sin(wt) / (1 + iwτ) = (sin wt − wτ cos wt) / (1 + w²τ²)
    assert out == pytest.approx((np.sin(w * t) - w * tau * np.cos(w * t)) / (1 + (w * tau) ** 2), abs=1e-14)


def test_periodic_derivatives_of_a_cosine():
    n, period = 256, 0.8
    t = np.arange(n) * period / n
    w = 2 * np.pi * 5 / period
    d1, d2 = periodic_derivatives(np.cos(w * t), period)
    assert d1 == pytest.approx(-w * np.sin(w * t), abs=1e-10 * w)
    assert d2 == pytest.approx(-w * w * np.cos(w * t), abs=1e-10 * w * w)


def test_q_refuses_a_cutoff_that_is_not_positive():
    with pytest.raises(ArgumentError, match="cutoff"):
        q_response(np.array([1.0]), 0.0)
    with pytest.raises(ArgumentError, match="cutoff"):
        q_response(np.array([1.0]), -1.0)
    assert q_response(np.array([0.0]), 1e-9)[0] == 1.0  # any positive cutoff is accepted; Q(0) = 1


@pytest.mark.filterwarnings("error")
def test_q_of_a_tiny_cutoff_is_zero_above_it_without_overflow():
    """(f/f_c)^8 overflows for f_c = 1e-300 Hz and f ≥ 1e-261 Hz; Q is 0 there, and 1/2, 1/257 as ever near f_c."""
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        q = q_response(np.array([0.0, 1e-300, 2e-300, 1.0, 1e300, np.inf]), 1e-300)
        assert q.tolist() == [1.0, 0.5, pytest.approx(1.0 / 257.0, rel=1e-15), 0.0, 0.0, 0.0]
        assert q_response(np.array([1.0]), 10.0)[0] == pytest.approx(1.0 / (1.0 + 1e-8), rel=1e-15)  # a decade below
        assert q_response(np.array([10.0]), 1.0)[0] == pytest.approx(1.0 / (1.0 + 1e8), rel=1e-15)  # a decade above
        assert q_response(np.array([-20.0, -5.0]), 10.0) == pytest.approx([1.0 / 257.0, 256.0 / 257.0], rel=1e-15)


def test_a_lag_of_zero_is_one_and_a_negative_lag_is_refused():
    assert lag_response(np.array([0.0, 3.0]), 0.0) == pytest.approx([1.0, 1.0])
    # at f = 1/(2πτ): 1/(1 + i) = (1 − i)/2
    assert lag_response(np.array([1.0 / (2 * np.pi * 0.1)]), 0.1)[0] == pytest.approx(0.5 - 0.5j)
    with pytest.raises(ArgumentError, match="lag"):
        lag_response(np.array([1.0]), -1e-12)


def test_the_nyquist_bin_of_an_even_period_takes_the_responses_real_part():
    x = np.array([1.0, -1.0, 1.0, -1.0])  # all at the Nyquist bin (f = 2/T for n = 4)
    response = np.array([1.0, 1.0, 0.25 + 5.0j])
    assert apply_response(x, response) == pytest.approx(0.25 * x, abs=1e-15)
    # an odd period has no Nyquist bin: a pure delay of one sample at the fundamental is e^{−i2π/3}
    y = np.cos(2 * np.pi * np.arange(3) / 3)
    delayed = apply_response(y, np.array([1.0, np.exp(-2j * np.pi / 3)]))
    assert delayed == pytest.approx(np.roll(y, 1), abs=1e-15)


def test_a_response_acts_on_every_column_alike():
    x = np.stack([np.ones(6), 2 * np.ones(6)], axis=1)
    out = apply_response(x, np.array([0.5, 1.0, 1.0, 1.0]))  # the mean halved, nothing else to act on
    assert out == pytest.approx(np.stack([0.5 * np.ones(6), np.ones(6)], axis=1), abs=1e-15)


def test_the_derivatives_drop_the_nyquist_bin_of_an_even_period():
    x = np.array([1.0, -1.0, 1.0, -1.0])  # its derivative is not a real signal: both derivatives are zero
    d1, d2 = periodic_derivatives(x, 1.0)
    assert d1 == pytest.approx(np.zeros(4), abs=1e-15) and d2 == pytest.approx(np.zeros(4), abs=1e-15)
    # a sine on an odd period: the fundamental's derivatives exactly
    t = np.arange(5) / 5
    d1, d2 = periodic_derivatives(np.sin(2 * np.pi * t), 1.0)
    assert d1 == pytest.approx(2 * np.pi * np.cos(2 * np.pi * t), abs=1e-12)
    assert d2 == pytest.approx(-((2 * np.pi) ** 2) * np.sin(2 * np.pi * t), abs=1e-12)

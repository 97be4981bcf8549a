"""hipsim.rig.logs.reversals pinned by hand: the window around each reversal of a slider.

A flexion α = 10°·sin(2π·t + φ) moves every slider one way while α rises and back while it falls, so each slider
reverses where the closed-form rate cos(2π·t + φ) changes sign; an abduction β leaves slider 2 still (the platform
tilts about the axis through it), so it never reverses. The window is ⌈1.5·f_s/f_c⌉ samples either side:
⌈1.5·250/20⌉ = 19 at 250 Hz and 20 Hz, from the sample before the sign change to the one after.
"""

from __future__ import annotations

import numpy as np
import pytest

import hipsim
from hipsim.motion.trajectories import Trajectory
from hipsim.rig.logs.log import MeasuredLog
from hipsim.rig.logs.reversals import REVERSAL_PERIODS, reversal_mask

PARAMS = hipsim.load_parameters()
RATE, CUTOFF, HALF = 250.0, 20.0, 19


def log(angle: int, n: int, cutoff=CUTOFF, phase=1.3):
    t = np.arange(n) / RATE
    q = np.zeros((n, 3))
    q[:, angle] = np.radians(10.0) * np.sin(2 * np.pi * t + phase)
    still = np.zeros((n, 3))
    return MeasuredLog(Trajectory(t, q, still, still, np.full(n, 1000.0)), np.zeros((n, 3)), cutoff, "r.csv")


def expected(n: int, phase=1.3) -> np.ndarray:
    """Samples within HALF of a sign change of the closed-form rate (the change between samples c and c + 1)."""
    rate = np.cos(2 * np.pi * np.arange(n) / RATE + phase)
    window = np.zeros(n, dtype=bool)
    for c in np.flatnonzero(np.sign(rate[1:]) != np.sign(rate[:-1])):
        window[max(c - HALF, 0) : min(c + HALF + 2, n)] = True
    return window


def test_the_window_width():
    assert REVERSAL_PERIODS == 1.5


@pytest.mark.parametrize("n", [500, 520])
def test_each_slider_reverses_with_the_flexion(n):
    # φ = 1.3 puts the first reversal 10 samples in (its window cut at the log's start); 520 samples end 9
    # samples after the last one (its window cut at the log's end).
    mask = reversal_mask(PARAMS, log(0, n))
    window = expected(n)
    assert window[0] and window[-1] == (n == 520)
    assert mask.shape == (n, 3) and mask.dtype == bool
    for i in range(3):
        np.testing.assert_array_equal(mask[:, i], window)


def test_a_slider_that_does_not_move_never_reverses():
    mask = reversal_mask(PARAMS, log(1, 500))
    np.testing.assert_array_equal(mask[:, 0], expected(500))
    assert not mask[:, 1].any()
    np.testing.assert_array_equal(mask[:, 2], expected(500))


def test_an_unfiltered_log_has_no_windows():
    mask = reversal_mask(PARAMS, log(0, 500, cutoff=None))
    assert mask.shape == (500, 3) and not mask.any()

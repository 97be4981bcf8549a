"""The noise check: a clean gait sampled at 60 Hz passes, the same with measurement noise is called noisy."""

import numpy as np
import pytest
from support import given

from hipsim.motion.noise_check import SUGGESTED_CUTOFF, check_noise
from hipsim.motion.trajectories import iso14242_angles


def gait(rate, cycles=5, noise_deg=0.0, seed=0):
    t = np.arange(int(cycles * rate)) / rate
    q, _, _ = iso14242_angles(t)
    return t, q + np.radians(np.random.default_rng(seed).normal(0.0, noise_deg, q.shape))


@pytest.mark.parametrize("rate", [60.0, 100.0, 1000.0])
def test_clean_gait_is_not_noisy(rate):
    check = check_noise(*gait(rate))
    assert not check.noisy and check.share.max() < 0.01
    assert check.warning("walk.mot") is None


@pytest.mark.parametrize(("rate", "noise_deg"), [(60.0, 0.1), (100.0, 0.05), (1000.0, 0.003)])
def test_measurement_noise_is_called_and_the_warning_suggests_the_cutoff(rate, noise_deg):
    check = check_noise(*gait(rate, noise_deg=noise_deg))
    assert check.noisy
    text = given(check.warning("walk.mot"))
    assert text.startswith("walk.mot: ") and f"--cutoff {SUGGESTED_CUTOFF:g}" in text and f"{rate:g} Hz" in text


def test_a_part_cycle_does_not_leak_into_the_high_band():
    t, q = gait(60.0, cycles=2.37)
    assert not check_noise(t, q).noisy


def test_too_slow_or_too_short_to_tell():
    assert not check_noise(*gait(20.0, noise_deg=1.0)).noisy
    t, q = gait(1000.0, cycles=0.01, noise_deg=1.0)
    assert not check_noise(t, q).noisy

"""Gait events from the load: heel strike at the load's rise, toe-off at its return, phases from heel strike."""

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.motion.gait_events import detect_gait_events, gait_phase
from hipsim.motion.trajectories import ISO_LOAD_KNOTS, iso14242_load

RATE = 1000.0
# The built-in load leaves its 300 N swing level at s = 0 and returns to it at s = 0.62 (spec §7.2).
RISE_S, RETURN_S = ISO_LOAD_KNOTS[0][0], ISO_LOAD_KNOTS[4][0]


def sampled(offset, cycles=4.0, rate=RATE):
    t = offset + np.arange(int(cycles * rate)) / rate
    return t, iso14242_load(t)


@pytest.mark.parametrize("seed", range(20))
def test_heel_strike_is_the_sample_of_the_loads_rise_whatever_the_first_sample(seed):
    offset = np.random.default_rng(seed).uniform(0.0, 1.0)
    t, load = sampled(offset)
    events = detect_gait_events(t, load)
    # The true rises are at whole seconds; the first sample at or after each lies within one step.
    rises = np.arange(np.ceil(t[0]), t[-1])
    assert events.t_heel_strikes.size >= 3
    for hs in events.t_heel_strikes:
        nearest = rises[np.argmin(np.abs(rises - hs))]
        assert abs(hs - nearest) <= 1.0 / RATE + 1e-12, (hs, nearest)
    for to in events.t_toe_offs:
        returns = rises - 1.0 + RETURN_S
        returns = np.concatenate([returns, returns + 1.0])
        assert np.min(np.abs(returns - to)) <= 1.0 / RATE + 1e-12, to
    assert events.period == pytest.approx(1.0, abs=1.5 / RATE)


def test_noise_neither_adds_nor_loses_events():
    t, load = sampled(0.37, cycles=6)
    noisy = load + np.random.default_rng(1).normal(0.0, 30.0, load.size)  # 1 % of the range
    clean, rough = detect_gait_events(t, load), detect_gait_events(t, noisy)
    assert rough.heel_strikes.size == clean.heel_strikes.size == 6
    assert rough.toe_offs.size == clean.toe_offs.size
    # With noise the rise is found a few samples late, never early by more than one.
    lag = rough.heel_strikes - clean.heel_strikes
    assert np.all(lag >= -1) and np.all(lag <= 25), lag


def test_a_constant_load_has_no_events():
    t = np.arange(1000) / RATE
    events = detect_gait_events(t, np.full(t.size, 800.0))
    assert events.cycles == 0 and events.heel_strikes.size == 0
    with pytest.raises(TrajectoryError, match="two heel strikes"):
        gait_phase(t, events)


def test_phase_runs_from_heel_strike_and_stance_ends_at_toe_off():
    t, load = sampled(0.25, cycles=5)
    phase, stance = gait_phase(t, detect_gait_events(t, load))
    # The true phase is the cycle fraction from the rise at whole seconds.
    truth = 100.0 * np.mod(t, 1.0)
    wrapped = np.abs((phase - truth + 50.0) % 100.0 - 50.0)
    assert wrapped.max() <= 100.0 * 1.5 / RATE
    inside = (np.abs(truth - 100 * RETURN_S) > 0.2) & (truth > 0.2) & (truth < 99.8)
    np.testing.assert_array_equal(stance[inside], truth[inside] < 100 * RETURN_S)


def test_bad_thresholds_are_refused():
    t, load = sampled(0.0, cycles=2)
    with pytest.raises(TrajectoryError, match="0 < fall ≤ rise < 1"):
        detect_gait_events(t, load, rise=0.1, fall=0.2)

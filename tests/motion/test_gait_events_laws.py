"""hipsim.motion.gait_events pinned on load curves drawn by hand: where each event falls, sample by sample.

The curves are piecewise linear and written out here (swing level, ramps,
stance level), so each heel strike (the last sample at the swing level before
a rise) and toe-off (the first sample back at it) is known by construction.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.motion.gait_events import DEFAULT_FALL, DEFAULT_RISE, detect_gait_events, gait_cycles, gait_phase
from hipsim.motion.trajectories import iso14242

RATE = 100.0


def cycle(swing=40, ramp=10, stance=40, low=200.0, high=1200.0):
    """One cycle: ``swing`` samples at ``low``, a rise over ``ramp`` samples, ``stance`` at ``high``, a fall."""
    up = low + (high - low) * np.arange(1, ramp + 1) / ramp
    return np.concatenate([np.full(swing, low), up, np.full(stance, high), up[::-1][1:], [low]])


def curve(cycles=3, **shape):
    load = np.concatenate([cycle(**shape) for _ in range(cycles)] + [np.full(40, shape.get("low", 200.0))])
    return np.arange(load.size) / RATE, load


def test_heel_strikes_and_toe_offs_of_a_drawn_curve():
    # One cycle is 40 + 10 + 40 + 10 = 100 samples. In cycle c (starting at 100c) the last swing
    # sample is 100c + 39, the load is back at 200 N at 100c + 99 (the fall's last value is 200).
    t, load = curve()
    events = detect_gait_events(t, load)
    np.testing.assert_array_equal(events.heel_strikes, [39, 139, 239])
    np.testing.assert_array_equal(events.toe_offs, [99, 199, 299])
    np.testing.assert_allclose(events.t_heel_strikes, [0.39, 1.39, 2.39])
    np.testing.assert_allclose(events.t_toe_offs, [0.99, 1.99, 2.99])
    assert events.low == 200.0 and events.high == 1200.0
    assert events.cycles == 2
    np.testing.assert_allclose(events.periods, [1.0, 1.0])
    assert events.period == pytest.approx(1.0)


def test_the_period_is_the_median_of_the_cycles():
    # Swings of 40, 60 and 40 samples: periods 1.2 s and 1.0 s and 1.0 s... median of (1.2, 1.0) is 1.1;
    # with three whole cycles (1.0, 1.2, 1.0) it is 1.0.
    low = np.concatenate([cycle(swing=40), cycle(swing=60), cycle(swing=40), cycle(swing=40), np.full(40, 200.0)])
    events = detect_gait_events(np.arange(low.size) / RATE, low)
    # Heel strikes at 39, 100 + 59 = 159, 220 + 39 = 259, 320 + 39 = 359.
    np.testing.assert_array_equal(events.heel_strikes, [39, 159, 259, 359])
    np.testing.assert_allclose(events.periods, [1.2, 1.0, 1.0])
    assert events.period == pytest.approx(1.0)


def test_no_whole_cycle_gives_no_period_and_the_count_is_never_negative():
    t, load = curve(cycles=1)
    events = detect_gait_events(t, load)
    assert events.cycles == 0 and np.isnan(events.period)
    flat = detect_gait_events(np.arange(50) / RATE, np.full(50, 300.0))
    assert flat.cycles == 0 and flat.heel_strikes.size == 0 and flat.toe_offs.size == 0


def test_the_thresholds_are_a_quarter_and_a_tenth_of_the_range():
    assert (DEFAULT_RISE, DEFAULT_FALL) == (0.25, 0.10)
    # A bump to 24 % of the 1000 N range above the swing is not a stance; one to 26 % is.
    base = np.concatenate([cycle(), cycle(), np.full(40, 200.0)])
    for height, strikes in [(0.24, 2), (0.26, 3)]:
        bump = np.concatenate([np.full(30, 200.0), np.full(20, 200.0 + height * 1000.0), np.full(30, 200.0)])
        load = np.concatenate([base, bump])
        assert detect_gait_events(np.arange(load.size) / RATE, load).heel_strikes.size == strikes, height
    # In stance, a dip to 11 % of the range does not end it (hysteresis); a dip to 9 % does.
    for depth, toe_offs in [(0.11, 3), (0.09, 4)]:
        dipped = cycle(stance=40).copy()
        dipped[70:75] = 200.0 + depth * 1000.0
        load = np.concatenate([cycle(), dipped, cycle(), np.full(40, 200.0)])
        assert detect_gait_events(np.arange(load.size) / RATE, load).toe_offs.size == toe_offs, depth


def test_custom_thresholds_are_checked():
    t, load = curve()
    for rise, fall in [(0.1, 0.2), (0.0, 0.0), (1.0, 0.1), (0.5, 0.0)]:
        with pytest.raises(TrajectoryError, match="0 < fall ≤ rise < 1"):
            detect_gait_events(t, load, rise=rise, fall=fall, source="gait.csv")
    # fall = rise is allowed.
    assert detect_gait_events(t, load, rise=0.3, fall=0.3).cycles == 2
    with pytest.raises(TrajectoryError, match="1-D of one length"):
        detect_gait_events(t[:-1], load)
    with pytest.raises(TrajectoryError, match="1-D of one length"):
        detect_gait_events(np.stack([t, t]), np.stack([load, load]))


def test_the_swing_noise_widens_the_baseline_by_three_times_its_estimate():
    # The swing before the second rise: 200 N (the fall's end), 19 pairs 200/202 N less the last
    # pair, then 205 and 206 N, then the load jumps to stance. Its 40 steps: 0, 19 × +2, 18 × −2,
    # +3, +1; their median is (1 + 2)/2 = 1.5, the median of |step − 1.5| is (0.5 + 1.5)/2 = 1.0,
    # so σ = 1.0/(0.6745·√2) = 1.0483 N; the baseline (median of the 41 samples) is 202 N.
    # Level 202 + 3σ = 205.145 N: 205 N is at the baseline, 206 N is not, so the heel strike is the
    # 205 N sample (with 2σ it would be the 202 N before it, with 4σ the 206 N after).
    swing = np.tile([200.0, 202.0], 20)
    first = cycle()
    second = np.concatenate([swing[:-2], [205.0, 206.0], np.full(40, 1200.0), np.linspace(1100.0, 200.0, 10)])
    load = np.concatenate([first, second, swing])
    events = detect_gait_events(np.arange(load.size) / RATE, load)
    assert events.heel_strikes[1] == first.size + 38  # the 205 N sample


def test_a_log_starting_in_stance_or_in_the_rise():
    t, load = curve()
    # Starting mid-stance: the first toe-off counts, the first heel strike is not in the log.
    events = detect_gait_events(t[60:] - t[60], load[60:])
    np.testing.assert_array_equal(events.heel_strikes, [139 - 60, 239 - 60])
    np.testing.assert_array_equal(events.toe_offs, [99 - 60, 199 - 60, 299 - 60])
    # Starting in the rise (sample 45): no sample of that swing, so no heel strike there.
    events = detect_gait_events(t[45:] - t[45], load[45:])
    np.testing.assert_array_equal(events.heel_strikes, [139 - 45, 239 - 45])


def test_the_iso_cycle_has_its_heel_strike_at_each_cycle_start():
    # 4.5 cycles of 0.8 s at 200 Hz: the load sits at 300 N from 62 % of the cycle to 100 % and rises
    # from each cycle's start, so the heel strikes are the samples 0, 160, 320, 480, 640 (4 whole cycles);
    # toe-off at 62 % + nothing: the first sample back at 300 N, 0.62·160 = 99.2 → sample 100.
    events = gait_cycles(iso14242(rate=200.0, cycles=4.5, frequency=1.25))
    np.testing.assert_array_equal(events.heel_strikes, [0, 160, 320, 480, 640])
    np.testing.assert_array_equal(events.toe_offs, [100, 260, 420, 580])
    assert events.cycles == 4
    assert events.period == pytest.approx(0.8, abs=1e-12)


def test_gait_phase_by_hand():
    # Heel strikes at 0.39, 1.39, 2.39 s; toe-offs 0.6 s after each: stance is 60 % of the cycle.
    t, load = curve()
    events = detect_gait_events(t, load)
    phase, stance = gait_phase(t, events)
    # At 0.89 s: half a cycle after 0.39 → 50 %, stance. At 1.19 s: 80 %, swing.
    i, j = 89, 119
    assert phase[i] == pytest.approx(50.0) and stance[i]
    assert phase[j] == pytest.approx(80.0) and not stance[j]
    # Before the first heel strike the median period (1 s) continues: 0.19 s is 80 % (0.2 s before).
    assert phase[19] == pytest.approx(80.0) and not stance[19]
    # After the last: 2.99 s is 60 % after 2.39; stance ended at 60 %.
    assert phase[299] == pytest.approx(60.0) and not stance[299]
    assert phase[290] == pytest.approx(51.0) and stance[290]
    assert phase[39] == 0.0 and stance[39]
    with pytest.raises(TrajectoryError, match="1 heel strike"):
        gait_phase(curve(cycles=1)[0], detect_gait_events(*curve(cycles=1)))


def test_gait_phase_with_two_heel_strikes():
    # Exactly one whole cycle (heel strikes at 0.39 and 1.39 s) is enough: 0.89 s is 50 %.
    t, load = curve(cycles=2)
    events = detect_gait_events(t, load)
    assert events.heel_strikes.size == 2
    phase, stance = gait_phase(t, events)
    assert phase[89] == pytest.approx(50.0) and stance[89]


def test_gait_phase_with_a_cycle_missing_its_toe_off_uses_the_typical_stance():
    # Whole cycles of 1 s; stance 60 % in each with a toe-off, so the typical stance is 60 %.
    t, load = curve(cycles=4)
    events = detect_gait_events(t, load)
    held = type(events)(
        events.heel_strikes, events.toe_offs[1:], events.t_heel_strikes, events.t_toe_offs[1:], 200.0, 1200.0
    )
    phase, stance = gait_phase(t, held)
    # Cycle 0 (0.39 → 1.39 s) lost its toe-off: 55 % is stance, 65 % swing by the typical 60 %.
    assert stance[39 + 55] and not stance[39 + 65]


def test_gait_cycles_of_a_log_or_a_trajectory():
    # A rig log hands its trajectory; a bad one is named by its source.
    tr = iso14242(rate=100.0, cycles=3)
    np.testing.assert_array_equal(gait_cycles(SimpleNamespace(trajectory=tr)).heel_strikes, [0, 100, 200])
    bad = SimpleNamespace(t=np.arange(5.0), Fe=np.zeros(4), name="walk.csv")
    with pytest.raises(TrajectoryError, match="walk.csv"):
        gait_cycles(bad)
    with pytest.raises(TrajectoryError) as refused:
        gait_cycles(SimpleNamespace(t=np.arange(5.0), Fe=np.zeros(4)))
    assert str(refused.value) == "load: times (5,) and load (4,) must be 1-D of one length"


def refusal(call, *args, **kwargs) -> str:
    """The whole message of the TrajectoryError that ``call`` raises."""
    with pytest.raises(TrajectoryError) as refused:
        call(*args, **kwargs)
    return str(refused.value)


def test_refusals_name_the_file_and_what_is_wrong():
    t, load = curve()
    assert refusal(detect_gait_events, t[:-1], load, source="gait.csv") == (
        f"gait.csv: times ({t.size - 1},) and load ({t.size},) must be 1-D of one length"
    )
    assert refusal(detect_gait_events, t, load, rise=0.1, fall=0.2, source="gait.csv") == (
        "gait.csv: gait event thresholds must satisfy 0 < fall ≤ rise < 1, got rise 0.1, fall 0.2"
    )
    # Without a source, the load is named as "load".
    assert refusal(detect_gait_events, t, load, rise=1.0) == (
        "load: gait event thresholds must satisfy 0 < fall ≤ rise < 1, got rise 1.0, fall 0.1"
    )
    one = detect_gait_events(*curve(cycles=1))
    assert refusal(gait_phase, curve(cycles=1)[0], one) == (
        "found 1 heel strike(s) in the load; a whole gait cycle (two heel strikes) is needed to know the phase"
    )


def test_three_samples_are_enough_for_events_and_two_are_not():
    # 200, 1200, 200 N: the 5th and 95th percentiles are 200 and 1100 N (linear between the sorted
    # samples 200, 200, 1200 at positions 0.1 and 1.9); the middle sample is stance, the ends swing.
    # The heel strike is the first sample, the toe-off the last.
    events = detect_gait_events(np.arange(3) / RATE, np.array([200.0, 1200.0, 200.0]))
    assert (events.low, events.high) == (200.0, 1100.0)
    np.testing.assert_array_equal(events.heel_strikes, [0])
    np.testing.assert_array_equal(events.toe_offs, [2])
    two = detect_gait_events(np.arange(2) / RATE, np.array([200.0, 1200.0]))
    assert two.heel_strikes.size == 0 and two.toe_offs.size == 0 and np.isnan(two.low) and np.isnan(two.high)
    assert two.heel_strikes.dtype == int and two.t_heel_strikes.size == 0 and two.t_toe_offs.size == 0


def test_a_constant_load_keeps_its_level_and_has_no_events():
    flat = detect_gait_events(np.arange(50) / RATE, np.full(50, 300.0))
    assert (flat.low, flat.high) == (300.0, 300.0)
    assert flat.heel_strikes.dtype == int and flat.t_toe_offs.size == 0 and flat.t_heel_strikes.size == 0


@pytest.mark.parametrize(
    ("low", "span", "found"),
    [(1000.0, 2e-6, True), (1000.0, 0.5e-6, False), (0.5, 1.5e-9, True), (0.5, 0.5e-9, False)],
)
def test_a_load_is_constant_when_it_varies_by_less_than_a_billionth_of_its_level(low, span, found):
    # Constant up to round-off: the 95th − 5th percentile at most 1e-9 of the stance level, or of 1 N
    # when the load is below 1 N. 1000 N varying by 2e-6 N has its events (above 1e-6 N), by 0.5e-6 N
    # none; 0.5 N varying by 1.5e-9 N has them (above 1e-9 N), by 0.5e-9 N none.
    t, load = curve(low=low, high=low + span)
    events = detect_gait_events(t, load)
    if found:
        np.testing.assert_array_equal(events.heel_strikes, [39, 139, 239])
        np.testing.assert_array_equal(events.toe_offs, [99, 199, 299])
    else:
        assert events.heel_strikes.size == 0 and events.toe_offs.size == 0


def test_a_swing_sample_above_its_level_by_round_off_is_at_the_level():
    # A noise-free swing (its steps all 0, so no noise estimate) whose last sample is 1e-7 N above
    # 200 N: within the floor of 1e-9 of the 1000 N range (1e-6 N), so it is the heel strike, not the
    # sample before it; 1e-5 N above is above the floor.
    t, load = curve()
    load[139] += 1e-7
    assert detect_gait_events(t, load).heel_strikes[1] == 139
    load[139] += 1e-5
    assert detect_gait_events(t, load).heel_strikes[1] == 138
    # The same at a toe-off: the fall's last sample (199) 1e-7 N above 200 N is back at the level.
    t, load = curve()
    load[199] += 1e-7
    assert detect_gait_events(t, load).toe_offs[1] == 199
    load[199] += 1e-5
    assert detect_gait_events(t, load).toe_offs[1] == 200


def test_gait_phase_of_every_sample_with_cycles_of_three_lengths():
    # Swings of 40, 60, 50 and 40 samples: cycles of 100, 120, 110 and 100 samples. Heel strikes at
    # 0.39, 1.59, 2.69 and 3.69 s (periods 1.2, 1.1 and 1.0 s, median 1.1 s); toe-offs at 0.99, 2.19,
    # 3.29 and 4.29 s (the last after the last heel strike). Stance: 0.6/1.2 = 50 %, 0.6/1.1 = 54.5 %,
    # 0.6/1.0 = 60 % of the three whole cycles; before the first and after the last heel strike the
    # phase runs on with the median period and stance is the median stance, 54.5 %.
    load = np.concatenate([cycle(swing=40), cycle(swing=60), cycle(swing=50), cycle(swing=40), np.full(40, 200.0)])
    t = np.arange(load.size) / RATE
    events = detect_gait_events(t, load)
    strikes = np.array([0.39, 1.59, 2.69, 3.69])
    np.testing.assert_allclose(events.t_heel_strikes, strikes)
    np.testing.assert_allclose(events.t_toe_offs, [0.99, 2.19, 3.29, 4.29])
    phase, stance = gait_phase(t, events)
    expected, limit = np.empty(t.size), np.empty(t.size)
    for i, ti in enumerate(t):
        if ti < strikes[0] or ti >= strikes[-1]:
            start = strikes[0] if ti < strikes[0] else strikes[-1]
            expected[i] = (100.0 * (ti - start) / 1.1) % 100.0
            limit[i] = 100.0 * 0.6 / 1.1
        else:
            c = np.searchsorted(strikes, ti, side="right") - 1
            expected[i] = 100.0 * (ti - strikes[c]) / (strikes[c + 1] - strikes[c])
            limit[i] = 100.0 * 0.6 / (strikes[c + 1] - strikes[c])
    np.testing.assert_allclose(phase, expected, atol=1e-9)
    # Away from the stance's end (where the sample and the limit coincide), stance is phase < limit.
    clear = np.abs(expected - limit) > 1e-6
    np.testing.assert_array_equal(stance[clear], (expected < limit)[clear])
    # A toe-off on a cycle's last sample is stance's end: 0.99 s is swing, 0.98 s stance.
    assert not stance[99] and stance[98]


def test_the_swing_noise_estimate_by_hand():
    from hipsim.motion.gait_events import _swing_baseline

    load = np.array([200.0, 202.0, 200.0, 206.0, 203.0])
    # Four samples: steps 2, −2, 6; their median 2; |step − 2| = 0, 4, 4, median 4: σ = 4/(0.6745·√2).
    baseline, noise = _swing_baseline(load, 0, 4)
    assert baseline == 201.0 and noise == pytest.approx(4.0 / (0.6745 * np.sqrt(2.0)), rel=1e-12)
    # Three samples (two steps) are too few to estimate the noise: 0. One sample: its value.
    assert _swing_baseline(load, 0, 3) == (200.0, 0.0)
    assert _swing_baseline(load, 1, 2) == (202.0, 0.0)
    assert _swing_baseline(load, 3, 3) == (206.0, 0.0)  # an empty range is widened to its first sample
    # From the last sample on and past the end: nothing, no level.
    assert _swing_baseline(load, 4, 9) == (203.0, 0.0)
    empty_baseline, empty_noise = _swing_baseline(load, 5, 9)
    assert np.isnan(empty_baseline) and empty_noise == 0.0


def test_the_levels_are_the_5th_and_95th_percentiles():
    # 0, 10, …, 1000 N: the 5th percentile is 50 N, the 95th 950 N.
    load = np.arange(101) * 10.0
    events = detect_gait_events(np.arange(101) / RATE, load)
    assert (events.low, events.high) == (50.0, 950.0)


def test_a_load_exactly_on_a_threshold_has_not_crossed_it():
    # Swing 200 N, stance 1200 N: stance begins above 200 + 0.25·1000 = 450 N and ends below 300 N.
    base = np.concatenate([cycle(), cycle(), np.full(40, 200.0)])
    bump = np.concatenate([np.full(30, 200.0), np.full(20, 450.0), np.full(30, 200.0)])
    load = np.concatenate([base, bump])
    assert detect_gait_events(np.arange(load.size) / RATE, load).heel_strikes.size == 2
    dipped = cycle().copy()
    dipped[70:75] = 300.0
    load = np.concatenate([cycle(), dipped, cycle(), np.full(40, 200.0)])
    assert detect_gait_events(np.arange(load.size) / RATE, load).toe_offs.size == 3


def test_one_step_up_or_down():
    # A load that only rises has a heel strike and no toe-off; one that only falls, the opposite.
    up = np.concatenate([np.full(50, 200.0), np.full(50, 1200.0)])
    events = detect_gait_events(np.arange(100) / RATE, up)
    np.testing.assert_array_equal(events.heel_strikes, [49])
    assert events.toe_offs.size == 0 and events.toe_offs.dtype == int and events.t_toe_offs.size == 0
    events = detect_gait_events(np.arange(100) / RATE, up[::-1])
    np.testing.assert_array_equal(events.toe_offs, [50])
    assert events.heel_strikes.size == 0 and events.heel_strikes.dtype == int and events.t_heel_strikes.size == 0


def test_a_log_starting_between_the_thresholds_has_no_state_until_it_crosses_one():
    # The first 20 samples at 15 % of the range (between 10 % and 25 %): neither stance nor swing. Their
    # fall to the swing level is no toe-off (stance was never seen); the cycles after are counted.
    t, load = curve()
    start = np.concatenate([np.full(20, 350.0), load])
    events = detect_gait_events(np.arange(start.size) / RATE, start)
    np.testing.assert_array_equal(events.heel_strikes, [59, 159, 259])
    np.testing.assert_array_equal(events.toe_offs, [119, 219, 319])


def test_gait_phase_without_any_toe_off_has_no_stance():
    t, load = curve()
    events = detect_gait_events(t, load)
    held = type(events)(
        events.heel_strikes, events.toe_offs[:0], events.t_heel_strikes, events.t_toe_offs[:0], 200.0, 1200.0
    )
    phase, stance = gait_phase(t, held)
    assert phase[89] == pytest.approx(50.0) and not stance.any()

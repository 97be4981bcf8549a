"""hipsim.motion.iso_compliance pinned both ways: a deviation above the tolerance fails, below passes, on either side.

Each run is the standard's own waveform (hipsim's built-in cycle) with one
change written here: a constant offset of one angle or of the load (whose
largest deviation is then the offset itself), or another frequency (whose
deviation is |f − 1 Hz|). Then the verdict's arithmetic on hand-made
deviations: the limit itself passes, the order and wording of the summary.
"""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.motion.iso_compliance import (
    DEFAULT_TOLERANCES,
    NOMINAL_FREQUENCY,
    PEAK_LOAD,
    CycleDeviation,
    IsoCheck,
    Tolerances,
    iso_check,
    parse_tolerances,
    periodic_extension,
)
from hipsim.motion.trajectories import iso14242_angles, iso14242_load


def run(frequency=1.0, cycles=3.0, rate=400.0, angle_offset=(0.0, 0.0, 0.0), load_offset=0.0):
    """The standard's waveforms at ``frequency`` with constant offsets: angles in [°], load in [N]."""
    t = 0.137 + np.arange(int(cycles * rate / frequency)) / rate
    q, _, _ = iso14242_angles(t, frequency)
    return t, q + np.radians(angle_offset), iso14242_load(t, frequency) + load_offset


def test_the_default_tolerances():
    # ±3° on each angle, ±3 % of the 3000 N peak = 90 N, ±0.1 Hz around 1 Hz.
    assert PEAK_LOAD == 3000.0 and NOMINAL_FREQUENCY == 1.0
    tol = DEFAULT_TOLERANCES
    assert (tol.alpha, tol.beta, tol.gamma, tol.load, tol.frequency) == (3.0, 3.0, 3.0, pytest.approx(90.0), 0.1)


@pytest.mark.parametrize(("frequency", "passed"), [(0.8, False), (1.2, False), (0.95, True), (1.05, True)])
def test_the_frequency_deviation_both_ways(frequency, passed):
    check = iso_check(*run(frequency=frequency))
    # Each cycle's frequency is the run's; its deviation |f − 1| is 0.2 Hz or 0.05 Hz.
    for cycle in check.cycles:
        assert cycle.frequency == pytest.approx(frequency, abs=1e-6)
    assert check.worst("frequency") == pytest.approx(abs(frequency - 1.0), abs=1e-6)
    assert check.passed is passed
    assert check.failing == (() if passed else ("frequency",))


@pytest.mark.parametrize(("index", "name"), [(0, "alpha"), (1, "beta"), (2, "gamma")])
@pytest.mark.parametrize(("offset", "passed"), [(4.0, False), (-4.0, False), (2.0, True), (-2.0, True)])
def test_each_angle_deviation_both_ways(index, name, offset, passed):
    # A constant offset of one angle: its largest |deviation| is |offset|, the other angles' stay 0.
    angles = [0.0, 0.0, 0.0]
    angles[index] = offset
    check = iso_check(*run(angle_offset=angles))
    # The cycles are aligned by a linear interpolation of the load's crossing, to ~0.1 ms at 400 Hz:
    # 0.4 m° on the angles, a few newtons on the load's steepest rise (22 kN/s).
    assert check.worst(name) == pytest.approx(abs(offset), abs=2e-3)
    for other in {"alpha", "beta", "gamma"} - {name}:
        assert check.worst(other) < 2e-3
    assert check.failing == (() if passed else (name,))
    assert check.passes(name).all() if passed else not check.passes(name).any()


@pytest.mark.parametrize(("offset", "passed"), [(100.0, False), (-100.0, False), (60.0, True), (-60.0, True)])
def test_the_load_deviation_both_ways(offset, passed):
    # A constant load offset moves the 5th/95th percentiles and their middle with it: the cycles are
    # aligned as without it, so the largest |deviation| is |offset|; tolerance 90 N.
    check = iso_check(*run(load_offset=offset))
    assert check.worst("load") == pytest.approx(abs(offset), abs=3.0)
    assert check.failing == (() if passed else ("load",))


def test_the_cycles_start_at_the_heel_strikes():
    # The run starts at 0.137 s, 0.137 into a 1 s cycle: the whole cycles start at 1.0 and 2.0 s.
    check = iso_check(*run(cycles=3.0))
    np.testing.assert_allclose([c.start for c in check.cycles], [1.0, 2.0], atol=2e-4)
    assert check.source == "run" and check.tolerances is DEFAULT_TOLERANCES


def test_a_periodic_run_is_checked_once_per_cycle():
    # Two whole periods at 1 Hz sampled at 200 Hz, starting at 0.5 s: as one period of an endless run,
    # cycles start at 1.0 and 2.0 s (the 2.0 s one wraps around), each once; checked as open, only 1.0 s.
    t = 0.5 + np.arange(400) / 200.0
    q, _, _ = iso14242_angles(t)
    check = iso_check(t, q, iso14242_load(t), periodic=True)
    np.testing.assert_allclose([c.start for c in check.cycles], [1.0, 2.0], atol=2e-4)
    assert check.passed
    open_check = iso_check(t, q, iso14242_load(t))
    np.testing.assert_allclose([c.start for c in open_check.cycles], [1.0], atol=2e-4)
    # The extension: three copies, the original in the middle, shifted by the span (2 s).
    te, qe, le = periodic_extension(t, q, iso14242_load(t))
    assert te.size == 1200 and te[0] == pytest.approx(-1.5) and te[400] == 0.5 and te[-1] == pytest.approx(4.495)
    np.testing.assert_array_equal(qe[800:], q)
    np.testing.assert_array_equal(le[:400], iso14242_load(t))


def test_the_verdict_on_hand_made_deviations():
    # Tolerances 2°, 2°, 2°, 50 N, 0.25 Hz. Cycle 1 sits exactly on every limit (passes: ≤);
    # cycle 2 exceeds β (2.5°) and the frequency (0.75 Hz: |0.75 − 1| = 0.25 passes, so 0.5 Hz fails).
    tol = Tolerances(alpha=2.0, beta=2.0, gamma=2.0, load=50.0, frequency=0.25)
    on_limits = CycleDeviation(0.0, 1.25, 2.0, 2.0, 2.0, 50.0)
    over = CycleDeviation(1.0, 0.5, 1.0, 2.5, 0.0, 10.0)
    check = IsoCheck((on_limits, over), tol, "walk.csv")
    assert on_limits.deviation("frequency") == 0.25 and over.deviation("frequency") == 0.5
    np.testing.assert_array_equal(check.passes("beta"), [True, False])
    np.testing.assert_array_equal(check.passes("frequency"), [True, False])
    np.testing.assert_array_equal(check.passes("load"), [True, True])
    assert check.failing == ("beta", "frequency")
    assert not check.passed
    assert check.worst("beta") == 2.5 and check.worst("frequency") == 0.5 and check.worst("load") == 50.0
    assert check.summary() == [
        "alpha: worst 2 ° (tolerance 2 °): pass",
        "beta: worst 2.5 ° (tolerance 2 °): FAIL in 1 of 2 cycles",
        "gamma: worst 2 ° (tolerance 2 °): pass",
        "load: worst 50 N (tolerance 50 N): pass",
        "frequency: worst 0.5 Hz (tolerance 0.25 Hz): FAIL in 1 of 2 cycles",
    ]
    assert IsoCheck((on_limits,), tol, "x").passed
    # Two of three cycles failing β: the count is of the failing ones.
    three = IsoCheck((on_limits, over, over), tol, "x")
    assert "beta: worst 2.5 ° (tolerance 2 °): FAIL in 2 of 3 cycles" in three.summary()


def test_tolerances_refuse_what_is_not_a_positive_number():
    for bad in (0.0, -1.0, float("nan"), float("inf"), True, "3"):
        with pytest.raises(ArgumentError) as refused:
            Tolerances(alpha=bad)  # type: ignore[arg-type]  # wrong types on purpose
        assert str(refused.value) == f"tolerance: expected a positive finite number, got {f'alpha={bad!r}'!r}"
    assert Tolerances(load=1).load == 1


def test_parse_tolerances_by_hand():
    # 2 % of the 3000 N peak is 60 N; names and values may have spaces; unnamed ones keep the base's.
    tol = parse_tolerances(" gamma = 1.5 , load = 2 % ", base=Tolerances(alpha=7.0))
    assert (tol.alpha, tol.beta, tol.gamma, tol.load, tol.frequency) == (7.0, 3.0, 1.5, 60.0, 0.1)
    # Empty entries are skipped, not the end: beta after one is read.
    assert parse_tolerances("alpha=2,,beta=1").beta == 1.0
    for text, expected in [
        ("alpha=5%", "--iso-tolerance: expected a percentage for the load only, got 'alpha=5%'"),
        ("beta=three", "--iso-tolerance: expected a number after '=', got 'beta=three'"),
        ("beta==3", "--iso-tolerance: expected a number after '=', got 'beta==3'"),
        ("load=3X", "--iso-tolerance: expected a number after '=', got 'load=3X'"),
        (
            "beta 3",
            "--iso-tolerance: expected NAME=VALUE with NAME one of alpha, beta, gamma, load, frequency, got 'beta 3'",
        ),
    ]:
        with pytest.raises(ArgumentError) as refused:
            parse_tolerances(text)
        assert str(refused.value) == expected


def test_runs_that_cannot_be_checked():
    t, q, load = run()
    with pytest.raises(TrajectoryError, match="do not match"):
        iso_check(t, q[:-1], load, source="walk.csv")
    with pytest.raises(TrajectoryError, match="do not match"):
        iso_check(t, q, load[:-1])
    with pytest.raises(TrajectoryError, match="no stance and swing levels"):
        iso_check(t, q, np.full(t.size, 500.0))
    with pytest.raises(TrajectoryError, match="no whole gait cycle"):
        iso_check(t[:500], q[:500], load[:500])


def refusal(call, *args, **kwargs) -> str:
    """The whole message of the TrajectoryError that ``call`` raises."""
    with pytest.raises(TrajectoryError) as refused:
        call(*args, **kwargs)
    return str(refused.value)


def test_refusals_name_the_run_and_what_is_wrong():
    t, q, load = run(rate=100.0)  # 300 samples
    assert refusal(iso_check, t, q[:-1], load, source="walk.csv") == (
        "walk.csv: times (300,), angles (299, 3) and load (300,) do not match"
    )
    assert refusal(iso_check, t, q, load[:, None], source="walk.csv") == (
        "walk.csv: times (300,), angles (300, 3) and load (300, 1) do not match"
    )
    flat = "the load has no stance and swing levels, so no heel strike to align the cycles on"
    assert refusal(iso_check, t, q, np.full(t.size, 500.0), source="walk.csv") == f"walk.csv: {flat}"
    # Periodic: the same refusal, still naming the run (checked as its extension).
    assert refusal(iso_check, t, q, np.full(t.size, 500.0), source="walk.csv", periodic=True) == f"walk.csv: {flat}"
    assert refusal(iso_check, t[:0], q[:0], load[:0], source="walk.csv") == f"walk.csv: {flat}"
    # 1.5 s from 0.137 s at 100 Hz: heel strikes at 1.0 s only (t[0] is in mid-cycle), no whole cycle.
    assert refusal(iso_check, t[:150], q[:150], load[:150], source="walk.csv") == (
        "walk.csv: found no whole gait cycle (1 heel strike(s) in 1.49 s): the check needs at least one"
    )


def test_a_run_that_starts_on_a_heel_strike_keeps_its_first_cycle():
    # The built-in cycle from t = 0 s at 100 Hz, 3 cycles: the load rises from each whole second, so the
    # first sample is a heel strike and the cycle from 0 s is whole; the one from 2 s has no next
    # crossing in the run (it ends at 2.99 s). Checked as periodic, it wraps around: 0, 1 and 2 s.
    t = np.arange(300) / 100.0
    q, _, _ = iso14242_angles(t)
    check = iso_check(t, q, iso14242_load(t))
    np.testing.assert_allclose([c.start for c in check.cycles], [0.0, 1.0], atol=1e-3)
    periodic = iso_check(t, q, iso14242_load(t), periodic=True)
    np.testing.assert_allclose([c.start for c in periodic.cycles], [0.0, 1.0, 2.0], atol=1e-3)


@pytest.mark.parametrize(("fraction", "starts"), [(0.3, [1.0, 2.0]), (0.7, [2.0, 3.0])])
def test_a_periodic_run_owns_the_cycles_that_start_within_half_a_sample_of_its_first(fraction, starts):
    # Two periods at 1 Hz sampled at 50 Hz (step 0.02 s), the first sample a fraction of a step after
    # the heel strike at 1 s. The run owns the cycles that start from half a step before its first
    # sample up to half a step before the first sample of its next repetition (t₀ + 2 s): a start
    # 0.3 step before t₀ is its first cycle, and 3 s (0.3 step before t₀ + 2 s) is not; a start
    # 0.7 step before t₀ is not, and 3 s is.
    step = 0.02
    t = 1.0 + fraction * step + np.arange(100) * step
    q, _, _ = iso14242_angles(t)
    check = iso_check(t, q, iso14242_load(t), periodic=True)
    np.testing.assert_allclose([c.start for c in check.cycles], starts, atol=2e-3)
    assert check.passed


def test_a_periodic_run_of_one_sample_is_refused_like_an_open_one():
    t, q, load = np.array([0.5]), np.zeros((1, 3)), np.array([900.0])
    expected = "walk.csv: the load has no stance and swing levels, so no heel strike to align the cycles on"
    assert refusal(iso_check, t, q, load, source="walk.csv", periodic=True) == expected


def test_a_periodic_extension_of_five_copies_keeps_the_original_in_the_middle():
    # Samples at 0.5, 0.75, 1.0, 1.25 s: a span of 1 s; five copies shifted by −2 … +2 s.
    t = np.array([0.5, 0.75, 1.0, 1.25])
    q = np.arange(12.0).reshape(4, 3)
    te, qe, le = periodic_extension(t, q, np.array([1.0, 2.0, 3.0, 4.0]), copies=5)
    np.testing.assert_allclose(te, np.concatenate([t - 2.0, t - 1.0, t, t + 1.0, t + 2.0]))
    np.testing.assert_array_equal(qe[8:12], q)
    np.testing.assert_array_equal(le, np.tile([1.0, 2.0, 3.0, 4.0], 5))


@pytest.mark.parametrize(
    ("level", "span", "checked"),
    [(1000.0, 2e-6, True), (1000.0, 0.5e-6, False), (0.5, 1.5e-9, True), (0.5, 0.5e-9, False)],
)
def test_a_load_varying_by_less_than_a_billionth_of_its_level_is_refused(level, span, checked):
    # The standard's load shape scaled to a span (95th − 5th percentile) of about ``span`` above
    # ``level``: above 1e-9 of the level (of 1 N below 1 N) its cycles are found and checked (and fail
    # the load's tolerance by far); below, the load is constant.
    t = 0.137 + np.arange(600) / 200.0
    q, _, _ = iso14242_angles(t)
    shape = (iso14242_load(t) - 300.0) / 2700.0
    load = level + span * shape
    if checked:
        # 3 s from 0.137 s: whole cycles from 1 s and 2 s (the next rise's crossing at 3.06 s is in the run).
        np.testing.assert_allclose([c.start for c in iso_check(t, q, load).cycles], [1.0, 2.0], atol=2e-3)
    else:
        assert refusal(iso_check, t, q, load, source="walk.csv") == (
            "walk.csv: the load has no stance and swing levels, so no heel strike to align the cycles on"
        )


def test_a_run_ending_in_its_last_rise_does_not_start_a_cycle_there():
    # From 0.137 s to 3.05 s at 200 Hz: the load rises from 3.0 s (a heel strike, past the 25 % rise
    # threshold by 3.05 s) but does not reach the middle of its range: that heel strike has no crossing
    # (and the cycle from 2 s, no end). One whole cycle, from 1 s.
    t = 0.137 + np.arange(583) / 200.0
    q, _, _ = iso14242_angles(t)
    check = iso_check(t, q, iso14242_load(t))
    np.testing.assert_allclose([c.start for c in check.cycles], [1.0], atol=2e-3)


def test_cycles_that_start_off_the_whole_seconds_and_one_that_deviates():
    # The standard's waveforms delayed by 0.3 s: cycles start at 0.3 + k s and follow the standard. Then
    # the second whole cycle only (1.3 to 2.3 s) with α 4° higher: only that cycle deviates by 4°.
    t = np.arange(800) / 200.0
    q, _, _ = iso14242_angles(t - 0.3)
    load = iso14242_load(t - 0.3)
    check = iso_check(t, q, load)
    np.testing.assert_allclose([c.start for c in check.cycles], [0.3, 1.3, 2.3], atol=2e-3)
    assert check.worst("alpha") < 0.02 and check.passed  # aligned to about 0.1 ms: 0.015° of α
    q[(t >= 1.3) & (t < 2.3), 0] += np.radians(4.0)
    deviations = [c.alpha for c in iso_check(t, q, load).cycles]
    np.testing.assert_allclose(deviations, [0.0, 4.0, 0.0], atol=0.05)


def test_a_periodic_check_is_named_and_two_samples_are_one_period():
    t = 0.5 + np.arange(400) / 200.0
    q, _, _ = iso14242_angles(t)
    check = iso_check(t, q, iso14242_load(t), source="walk.csv", periodic=True)
    assert check.source == "walk.csv"
    # 300 N and 3000 N repeating every 0.02 s: one cycle of 50 Hz in the period.
    two = iso_check(np.array([0.0, 0.01]), np.zeros((2, 3)), np.array([300.0, 3000.0]), periodic=True)
    assert len(two.cycles) == 1 and two.cycles[0].frequency == pytest.approx(50.0)

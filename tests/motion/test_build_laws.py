"""Laws of the steps every trajectory reader ends in (hipsim.motion.build), on tables made by hand.

A :class:`Table` is built here directly (no file): times a few hundredths of a second apart, angles
that are polynomials or sines of time (a quintic spline reproduces a polynomial of degree ≤ 5 exactly,
so velocity and acceleration are known by hand), loads in whole newtons.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from motion_support import error_of, quiet

from hipsim.motion.build import (
    MAX_LOAD,
    NoiseWarning,
    NoLoadWarning,
    SampledMotion,
    Table,
    TrajectoryWarning,
    _closes_on_itself,
    _cycle_period,
    _positive,
    _resampled,
    build_trajectory,
    check_time,
    check_time_unit,
    relative_time,
    stride_count,
)
from hipsim.motion.columns import Column, ColumnMap
from hipsim.motion.filtering import lowpass_record
from hipsim.motion.load_file import LoadCurve

DEG = ColumnMap(Column("t", "s"), (Column("a", "deg"), Column("b", "deg"), Column("c", "deg")), False, Column("F", "N"))


def table(time, angles, load=None, columns=DEG, quantum=0.0, lines=None, source="f.csv") -> Table:
    time = np.asarray(time, dtype=float)
    lines = np.arange(2, time.size + 2) if lines is None else np.asarray(lines)
    if load is None and columns.load is not None:
        load = np.full(time.size, 1000.0)
    return Table(source, lines, time, np.asarray(angles, dtype=float), load, columns, quantum)


def cubic(t):
    """Angles in [deg] that are cubics of t, and their first and second derivatives."""
    t = np.asarray(t, dtype=float)
    q = np.column_stack([10 + 20 * t + 30 * t**2, 5 - 40 * t**3, 2 * t + t**2 - 10 * t**3])
    qd = np.column_stack([20 + 60 * t, -120 * t**2, 2 + 2 * t - 30 * t**2])
    qdd = np.column_stack([60 + 0 * t, -240 * t, 2 - 60 * t])
    return q, qd, qdd


T10 = np.arange(10) / 100.0


# --------------------------------------------------------------------------- derivatives and units


def test_derivatives_of_a_cubic_are_exact():
    q, qd, qdd = cubic(T10)
    trajectory = build_trajectory(table(T10, q))
    np.testing.assert_allclose(trajectory.q, np.radians(q), rtol=0, atol=1e-13)
    np.testing.assert_allclose(trajectory.qd, np.radians(qd), rtol=0, atol=1e-10)
    np.testing.assert_allclose(trajectory.qdd, np.radians(qdd), rtol=0, atol=1e-7)
    np.testing.assert_array_equal(trajectory.Fe, np.full(10, 1000.0))
    np.testing.assert_array_equal(trajectory.lines, np.arange(2, 12))
    assert trajectory.name == "f.csv" and not trajectory.periodic


def test_time_in_milliseconds_and_angles_in_radians_with_signs():
    q, qd, _ = cubic(T10)
    columns = ColumnMap(
        Column("t", "ms"),
        (Column("a", "rad", -1.0), Column("b", "rad"), Column("c", "rad")),
        False,
        Column("F", "kN", -1.0),
    )
    trajectory = build_trajectory(table(1000 * T10, q / 100, load=np.full(10, -1.5), columns=columns))
    np.testing.assert_allclose(trajectory.t, T10, rtol=1e-15)
    np.testing.assert_allclose(trajectory.q, q / 100 * [-1, 1, 1], rtol=0, atol=1e-15)
    np.testing.assert_allclose(trajectory.qd, qd / 100 * [-1, 1, 1], rtol=0, atol=1e-11)
    np.testing.assert_array_equal(trajectory.Fe, np.full(10, 1500.0))


def test_time_in_percent_of_a_cycle():
    q, _, _ = cubic(T10)
    columns = ColumnMap(Column("t", "%"), DEG.angles, False, DEG.load)
    percent = np.arange(10) * 10.0
    trajectory = quiet(lambda: build_trajectory(table(percent, q, columns=columns), period=2.0))
    np.testing.assert_allclose(trajectory.t, np.arange(10) * 0.2, rtol=1e-15)
    trajectory = quiet(lambda: build_trajectory(table(percent, q, columns=columns), frequency=4.0))
    np.testing.assert_allclose(trajectory.t, np.arange(10) * 0.025, rtol=1e-15)
    error = error_of(lambda: build_trajectory(table(percent, q, columns=columns)))
    assert str(error) == "f.csv, column 't': time is in % of the cycle: give the cycle's period or frequency"


def test_a_time_unit_left_out_is_seconds():
    q, _, _ = cubic(T10)
    columns = ColumnMap(Column("t"), (Column("a"), Column("b"), Column("c")), False, Column("F"))
    trajectory = build_trajectory(table(T10, q, columns=columns))
    np.testing.assert_array_equal(trajectory.t, T10)
    np.testing.assert_allclose(trajectory.q, np.radians(q), rtol=0, atol=1e-15)  # degrees by default


# --------------------------------------------------------------------------- time checks


def test_times_that_do_not_increase_are_named():
    t = np.array([0.0, 0.01, 0.02, 0.02, 0.04, 0.05])
    error = error_of(lambda: check_time(t, 0.0, "f.csv", np.arange(5, 11), "t", True))
    assert str(error) == "f.csv, line 8, column 't': time 0.02 s does not increase (previous 0.02 s)"
    t = np.array([0.0, 0.01, 0.02, 0.01, 0.04, 0.05])
    assert error_of(lambda: check_time(t, 0.0, "f", np.arange(6), "t", False)).line == 3


def test_an_uneven_step_is_named_and_the_tolerance_is_a_thousandth_or_the_print_resolution():
    t = np.array([0.0, 0.01, 0.02, 0.0301, 0.04, 0.05, 0.06])
    error = error_of(lambda: check_time(t, 0.0, "f.csv", np.arange(2, 9), "t", True))
    assert str(error) == (
        "f.csv, line 5, column 't': uneven time step: 0.0101 s here, 0.01 s elsewhere (a dropped or repeated sample, "
        "or clock jitter): resample the data onto an even grid"
    )
    assert check_time(t, 0.0, "f", np.arange(7), "t", False) is t  # uneven is fine when resampling
    # Within a thousandth of a step: even.
    t = np.array([0.0, 0.01, 0.02, 0.030009, 0.04, 0.05, 0.06])
    even = check_time(t, 0.0, "f", np.arange(7), "t", True)
    np.testing.assert_allclose(even, np.arange(7) * 0.01, rtol=0, atol=1e-17)
    t = np.array([0.0, 0.01, 0.02, 0.030011, 0.04, 0.05, 0.06])
    assert error_of(lambda: check_time(t, 0.0, "f", np.arange(7), "t", True)).line == 3
    # Printed to 1e-4 s: a step off by 1e-4 is even to that resolution.
    t = np.array([0.0, 0.01, 0.02, 0.0301, 0.04, 0.05, 0.06])
    np.testing.assert_allclose(check_time(t, 1e-4, "f", np.arange(7), "t", True), np.arange(7) * 0.01, atol=1e-17)
    t = np.array([0.0, 0.01, 0.02, 0.03015, 0.04, 0.05, 0.06])
    assert error_of(lambda: check_time(t, 1e-4, "f", np.arange(7), "t", True)).line == 3
    # ... but never more than a quarter step.
    t = np.array([0.0, 1.0, 2.0, 3.2, 4.0, 5.0, 6.0])
    np.testing.assert_allclose(check_time(t, 1.0, "f", np.arange(7), "t", True), np.arange(7.0), atol=1e-15)
    t = np.array([0.0, 1.0, 2.0, 3.3, 4.0, 5.0, 6.0])
    assert error_of(lambda: check_time(t, 1.0, "f", np.arange(7), "t", True)).line == 3


def test_the_step_is_the_median_not_the_mean():
    t = np.array([0.0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.07])
    error = error_of(lambda: check_time(t, 0.0, "f", np.arange(7), "t", True))
    assert error.line == 6 and "0.02 s here, 0.01 s elsewhere" in str(error)


def test_even_times_are_returned_as_they_are_to_a_millionth_of_a_step():
    t = np.arange(7) * 0.01
    assert check_time(t, 0.0, "f", np.arange(7), "t", True) is t
    wobble = t + np.array([0, 5e-9, 0, 0, 0, 0, 0])
    assert check_time(wobble, 0.0, "f", np.arange(7), "t", True) is wobble
    wobble = t + np.array([0, 2e-8, 0, 0, 0, 0, 0])
    out = check_time(wobble, 0.0, "f", np.arange(7), "t", True)
    assert out is not wobble
    np.testing.assert_allclose(out, t, rtol=0, atol=1e-17)


def test_times_in_the_wrong_unit_are_refused():
    error = error_of(lambda: check_time_unit(np.arange(10) * 10.0, "s", "f.csv", "t"))
    assert error.column == "t" and error.source == "f.csv" and "milliseconds" in str(error)
    check_time_unit(np.arange(10) * 0.01, "s", "f.csv", "t")
    check_time_unit(np.array([5.0]), "s", "f", "t")
    check_time_unit(np.array([5.0, 5.0]), "s", "f", "t")
    q, _, _ = cubic(T10)
    error = error_of(lambda: build_trajectory(table(T10 * 1000, q)))
    assert "milliseconds" in str(error) and error.column == "t"
    columns = ColumnMap(Column("t", "ms"), DEG.angles, False, DEG.load)
    error = error_of(lambda: build_trajectory(table(T10, q, columns=columns)))
    assert "the times look like seconds" in str(error)


def test_epoch_time_stamps_are_read_relative_to_the_first():
    stamps = 1.7e9 + np.arange(10) * 0.25
    with pytest.warns(TrajectoryWarning) as record:
        relative = relative_time(stamps, "f.csv", "t")
    np.testing.assert_array_equal(relative, np.arange(10) * 0.25)
    assert str(record[0].message).startswith("f.csv: column 't': the times are Unix time stamps (from 2023-11-14")
    small = np.arange(3.0)
    assert relative_time(small, "f", "t") is not None
    np.testing.assert_array_equal(relative_time(small, "f", "t"), small)
    assert relative_time(np.array([]), "f", "t").size == 0


def test_a_load_file_on_the_epoch_clock_meets_the_motion_there():
    stamps = 1.7e9 + np.arange(10) * 0.25
    q = np.column_stack([np.arange(10.0) * 3, np.arange(10.0), np.zeros(10)])
    columns = ColumnMap(DEG.time, DEG.angles)
    curve = LoadCurve(
        1.7e9 + np.array([-1.0, 0.0, 1.0, 2.0, 3.0]),
        np.array([0.0, 100.0, 200.0, 300.0, 400.0]),
        np.arange(5),
        "l",
        "F",
    )
    trajectory = quiet(lambda: build_trajectory(table(stamps, q, columns=columns), load_curve=curve))
    np.testing.assert_allclose(trajectory.Fe, 100.0 + 100.0 * np.arange(10) * 0.25, rtol=1e-12)
    np.testing.assert_array_equal(trajectory.t, np.arange(10) * 0.25)


# --------------------------------------------------------------------------- arguments


@pytest.mark.parametrize("value", ["1", True, -1.0, 0, math.nan, math.inf, None])
def test_a_rate_period_or_weight_must_be_a_positive_number(value):
    error = error_of(lambda: _positive(value, "resample rate", "Hz", "f.csv"))
    assert str(error) == f"f.csv: resample rate must be a positive number of Hz, got {value!r}"


def test_positive_numbers_and_the_cycle():
    assert _positive(3, "x", "s", "f") == 3.0 and isinstance(_positive(3, "x", "s", "f"), float)
    assert _cycle_period(4.0, None, "f") == 0.25
    assert _cycle_period(None, 2.0, "f") == 2.0
    assert _cycle_period(None, None, "f") is None
    assert (
        str(error_of(lambda: _cycle_period(1.0, 1.0, "f"))) == "f: give the cycle's frequency or its period, not both"
    )
    assert (
        str(error_of(lambda: _cycle_period(-1.0, None, "f")))
        == "f: cycle frequency must be a positive number of Hz, got -1.0"
    )
    assert str(error_of(lambda: _cycle_period(None, 0, "f"))) == "f: cycle period must be a positive number of s, got 0"
    q, _, _ = cubic(T10)
    assert "resample rate must be" in str(error_of(lambda: build_trajectory(table(T10, q), resample=0.0)))


# --------------------------------------------------------------------------- angles


def test_angles_beyond_a_turn_are_named_where_they_are():
    q = np.column_stack([np.arange(10.0), np.zeros(10), np.zeros(10)])
    q[4, 1] = -400.0
    error = error_of(lambda: build_trajectory(table(T10, q)))
    assert str(error) == "f.csv, line 6, column 'b': -400° is more than a full turn"
    q[4, 1] = 360.0
    assert quiet(lambda: build_trajectory(table(T10, q))).q[4, 1] == pytest.approx(2 * math.pi)
    columns = ColumnMap(DEG.time, (Column("a", "rad"), Column("b", "rad"), Column("c", "rad")), False, DEG.load)
    q = np.column_stack([np.arange(10.0) * 0.1, np.zeros(10), np.zeros(10)])
    q[7, 2] = -3.5
    error = error_of(lambda: build_trajectory(table(T10, q, columns=columns)))
    assert str(error) == "f.csv, line 9, column 'c': -3.5 rad is more than half a turn: these look like degrees"
    q[7, 2] = -3.14
    assert quiet(lambda: build_trajectory(table(T10, q, columns=columns))).q[7, 2] == pytest.approx(-3.14, abs=1e-12)


def test_radians_under_degrees_are_refused_and_tiny_spans_warned_of():
    q = np.column_stack([np.linspace(0, 0.6, 10), np.linspace(0, 0.2, 10), np.linspace(0, -0.1, 10)])
    error = error_of(lambda: build_trajectory(table(T10, q)))
    assert str(error) == (
        "f.csv, column 'a': the angles look like radians: the widest spans 0.6°, a gait's 34.4° if read as radians; "
        "label them in rad (_rad, or :rad in --columns)"
    )
    # One angle in radians: the others, in degrees, are not judged as a gait's.
    columns = ColumnMap(DEG.time, (Column("a", "rad"), Column("b", "deg"), Column("c", "deg")), False, DEG.load)
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(T10, q, columns=columns))
    assert str(record[0].message) == (
        "f.csv: the angles span less than a degree (at most 0.2° in 'b'): if they are radians, label them so"
    )
    q = np.column_stack([np.linspace(0, 0.05, 10), np.zeros(10), np.zeros(10)])
    with pytest.warns(TrajectoryWarning, match="at most 0.05° in 'a'"):
        build_trajectory(table(T10, q))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_trajectory(table(T10, np.zeros((10, 3))))  # a still pose: no span, no warning
        build_trajectory(table(T10, np.column_stack([np.linspace(0, 1.0, 10), np.zeros(10), np.zeros(10)])))


def test_a_hip_chain_is_turned_into_the_platform_angles_and_unwrapped():
    columns = ColumnMap(DEG.time, (Column("fl", "deg"), Column("ad", "deg"), Column("ro", "deg")), True, DEG.load)
    flexion = np.array([170.0, 175, 179, 181, 185, 190, 195, 200, 205, 210])
    q = np.column_stack([flexion, np.zeros(10), np.zeros(10)])
    trajectory = quiet(lambda: build_trajectory(table(T10, q, columns=columns)))
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(flexion), rtol=0, atol=1e-12)


# --------------------------------------------------------------------------- the load


def test_the_load_in_each_unit():
    q, _, _ = cubic(T10)
    load = np.full(10, 150.0)
    for unit, weight, expected in (
        ("N", None, 150.0),
        ("kN", None, 150e3),
        ("%BW", 800.0, 1200.0),
        (None, 800.0, 1200.0),
    ):
        columns = ColumnMap(DEG.time, DEG.angles, False, Column("F", unit))
        got = quiet(lambda: build_trajectory(table(T10, q, load=load, columns=columns), body_weight=weight))
        np.testing.assert_allclose(got.Fe, expected, rtol=1e-15)


def test_a_load_without_a_unit_or_body_weight_is_named():
    q, _, _ = cubic(T10)
    cases = [
        (
            Column("Fz [%BW]"),
            None,
            "f.csv, column 'Fz [%BW]': the load column's name says %BW, but it would be read as N: give the body weight (--body-weight, in kg or N)",
        ),
        (
            Column("Fz_kN"),
            None,
            "f.csv, column 'Fz_kN': the load column's name says kN, but it would be read as N: map it with its unit, load=Fz_kN:kN",
        ),
        (
            Column("F", "%BW"),
            None,
            "f.csv, column 'F': the load is in % body weight: give the body weight (--body-weight, in kg or N)",
        ),
        (Column("F", "kN"), 700.0, "f.csv, column 'F': a body weight was given, but the load is in kN"),
        (None, 700.0, "f.csv: a body weight was given, but no load column"),
        (Column("F"), -5.0, "f.csv: body weight must be a positive number of N, got -5.0"),
    ]
    for column, weight, message in cases:
        columns = ColumnMap(DEG.time, DEG.angles, False, column)
        load = np.full(10, 1.5) if column is not None else None
        assert (
            str(error_of(lambda: build_trajectory(table(T10, q, load=load, columns=columns), body_weight=weight)))
            == message
        )
    columns = ColumnMap(DEG.time, DEG.angles, False, Column("Fz_kN", "kN"))
    np.testing.assert_allclose(build_trajectory(table(T10, q, load=np.full(10, 1.5), columns=columns)).Fe, 1500.0)


def test_negative_slipped_and_huge_loads_are_named():
    q, _, _ = cubic(T10)
    load = np.full(10, 1000.0)
    load[6] = -3.0
    error = error_of(lambda: build_trajectory(table(T10, q, load=load)))
    assert str(error) == (
        "f.csv, line 8, column 'F': load -3 N is negative (F_e is a magnitude: flip the column's sign if it is a "
        "compressive component)"
    )
    error = error_of(lambda: build_trajectory(table(T10, q, load=np.full(10, 2.0))))
    assert error.column == "F" and "the load looks like kN" in str(error)
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(T10, q, load=np.full(10, 50.0)))
    assert str(record[0].message).startswith("f.csv: column 'F': the load peaks at 50 N, far below")
    load = np.full(10, 1000.0)
    load[3] = 2e9
    error = error_of(lambda: build_trajectory(table(T10, q, load=load)))
    assert str(error) == "f.csv, line 5, column 'F': load 2e+09 N is beyond 1e+09 N (a unit slip?)"
    assert MAX_LOAD == 1e9
    load[3] = 1e9
    assert quiet(lambda: build_trajectory(table(T10, q, load=load))).Fe[3] == 1e9
    zero = build_trajectory(table(T10, q, load=np.zeros(10)))
    np.testing.assert_array_equal(zero.Fe, 0.0)


def test_no_load_column_is_warned_of_and_a_load_file_fills_it():
    q, _, _ = cubic(T10)
    columns = ColumnMap(DEG.time, DEG.angles)
    with pytest.warns(NoLoadWarning) as record:
        trajectory = build_trajectory(table(T10, q, columns=columns))
    assert str(record[0].message) == (
        "f.csv: no load column: F_e = 0 N, so the friction parts are those of an unloaded machine "
        "(give the load: a Fe_N column, --load-column or --load)"
    )
    np.testing.assert_array_equal(trajectory.Fe, np.zeros(10))
    curve = LoadCurve(np.array([0.02, 0.05, 0.08]), np.array([100.0, 400.0, 700.0]), np.array([2, 3, 4]), "l.csv", "F")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        trajectory = build_trajectory(table(T10, q, columns=columns), load_curve=curve)
    assert not [w for w in caught if issubclass(w.category, NoLoadWarning)]
    np.testing.assert_allclose(trajectory.t, T10[2:9], rtol=1e-15)
    np.testing.assert_allclose(trajectory.Fe, 100.0 + 10000.0 * (T10[2:9] - 0.02), rtol=1e-12)
    np.testing.assert_array_equal(trajectory.lines, np.arange(4, 11))
    np.testing.assert_allclose(trajectory.q, np.radians(q[2:9]), rtol=0, atol=1e-13)
    error = error_of(lambda: build_trajectory(table(T10, q), load_curve=curve))
    assert str(error) == "f.csv, column 'F': a load column and a load file are both given: which is the load?"


# --------------------------------------------------------------------------- periodicity


def closing_sine(n=9, load=None):
    t = np.arange(n) / (n - 1)
    q = np.column_stack([30 * np.sin(2 * np.pi * t), 10 * np.cos(2 * np.pi * t), 5 * np.sin(4 * np.pi * t)])
    return t, q


def test_a_last_row_that_repeats_the_first_with_its_slope_is_periodic():
    t, q = closing_sine()
    trajectory = build_trajectory(table(t, q))
    assert trajectory.periodic and len(trajectory) == 8
    np.testing.assert_array_equal(trajectory.t, t[:-1])
    assert build_trajectory(table(t, q), periodic=False).periodic is False
    assert len(build_trajectory(table(t, q), periodic=False)) == 9
    q_rad = np.radians(q)
    assert _closes_on_itself(q_rad, np.full(9, 1000.0))
    # Values that come back with another slope (out and back), a load that does not, are not periodic.
    u = np.arange(41) / 40
    back = np.column_stack([u * (1 - u)] * 3)  # out and back: leaves rising, arrives falling
    assert not _closes_on_itself(back, np.zeros(41))
    load = np.full(9, 1000.0)
    load[-1] = 1000.001
    assert not _closes_on_itself(q_rad, load)
    load[-1] = 1000.0 + 5e-7
    assert _closes_on_itself(q_rad, load)
    shifted = q_rad.copy()
    shifted[-1, 1] += 1.5e-9  # beyond 1e-9 of the largest angle (under 1 rad: of 1), with no share of 0.17 rad
    assert not _closes_on_itself(shifted, np.zeros(9))
    shifted[-1, 1] = shifted[0, 1] + 5e-10
    assert _closes_on_itself(shifted, np.zeros(9))


def test_closing_tolerances_scale_with_the_largest_angle_and_load():
    t = np.arange(9) / 8
    big = 1000.0 * np.column_stack([np.sin(2 * np.pi * t)] * 3)
    big[-1] = big[0] + 5e-7  # within 1e-9 of the largest angle, 1000
    assert _closes_on_itself(big, np.zeros(9))
    load = np.full(9, 1e6)
    load[-1] += 5e-4  # within 1e-9 of the largest load
    assert _closes_on_itself(big, load)
    load[-1] += 1e-3
    assert not _closes_on_itself(big, load)
    # The slopes across the wrap must agree to within ten times the largest second difference: for
    # u(1 − u) at steps h they differ by 2h(1 − h), its second differences are 2h², so it closes for h ≥ 1/11.
    for n, closes in ((11, True), (14, False)):
        u = np.arange(n) / (n - 1)
        assert _closes_on_itself(np.column_stack([u * (1 - u)] * 3), np.zeros(n)) is closes
    still = np.zeros((9, 3))
    assert _closes_on_itself(still, np.zeros(9))


def test_periodic_asked_of_an_open_file_is_named_at_its_last_line():
    q, _, _ = cubic(T10)
    error = error_of(lambda: build_trajectory(table(T10, q), periodic=True))
    assert str(error) == (
        "f.csv, line 11: periodic was asked for, but the last row does not repeat the first (angles, load and slope)"
    )


def test_a_periodic_table_has_periodic_derivatives():
    t, q = closing_sine(n=65)
    trajectory = build_trajectory(table(t, q))
    w = 2 * np.pi
    expected = np.radians(
        np.column_stack([30 * w * np.cos(w * t), -10 * w * np.sin(w * t), 5 * 2 * w * np.cos(2 * w * t)])
    )[:-1]
    np.testing.assert_allclose(trajectory.qd, expected, rtol=0, atol=2e-5 * np.abs(expected).max())


# --------------------------------------------------------------------------- rescaling and strides


def test_rescaling_to_a_frequency_counts_the_closing_step():
    t, q = closing_sine()
    trajectory = build_trajectory(table(t * 2.0, q), frequency=2.0)  # a 2 s cycle made 0.5 s
    np.testing.assert_allclose(trajectory.t, np.arange(8) / 16.0, rtol=0, atol=1e-15)
    q, _, _ = cubic(T10)
    trajectory = quiet(lambda: build_trajectory(table(T10 + 1.0, q), period=1.0))  # ten samples, plus one step
    np.testing.assert_allclose(trajectory.t, 1.0 + np.arange(10) * 0.1, rtol=0, atol=1e-15)
    np.testing.assert_allclose(trajectory.qd, np.radians(cubic(T10)[1]) / 10.0, rtol=0, atol=1e-10)


def test_strides_are_counted_with_hysteresis():
    t = np.arange(9.0)
    assert stride_count(t, np.array([0, 10, 0, 10, 0, 10, 0, 10, 0.0])) == (4, 2.0)
    assert stride_count(t, np.array([0, 6, 4, 6, 4, 6, 4, 10, 0.0])) == (1, None)  # 6 is not above 7.5
    assert stride_count(t, np.array([5.0] * 9)) == (0, None)
    assert stride_count(t, np.array([10, 0, 7.4, 2.6, 7.6, 0, 10, 0, 0.0])) == (2, 2.0)
    assert stride_count(t, np.array([0, 10, 10, 10, 0, 0, 10, 0, 0.0]))[0] == 2


def test_several_strides_or_part_of_one_rescaled_as_a_cycle_are_warned_of():
    t = np.arange(41) / 10.0
    strides = np.column_stack([20 * np.sin(2 * np.pi * t), np.zeros(41), np.zeros(41)])
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(t, strides), period=1.0)
    assert str(record[0].message) == (
        "f.csv: the file holds about 4 strides (one alpha cycle every 1 s of its time, over 4 s), but "
        "--frequency/--period rescale the whole file as one cycle: each stride then runs that much faster; cut one "
        "stride out, or scale the period by the stride count"
    )
    part = np.column_stack([np.zeros(11), np.linspace(0, 30, 11), np.zeros(11)])
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(np.arange(11) / 10.0, part), period=1.0)
    assert str(record[0].message) == (
        "f.csv: the motion does not come back to its start (beta starts at 0° and ends at 30°, 100 % of its range "
        "away): part of a stride, rescaled as a whole cycle by --frequency/--period"
    )
    t, q = closing_sine()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_trajectory(table(t, q), period=1.0)  # one whole stride
        build_trajectory(table(np.arange(11) / 10.0, part))  # not rescaled
    nearly = np.column_stack([np.zeros(9), [0, 10, 20, 30, 40, 30, 20, 10, 10.0], np.zeros(9)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_trajectory(table(np.arange(9) / 10.0, nearly), period=1.0)  # 25 % of its range away: not warned


# --------------------------------------------------------------------------- resampling and filtering


def test_resampling_onto_an_even_grid():
    q, qd, _ = cubic(T10)
    uneven = T10 + np.array([0, 0.002, 0, -0.001, 0, 0, 0.003, 0, 0, 0])
    q, qd, _ = cubic(uneven)
    trajectory = build_trajectory(table(uneven, q, load=1000.0 + 1000.0 * uneven), resample=200.0)
    grid = np.arange(19) / 200.0
    np.testing.assert_allclose(trajectory.t, grid, rtol=0, atol=1e-15)
    np.testing.assert_allclose(trajectory.q, np.radians(cubic(grid)[0]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(trajectory.qd, np.radians(cubic(grid)[1]), rtol=0, atol=1e-9)
    np.testing.assert_allclose(trajectory.Fe, 1000.0 + 1000.0 * grid, rtol=1e-14)
    assert trajectory.lines is None
    error = error_of(lambda: build_trajectory(table(uneven, q), resample=50.0))
    assert str(error) == "f.csv: resampling 0.09 s at 50 Hz gives 5 samples; at least 6 are needed"
    assert len(build_trajectory(table(uneven, q), resample=55.6)) == 6  # 0.09 s × 55.6 Hz = 5.004 steps


def test_a_periodic_resampled_grid_keeps_a_whole_period():
    t, q = closing_sine()
    trajectory = build_trajectory(table(t, q), resample=10.0)
    np.testing.assert_allclose(trajectory.t, np.arange(10) / 10.0, rtol=0, atol=1e-15)
    assert trajectory.periodic
    motion = _resampled(t, np.radians(q), np.full(9, 1.0), 7.4, True, "f")
    np.testing.assert_allclose(motion.t, np.arange(7) / 7.0, rtol=0, atol=1e-15)  # round(7.4) = 7 steps of 1/7 s
    assert motion.lines is None and len(motion) == 7


def test_the_lazy_motion_gives_pieces_of_the_one_spline():
    q, qd, qdd = cubic(T10)
    motion = build_trajectory(table(T10, q), lazy=True)
    assert isinstance(motion, SampledMotion) and len(motion) == 10
    piece = motion.piece(3, 7)
    np.testing.assert_allclose(piece.qd, np.radians(qd[3:7]), rtol=0, atol=1e-10)
    np.testing.assert_array_equal(piece.lines, np.arange(5, 9))
    np.testing.assert_array_equal(piece.Fe, np.full(4, 1000.0))
    assert piece.name == "f.csv" and not piece.periodic
    t, q = closing_sine()
    load = 300.0 + 100.0 * np.sin(2 * np.pi * t) ** 2  # 350 N at t = 1/8, 400 N at 1/4
    motion = build_trajectory(table(t, q, load=load), lazy=True, resample=16.0)
    assert motion.lines is None and len(motion) == 16
    piece = motion.piece(2, 4)
    np.testing.assert_allclose(piece.Fe, [350.0, 375.0], rtol=1e-14)
    assert piece.lines is None
    whole = motion.trajectory()
    assert whole.periodic and len(whole) == 16


def test_a_cutoff_filters_the_angles_and_not_the_load():
    t = np.arange(101) / 100.0
    slow = 20 * np.sin(2 * np.pi * t)
    fast = 2 * np.sin(2 * np.pi * 40 * t)
    q = np.column_stack([slow + fast, slow, slow])
    load = 1000.0 + 100.0 * np.sin(2 * np.pi * 40 * t)
    trajectory = quiet(lambda: build_trajectory(table(t, q, load=load), cutoff=6.0, periodic=False))
    inner = slice(30, 70)
    assert np.abs(np.degrees(trajectory.q[inner, 0]) - slow[inner]).max() < 0.1
    np.testing.assert_array_equal(trajectory.Fe, load)
    # With resampling first: the filter runs on the grid (here the same times: 100 Hz).
    resampled = quiet(lambda: build_trajectory(table(t, q, load=load), cutoff=6.0, resample=100.0))
    assert np.abs(np.degrees(resampled.q[inner, 0]) - slow[inner]).max() < 0.1
    assert resampled.periodic  # the file closes (40 Hz whole in one second): the grid holds one period
    np.testing.assert_allclose(resampled.t, t[:-1], rtol=0, atol=1e-14)
    np.testing.assert_allclose(resampled.Fe, load[:-1], rtol=1e-12)


def test_percent_times_are_even_to_their_printed_resolution_in_the_cycle():
    q, _, _ = cubic(T10)
    columns = ColumnMap(Column("t", "%"), DEG.angles, False, DEG.load)
    percent = np.arange(10) * 10.0
    percent[4] += 0.05  # printed to 0.1 %: even
    trajectory = quiet(lambda: build_trajectory(table(percent, q, columns=columns, quantum=0.1), period=1.0))
    np.testing.assert_allclose(trajectory.t, np.arange(10) * 0.1, rtol=0, atol=1e-15)
    percent[4] += 1.95  # 2 % off: a fifth of a step
    error = error_of(lambda: build_trajectory(table(percent, q, columns=columns, quantum=0.1), period=1.0))
    assert error.line == 6 and "uneven time step" in str(error)


def test_two_strides_are_warned_of_and_two_crossings_a_cycle_apart_are_not():
    t = np.arange(21) / 20.0
    two = np.column_stack([-20 * np.cos(4 * np.pi * t), np.zeros(21), np.zeros(21)])  # risen at 1/8 and 5/8 s
    with pytest.warns(TrajectoryWarning, match="holds about 2 strides"):
        build_trajectory(table(t, two), period=1.0)
    # Risen at 0.05 s and at 0.95 s: the interval, 0.9 s, is more than three quarters of the file's 1 s.
    ends = np.zeros((21, 3))
    ends[1, 0] = ends[19, 0] = 10.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_trajectory(table(t, ends), period=1.0)


def test_a_cutoff_is_the_records_low_pass_at_the_files_rate():
    t = np.arange(41) / 50.0  # 50 Hz
    q = np.column_stack([20 * np.sin(2 * np.pi * t) + np.sin(2 * np.pi * 20 * t), 5 * t, np.zeros(41)])
    trajectory = quiet(lambda: build_trajectory(table(t, q), cutoff=5.0))
    expected = lowpass_record(np.radians(q), 50.0, 5.0, False)
    np.testing.assert_allclose(trajectory.q, expected, rtol=0, atol=1e-9)
    # A periodic file is filtered wrapped around.
    t = np.arange(51) / 50.0
    q = np.column_stack([20 * np.sin(2 * np.pi * t) + np.sin(2 * np.pi * 20 * t), np.zeros(51), np.zeros(51)])
    trajectory = quiet(lambda: build_trajectory(table(t, q), cutoff=5.0))
    assert trajectory.periodic
    expected = lowpass_record(np.radians(q), 50.0, 5.0, True)
    np.testing.assert_allclose(trajectory.q, expected[:-1], rtol=0, atol=1e-9)


def test_noisy_angles_are_warned_of_without_a_cutoff_only():
    t = np.arange(40) / 100.0
    q = np.column_stack([10 + 0.5 * (-1.0) ** np.arange(40), np.arange(40.0), -np.arange(40.0)])
    with pytest.warns(NoiseWarning) as record:
        build_trajectory(table(t, q))
    noise = [str(w.message) for w in record if issubclass(w.category, NoiseWarning)]
    assert len(noise) == 1 and noise[0].startswith("f.csv: ") and noise[0].endswith("--cutoff 6")
    with warnings.catch_warnings():
        warnings.simplefilter("error", NoiseWarning)
        build_trajectory(table(t, q), cutoff=6.0)


# --------------------------------------------------------------------------- survivors of the first run


def test_strides_of_an_angle_away_from_zero_and_the_edges_of_the_band():
    t = np.arange(7.0)
    # 10 to 20: mid 15, band 2.5 (a quarter of the range, not of the sum).
    assert stride_count(t, np.array([10, 20, 10, 20, 10, 20, 10.0])) == (3, 2.0)
    assert stride_count(t, np.array([10, 20, 16, 20, 10, 20, 10.0])) == (2, 4.0)
    t = np.arange(6.0)
    assert stride_count(t, np.array([0, 10, 2.5, 10, 0, 10.0])) == (2, 4.0)  # 2.5 is not below 2.5: not armed
    assert stride_count(t, np.array([0, 10, 6, 10, 0, 10.0])) == (2, 4.0)  # 6 is between: not armed
    assert stride_count(t, np.array([0, 10, 0, 7.5, 0, 10.0])) == (2, 4.0)  # 7.5 is not above 7.5


@pytest.mark.parametrize(("k", "name"), [(0, "alpha"), (1, "beta"), (2, "gamma")])
def test_the_stride_warnings_name_the_widest_angle(k, name):
    t = 1.0 + np.arange(41) / 10.0  # a file that starts at 1 s
    strides = np.zeros((41, 3))
    strides[:, k] = 20 * np.sin(2 * np.pi * t)
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(t, strides), period=1.0)
    assert str(record[0].message).startswith(
        f"f.csv: the file holds about 4 strides (one {name} cycle every 1 s of its time, over 4 s)"
    )
    part = np.zeros((11, 3))
    part[:, k] = np.linspace(10, 30, 11)  # 20° from 10°: 0.35 rad, more than a quarter of its range
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(1.0 + np.arange(11) / 10.0, part), period=1.0)
    assert str(record[0].message).startswith(
        f"f.csv: the motion does not come back to its start ({name} starts at 10° and ends at 30°, 100 % of its range"
    )


def test_two_crossings_three_quarters_of_the_file_apart_are_one_stride():
    t = np.arange(9) * 0.5  # 4 s
    q = np.zeros((9, 3))
    q[1, 0] = q[7, 0] = 10.0  # risen at 0.5 s and 3.5 s: 3 s apart, exactly 3/4 of the file
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        build_trajectory(table(t, q), period=1.0)


def test_a_resampled_motion_keeps_its_name_start_and_periodic_spline():
    q, _, _ = cubic(T10)
    trajectory = build_trajectory(table(1.0 + T10, q), resample=200.0)
    assert trajectory.name == "f.csv"
    np.testing.assert_allclose(trajectory.t, 1.0 + np.arange(19) / 200.0, rtol=0, atol=1e-14)
    # A periodic file resampled at its own rate is its own samples, through the same periodic spline.
    t, q = closing_sine(n=33)
    whole = build_trajectory(table(t, q))
    resampled = build_trajectory(table(t, q), resample=32.0)
    assert resampled.periodic and len(resampled) == 32
    np.testing.assert_allclose(resampled.qd, whole.qd, rtol=0, atol=1e-12)
    np.testing.assert_allclose(resampled.qdd, whole.qdd, rtol=0, atol=1e-10)


def test_closing_tolerances_of_small_loads_and_each_angles_own_curvature():
    t, q = closing_sine()
    q_rad = np.radians(q)
    load = np.full(9, 0.5)
    load[-1] += 1.5e-9  # beyond 1e-9 of 1 N (a load under 1 N counts as 1)
    assert not _closes_on_itself(q_rad, load)
    # An angle that comes back with another slope is not excused by another angle's larger curvature.
    u = np.arange(41) / 40
    mixed = np.column_stack([np.sin(2 * np.pi * u), 1e-3 * u * (1 - u), np.zeros(41)])
    assert not _closes_on_itself(mixed, np.zeros(41))


def test_the_edges_of_a_turn_and_the_widest_angle_named():
    columns = ColumnMap(DEG.time, (Column("a", "rad"), Column("b", "rad"), Column("c", "rad")), False, DEG.load)
    q = np.column_stack([np.arange(10.0) * 0.1, np.zeros(10), np.zeros(10)])
    q[5, 1] = math.pi  # half a turn exactly is allowed
    assert quiet(lambda: build_trajectory(table(T10, q, columns=columns))).q[5, 1] == pytest.approx(math.pi, abs=1e-12)
    q = np.column_stack([np.arange(10.0), np.zeros(10), np.zeros(10)])
    q[5, 2] = 360.5
    assert (
        str(error_of(lambda: build_trajectory(table(T10, q))))
        == "f.csv, line 7, column 'c': 360.5° is more than a full turn"
    )
    q = np.column_stack([np.linspace(0, 0.05, 10), np.linspace(0, 0.3, 10), np.zeros(10)])
    error = error_of(lambda: build_trajectory(table(T10, q)))
    assert str(error).startswith(
        "f.csv, column 'b': the angles look like radians: the widest spans 0.3°, a gait's 17.2°"
    )


def test_the_first_negative_or_huge_load_is_named_and_slips_by_unit():
    q, _, _ = cubic(T10)
    load = np.full(10, 1000.0)
    load[3], load[6] = 0.0, -3.0
    assert error_of(lambda: build_trajectory(table(T10, q, load=load))).line == 8
    load = np.full(10, 1000.0)
    load[2], load[3] = 1e9, 2e9
    assert error_of(lambda: build_trajectory(table(T10, q, load=load))).line == 5
    columns = ColumnMap(DEG.time, DEG.angles, False, Column("F", "kN"))
    error = error_of(lambda: build_trajectory(table(T10, q, load=np.full(10, 1500.0), columns=columns)))
    assert str(error).startswith("f.csv, column 'F': the load looks like N read as kN: its peak is 1.5e+06 N")
    error = error_of(lambda: build_trajectory(table(T10, q, load=np.full(10, 2.0))))
    assert str(error).startswith("f.csv, column 'F': the load looks like kN: its peak is 2 N")


def test_the_tiny_span_warning_names_the_widest_degree_angle():
    columns = ColumnMap(DEG.time, (Column("a", "rad"), Column("b", "deg"), Column("c", "deg")), False, DEG.load)
    q = np.column_stack([np.linspace(0, 0.5, 10), np.linspace(0, 0.05, 10), np.linspace(0, 0.3, 10)])
    with pytest.warns(TrajectoryWarning, match="at most 0.3° in 'c'"):
        build_trajectory(table(T10, q, columns=columns))


def test_messages_of_the_arguments_name_the_file():
    q, _, _ = cubic(T10)
    assert str(error_of(lambda: build_trajectory(table(T10, q), resample=-1))) == (
        "f.csv: resample rate must be a positive number of Hz, got -1"
    )
    assert str(error_of(lambda: build_trajectory(table(T10, q), frequency=1.0, period=1.0))) == (
        "f.csv: give the cycle's frequency or its period, not both"
    )
    assert str(error_of(lambda: build_trajectory(table(T10, q), cutoff=6.0, resample=50.0))) == (
        "f.csv: resampling 0.09 s at 50 Hz gives 5 samples; at least 6 are needed"
    )
    assert str(error_of(lambda: build_trajectory(table(T10, q), cutoff=60.0))) == (
        "f.csv: the low-pass cutoff 60 Hz is not below the Nyquist frequency 50 Hz of a 100 Hz log"
    )
    curve = LoadCurve(np.array([5.0, 6.0]), np.array([0.0, 1.0]), np.array([2, 3]), "l.csv", "F")
    columns = ColumnMap(DEG.time, DEG.angles)
    assert str(error_of(lambda: build_trajectory(table(T10, q, columns=columns), load_curve=curve))) == (
        "l.csv, column 'F': no overlapping time: the motion f.csv covers 0 to 0.09 s, the load 5 to 6 s"
    )
    error = error_of(lambda: build_trajectory(table(T10 * 1000, q)))
    assert str(error).startswith("f.csv, column 't': the times look like milliseconds")
    with pytest.warns(TrajectoryWarning) as record:
        build_trajectory(table(1.7e9 + T10 * 100, q))
    assert str(record[0].message).startswith("f.csv: column 't': the times are Unix time stamps")


def test_a_cutoff_on_a_file_that_starts_late_uses_its_own_step():
    t = 1.0 + np.arange(41) / 50.0
    q = np.column_stack([20 * np.sin(2 * np.pi * t) + np.sin(2 * np.pi * 20 * t), 5 * t, np.zeros(41)])
    trajectory = quiet(lambda: build_trajectory(table(t, q), cutoff=5.0))
    np.testing.assert_allclose(trajectory.q, lowpass_record(np.radians(q), 50.0, 5.0, False), rtol=0, atol=1e-9)


def test_percent_times_of_part_of_a_cycle_and_their_resolution_in_seconds():
    q, _, _ = cubic(T10)
    columns = ColumnMap(Column("t", "%"), DEG.angles, False, DEG.load)
    half = np.arange(10) * 5.0  # 0 to 45 % of a 1 s cycle: not rescaled again
    trajectory = quiet(lambda: build_trajectory(table(half, q, columns=columns), period=1.0))
    np.testing.assert_allclose(trajectory.t, np.arange(10) * 0.05, rtol=0, atol=1e-15)
    # Printed to 0.1 % of a 2 s cycle: 2 ms; a time 0.0995 % (1.99 ms) off is even to it.
    percent = np.arange(10) * 10.0
    percent[4] += 0.0995
    trajectory = quiet(lambda: build_trajectory(table(percent, q, columns=columns, quantum=0.1), period=2.0))
    np.testing.assert_allclose(trajectory.t, np.arange(10) * 0.2, rtol=0, atol=1e-14)
    # A load file on the cycle's clock: percent times have no epoch.
    curve = LoadCurve(np.array([0.0, 2.0]), np.array([0.0, 2000.0]), np.array([2, 3]), "l.csv", "F")
    plain = ColumnMap(Column("t", "%"), DEG.angles)
    trajectory = quiet(
        lambda: build_trajectory(table(percent, q, columns=plain, quantum=0.1), period=2.0, load_curve=curve)
    )
    np.testing.assert_allclose(trajectory.Fe, 1000.0 * trajectory.t, rtol=1e-12)


def test_milliseconds_since_a_late_start_meet_a_load_file_in_seconds_and_keep_their_resolution():
    q, _, _ = cubic(T10)
    columns = ColumnMap(Column("t", "ms"), DEG.angles)
    stamps = 2e8 + 10.0 * np.arange(10)  # ms: read as from an epoch, 2e5 s
    curve = LoadCurve(2e5 + np.array([-1.0, 1.0]), np.array([0.0, 2000.0]), np.array([2, 3]), "l.csv", "F")
    trajectory = quiet(lambda: build_trajectory(table(stamps, q, columns=columns), load_curve=curve))
    np.testing.assert_allclose(trajectory.Fe, 1000.0 * (1.0 + T10), rtol=1e-9)
    # Printed in whole ms: a step 2 ms off (a fifth) is not even to 1 ms.
    times = 10.0 * np.arange(10)
    times[4] += 2.0
    columns = ColumnMap(Column("t", "ms"), DEG.angles, False, DEG.load)
    error = error_of(lambda: build_trajectory(table(times, q, columns=columns, quantum=1.0)))
    assert error.line == 6 and "uneven time step" in str(error)


def test_two_times_are_enough_to_tell_milliseconds_and_the_first_time_tells_an_epoch():
    error = error_of(lambda: check_time_unit(np.array([0.0, 100.0]), "s", "f.csv", "t"))
    assert "the times look like milliseconds" in str(error)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(relative_time(np.array([5e7, 2e8]), "f", "t"), [5e7, 2e8])


def test_a_long_files_times_are_evened_block_by_block():
    # 70 000 times: two blocks of 65 536; a wobble of 5e-8 s in the second is within the step's thousandth
    # (even) but beyond its millionth (so the even grid is returned).
    t = np.arange(70_000) * 1e-3
    t[69_000] += 5e-8
    out = check_time(t, 0.0, "f", np.arange(70_000), "t", True)
    assert out is not t
    np.testing.assert_allclose(out, np.arange(70_000) * (t[-1] / 69_999), rtol=0, atol=1e-12)
    assert abs(out[69_000] - 69.0) < 1e-12


def test_a_load_file_meets_a_motion_that_starts_late_on_the_same_clock():
    q, _, _ = cubic(T10)
    columns = ColumnMap(DEG.time, DEG.angles)
    curve = LoadCurve(np.array([0.0, 2.0]), np.array([0.0, 2000.0]), np.array([2, 3]), "l.csv", "F")
    trajectory = build_trajectory(table(1.0 + T10, q, columns=columns), load_curve=curve)
    np.testing.assert_allclose(trajectory.Fe, 1000.0 * (1.0 + T10), rtol=1e-12)

"""hipsim/plausibility.py at the edge of every range: each comparison on its limit and just past it, the factor a slip
is named by, and every message whole. The values are chosen by hand so that each limit decides (a 50 s span read as
ms is 0.05 s, exactly the shortest plausible motion; 1e8 s is 3 March 1973, 09:46:40 UTC)."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from hipsim.plausibility import (
    below,
    beyond,
    drive_slip,
    epoch_warning,
    factor_name,
    load_slip,
    one_radians_slip,
    radians_slip,
    time_slip,
    unit_slip,
)

DEG = 180.0 / math.pi


def test_rounding_at_a_negative_limit_is_relative_to_its_size():
    assert not beyond(-1.0 + 0.5e-9, -1.0) and beyond(-1.0 + 2e-9, -1.0)
    assert not below(-1.0 - 0.5e-9, -1.0) and below(-1.0 - 2e-9, -1.0)
    assert beyond(1.0 + 1e-12, 1.0, rel=0.0) and below(1.0 - 1e-12, 1.0, rel=0.0)
    assert not beyond(1.0, 1.0, rel=0.0) and not below(1.0, 1.0, rel=0.0)  # on the limit is not past it
    assert not beyond(1.05, 1.0, rel=0.1) and not below(0.95, 1.0, rel=0.1)
    assert beyond(2.0, 1.0) is True and below(2.0, 1.0) is False  # a bool, not a NumPy scalar
    np.testing.assert_array_equal(below(np.array([1.0, 1.0 - 2e-9, 0.5]), 1.0), [False, True, True])


def test_a_unit_slip_at_each_edge():
    assert unit_slip(0.01, 0.01, 300.0) is None and unit_slip(300.0, 0.01, 300.0) is None  # the range's own edges
    assert unit_slip(0.0, 0.01, 300.0) is None
    assert unit_slip(math.inf, 0.01, 300.0) is None and unit_slip(math.nan, 0.01, 300.0) is None
    assert unit_slip(10.0, 0.01, 300.0) is None
    assert unit_slip(1.0, 10.0, 3000.0) == 1e-3  # one, read a thousandth
    assert unit_slip(-1910.0, 0.01, 300.0) == 1e3  # a magnitude
    assert unit_slip(300e3, 0.01, 300.0) == 1e3 and unit_slip(300.1e3, 0.01, 300.0) is None
    assert unit_slip(0.0099, 0.01, 300.0) == 1e-3 and unit_slip(0.3, 1.0, 300.0) == 1e-3
    assert unit_slip(10.0, 0.01, 300.0 - 1e-9) is None  # inside: no factor tried
    assert (
        unit_slip(500.0, 0.01, 300.0, factors=(10.0,)) == 10.0
        and unit_slip(500e3, 0.01, 300.0, factors=(10.0,)) is None
    )
    assert unit_slip(0.2, 10.0, 300.0, factors=(1e-3, 1e-2)) == 1e-3  # the first factor that fits


def test_a_factor_in_words():
    assert factor_name(1e3) == "1000 times" and factor_name(1.0) == "1 times"
    assert factor_name(1e-3) == "1/1000 of" and factor_name(0.5) == "1/2 of"
    assert factor_name(12345.0) == "1.234e+04 times"


def test_a_drive_figure_in_another_unit_names_its_factor():
    assert drive_slip("s1_torque", [1910.0], "Nm") == (
        "1910 Nm is 1000 times a plausible figure for this machine's drive (0.01 to 100 N·m): a unit slip by 1000 "
        "(N·mm under an _Nm key, N·m under _Nmm, m under _mm, krpm under _rpm?): check the key's unit against the data sheet"
    )
    # The smallest positive value when none is too large; shown in the key's unit.
    message = drive_slip("rated_torque", [0.0, -1.0, 5e-5, 100.0], "Nmm", factor=1e-3)  # the top on its edge
    assert message is not None and message.startswith(
        "0.05 Nmm is 1/1000 of a plausible figure for this machine's drive (0.01 to 100 N·m): a unit slip by 1/1000 ("
    )
    # The largest when it is too large, though the smallest is plausible.
    largest = drive_slip("s1_torque", [0.05, 1910.0], "Nm")
    assert largest is not None and largest.startswith("1910 Nm is 1000 times")
    speed = drive_slip("max_speed", 3000e3 * math.pi / 30.0, "rpm", factor=math.pi / 30.0)
    assert speed is not None and "(10.5 to 3.14e+03 rad/s)" in speed and speed.startswith("3e+06 rpm is 1000 times")
    assert drive_slip("s1_torque", [5.0, 100.0], "Nm") is None
    assert drive_slip("s1_torque", [1e9], "Nm") is None  # no factor of 1000 explains it
    assert drive_slip("s1_torque", [0.0, -3.0], "Nm") is None
    assert drive_slip("colour", [1e9], "Nm") is None
    assert drive_slip("peak_torque", [250.0], "Nm") is None and drive_slip("s1_torque", [250.0], "Nm") is not None
    assert drive_slip("lead", 5e-6, "mm", 1e-3) is not None and drive_slip("preload", 1e-3, "N") is None


def test_milliseconds_read_as_seconds_at_the_edges_of_the_step_and_the_span():
    t = np.arange(101) * 0.5  # a step of 0.5 s over 50 s: 0.05 s read as ms, the shortest plausible motion
    assert time_slip(t, "s") == (
        "the times look like milliseconds: a sample every 0.5 s over 50 s is no gait recording (0.05 s in ms); "
        "give the times in s (or, for a trajectory file, map the column with :ms)"
    )
    assert time_slip(np.arange(101) * 0.4999, "s") is None  # a step under 0.5 s
    late = time_slip(10.0 + np.arange(101) * 0.5, "s")  # the span from the first time, not from zero
    assert late is not None and "a sample every 0.5 s over 50 s is no gait recording (0.05 s in ms)" in late
    assert time_slip(np.arange(100) * 0.5, "s") is None  # 49.5 s: 0.0495 s as ms is shorter than any motion
    assert time_slip(np.array([0.0, 86400e3]), "s") is not None and time_slip(np.array([0.0, 86401e3]), "s") is None
    assert time_slip(np.array([0.0]), "s") is None and time_slip(t, "min") is None
    # The median step, not the mean: 101 steps of 0.5 s and 100 of 0.01 s (mean 0.26 s) are a slip ...
    steps = np.concatenate([np.full(101, 0.5), np.full(100, 0.01)])
    assert time_slip(np.concatenate([[0.0], np.cumsum(steps)]), "s") is not None
    # ... and 100 steps of 0.1 s with one gap of 100 s (mean 1.09 s) are not.
    gap = np.concatenate([np.full(100, 0.1), [100.0]])
    assert time_slip(np.concatenate([[0.0], np.cumsum(gap)]), "s") is None


def test_seconds_read_as_milliseconds_at_the_edges_of_the_span():
    t = np.arange(41) * 0.001  # 40 ms: as s, 40 s at 1 kHz
    assert time_slip(t, "ms") == (
        "the times look like seconds: read as ms the motion lasts 40 ms (1000 Hz sampling); label the time column "
        "in s (drop ':ms')"
    )
    assert time_slip(np.arange(51) * 0.001, "ms") is None  # 50 ms: the shortest plausible motion
    assert time_slip(np.array([0.0, 0.05 - 1e-12]), "ms") is not None
    assert time_slip(np.array([0.0, 0.00004]), "ms") is None  # 0.04 s as s: shorter than any motion
    assert time_slip(np.array([0.0, 0.0000499975]), "ms") is None  # 0.0499975 s as s: a thousand times, no more
    assert time_slip(np.array([0.0, 0.00005]), "ms") is not None
    assert time_slip(t, "s") is None


def test_epoch_time_stamps_from_the_floor_on(monkeypatch):
    monkeypatch.setenv("TZ", "Asia/Tokyo")  # the stamp is UTC, whatever the machine's zone
    time.tzset()
    assert epoch_warning(1e8) == (
        "the times are Unix time stamps (from 1973-03-03 09:46:40 UTC): read relative to the first, 100000000 s"
    )
    assert epoch_warning(1e8 - 1e-3) is None and epoch_warning(0.0) is None
    assert epoch_warning(math.nan) is None and epoch_warning(math.inf) is None
    assert epoch_warning(1e20) is None  # beyond any date: no time stamp
    message = epoch_warning(1732700000.25)
    assert message is not None and message.endswith("the first, 1732700000.25 s")
    monkeypatch.undo()
    time.tzset()


LOADS = "(ISO 14242-1: 300 to 3000 N)"


def test_a_loads_peak_against_the_test_loads():
    error, warning = load_slip(3.0)
    assert warning is None and error == (
        f"the load looks like kN: its peak is 3 N, 1/1000 of a hip simulator's test loads {LOADS}; give it in N, or "
        "label it :kN"
    )
    error, warning = load_slip(3e6, "kN")
    assert warning is None and error == (
        f"the load looks like N read as kN: its peak is 3e+06 N, 1000 times a hip simulator's test loads {LOADS}; "
        "label it :N"
    )
    error, warning = load_slip(3e6)
    assert (
        warning is None
        and error == f"the load peaks at 3e+06 N, 1000 times a hip simulator's test loads {LOADS}: check its unit"
    )
    assert load_slip(3.0, "kN") == (
        None,
        "the load peaks at 3 N, far below a hip simulator's test loads (ISO 14242-1: 300 to 3000 N): is it in N?",
    )
    assert load_slip(6000.0) == (
        None,
        "the load peaks at 6000 N, above any hip simulator's test load (5000 N): check its unit",
    )


def test_a_loads_peak_at_each_edge():
    assert load_slip(0.3)[0] is not None and load_slip(0.299)[0] is None  # 300 N as kN is the lowest test load
    assert load_slip(0.299)[1] is not None
    assert load_slip(5e6)[0] is not None and load_slip(5.001e6)[0] is None
    assert load_slip(100.0) == (None, None) and load_slip(99.99)[1] is not None  # the warning's floor
    assert load_slip(5000.0) == (None, None) and load_slip(5000.5)[1] is not None
    assert load_slip(300.0) == (None, None) and load_slip(2000.0, "%BW") == (None, None)
    assert load_slip(0.0) == (None, None) and load_slip(-3000.0) == (None, None)
    assert load_slip(math.nan) == (None, None) and load_slip(math.inf) == (None, None)
    error, warning = load_slip(3.0, "%BW")  # a factor, but no unit that explains it: doubtful
    assert error is None and warning is not None and warning.startswith("the load peaks at 3 N, far below")


def test_all_angles_in_radians_at_the_edges():
    assert radians_slip(np.array([0.1, 0.5, 0.2])) == (1, pytest.approx(0.5 * DEG))
    assert radians_slip(np.array([0.5, 0.5])) == (0, pytest.approx(0.5 * DEG))  # the first widest
    assert radians_slip(np.array([1.0, 0.5])) is None  # 1° spans no less than a degree
    assert radians_slip(np.array([0.999, 0.5])) is not None
    assert radians_slip(np.array([5.0 / DEG, 0.01])) == (0, pytest.approx(5.0))  # 5°: the narrowest gait range
    assert radians_slip(np.array([4.99 / DEG, 0.01])) is None
    assert radians_slip(np.array([])) is None and radians_slip(np.array([0.5, math.nan])) is None
    assert radians_slip(np.array([0.2])) == (0, pytest.approx(0.2 * DEG))


def test_one_angle_in_radians_beside_degrees():
    found = one_radians_slip(np.array([40.0, 0.5, 0.0, 1.0, 0.25]))
    assert found == [(1, pytest.approx(0.5 * DEG)), (4, pytest.approx(0.25 * DEG))]  # a still angle is planar
    assert one_radians_slip(np.array([5.0, 0.5])) == [(1, pytest.approx(0.5 * DEG))]  # the widest on 5°
    assert one_radians_slip(np.array([4.99, 0.5])) == []
    assert one_radians_slip(np.array([0.5])) == [] and one_radians_slip(np.array([40.0, math.nan, 0.5])) == []
    assert one_radians_slip(np.array([30.0, 0.999])) == [(1, pytest.approx(0.999 * DEG))]

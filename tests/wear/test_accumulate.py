"""hipsim.wear.accumulate by hand: whole cycles of a motion, the intervals snapshots stand for, a station's exposure
(integrals over any span, the mean motion with its CS weighted by overlap × work, the volume predicted at each stop)
and the table of intervals between stops."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from hipsim.exceptions import ArgumentError
from hipsim.motion.trajectories import iso14242
from hipsim.wear.accumulate import Exposure, interval_table, snapshot_intervals, whole_cycles
from hipsim.wear.factors import MotionIntegrals


def test_whole_cycles_run_from_the_first_heel_strike_to_the_last():
    motion = iso14242(rate=50, cycles=3)
    cut, period = whole_cycles(motion)
    assert period == pytest.approx(1.0, abs=1e-9)
    assert cut.t[-1] - cut.t[0] == pytest.approx(2.0 - 0.02, abs=1e-9)  # two cycles, the closing sample left out
    assert cut.t.size == 2 * 50
    with pytest.raises(ArgumentError, match=r"expected a snapshot of at least one whole cycle \(two heel strikes\)"):
        whole_cycles(iso14242(rate=50, cycles=1).slice(slice(0, 40)))


def test_snapshot_intervals_by_hand():
    assert_allclose(snapshot_intervals(np.array([2.0, 4.0, 10.0]), 0.0, 12.0), [0.0, 3.0, 7.0, 12.0])
    # A snapshot before the first stop (or after the last) widens the span to it.
    assert_allclose(snapshot_intervals(np.array([2.0, 4.0]), 3.0, 3.5), [2.0, 3.0, 4.0])
    assert_allclose(snapshot_intervals(np.array([5.0]), 0.0, 9.0), [0.0, 9.0])
    for bad in (np.array([1.0, 1.0]), np.array([2.0, 1.0]), np.array([]), np.array([[1.0, 2.0]])):
        with pytest.raises(ArgumentError, match="snapshot cycles: expected increasing cycles, at least one"):
            snapshot_intervals(bad, 0.0, 9.0)


MOTIONS = (MotionIntegrals(10.0, 1.0, 0.1, "a"), MotionIntegrals(30.0, 3.0, 0.3, "b"))


def test_an_exposure_over_any_span():
    """Interval 0: cycles 0–4 at 10 N·m a cycle; interval 1: 4–10 at 30 (before 0 the first's, after 10 the last's)."""
    exposure = Exposure("1", np.array([0, 4, 10]), MOTIONS, "snapshots")
    assert exposure.boundaries.dtype == float
    assert exposure.integral("local", 2.0, 6.0) == pytest.approx(2 * 10 + 2 * 30)
    assert exposure.integral("force-track", 2.0, 6.0) == pytest.approx(2 * 1 + 2 * 3)
    assert exposure.integral("local", -3.0, 0.0) == pytest.approx(30.0)  # before the first interval
    assert exposure.integral("local", 10.0, 12.0) == pytest.approx(60.0)  # after the last
    assert exposure.integral("local", 4.0, 4.0) == 0.0 and exposure.integral("local", 6.0, 2.0) == 0.0
    assert_allclose(exposure.predicted_mm3(1e-3, "local", np.array([2.0, 4.0, 6.0])), [0.0, 0.02, 0.08])


def test_the_mean_motion_weighs_cs_by_overlap_times_work():
    """Over 2–6: 2 cycles of a, 2 of b; the mean integrals 20 and 2; CS (2·10·0.1 + 2·30·0.3)/(2·10 + 2·30) = 0.25."""
    exposure = Exposure("1", np.array([0.0, 4.0, 10.0]), MOTIONS, "snapshots")
    mean = exposure.mean(2.0, 6.0)
    assert mean.load_slide_integral_Nm == pytest.approx(20.0) and mean.force_track_load_Nm == pytest.approx(2.0)
    assert mean.cross_shear_work_weighted == pytest.approx(0.25)  # not the overlap mean 0.2
    assert mean.name == "snapshots, cycles 2 to 6"
    assert exposure.mean(4.0, 10.0).cross_shear_work_weighted == pytest.approx(0.3)  # interval 0 has no overlap
    # No cycles: the first interval's motion at or before its start, else the last's.
    assert exposure.mean(0.0, 0.0) is MOTIONS[0] and exposure.mean(-1.0, -2.0) is MOTIONS[0]
    assert exposure.mean(5.0, 5.0) is MOTIONS[1]
    idle = Exposure("1", np.array([0.0, 1.0]), (MotionIntegrals(0.0, 0.0, math.nan),), "still")
    assert math.isnan(idle.mean(0.0, 1.0).cross_shear_work_weighted)


def test_an_exposure_refuses_boundaries_that_do_not_fit():
    for bad in (np.array([0.0, 4.0]), np.array([0.0, 4.0, 4.0]), np.array([[0.0, 4.0, 10.0]])):
        with pytest.raises(ArgumentError, match="boundaries: expected 3 increasing cycles"):
            Exposure("1", bad, MOTIONS, "s")


def test_the_interval_table_by_hand():
    exposure = Exposure("1", np.array([0.0, 4.0, 10.0]), MOTIONS, "snapshots")
    rows = interval_table("1", (0, 4, 10), (0.0, 0.5, 2.5), exposure, 1e-3, "force-track")
    assert [(r.station, r.first_cycle, r.last_cycle, r.measured_mm3) for r in rows] == [
        ("1", 0, 4, 0.5),
        ("1", 4, 10, 2.0),
    ]
    assert [r.predicted_mm3 for r in rows] == pytest.approx([0.004, 0.018])
    assert rows[1].to_json() == {
        "station": "1",
        "first_cycle": 4,
        "last_cycle": 10,
        "measured_mm3": 2.0,
        "predicted_mm3": pytest.approx(0.018),
    }
    assert isinstance(rows[0].first_cycle, int) and isinstance(rows[0].measured_mm3, float)


def test_one_whole_cycle_from_a_heel_strike_inside_the_motion():
    """A log starting mid-cycle (t = 0.5 s): whole cycles from its first heel strike at 1 s; exactly one cycle (two
    heel strikes) is enough."""
    motion = iso14242(rate=50, cycles=3).slice(slice(25, 110))  # 0.5 s … 2.18 s: heel strikes at 1 s and 2 s
    cut, period = whole_cycles(motion)
    assert cut.t[0] == pytest.approx(1.0) and cut.t[-1] == pytest.approx(1.98) and period == pytest.approx(1.0)
    short = iso14242(rate=50, cycles=3).slice(slice(25, 101))  # the second heel strike is not yet seen
    with pytest.raises(
        ArgumentError,
        match=r"^ISO 14242-1: expected a snapshot of at least one whole cycle \(two heel "
        r"strikes\), got 'fewer than two heel strikes'$",
    ):
        whole_cycles(short)


def test_snapshots_less_than_a_cycle_apart_and_a_short_mean():
    assert_allclose(snapshot_intervals(np.array([0.0, 0.5]), 0.0, 1.0), [0.0, 0.25, 1.0])
    with pytest.raises(ArgumentError, match=r"got shape \(2,\)$"):
        snapshot_intervals(np.array([1.0, 1.0]), 0.0, 9.0)
    three = MOTIONS + (MotionIntegrals(50.0, 5.0, 0.5, "c"),)
    exposure = Exposure("1", np.array([0.0, 4.0, 10.0, 12.0]), three, "s")
    assert exposure.mean(3.0, 3.0) is three[2]  # no cycles, after the start: the last interval's motion
    half = exposure.mean(2.0, 2.5)  # half a cycle in interval 0: its own motion, averaged
    assert half.load_slide_integral_Nm == pytest.approx(10.0) and half.cross_shear_work_weighted == pytest.approx(0.1)


def test_parts_of_a_cycle_count():
    exposure = Exposure("1", np.array([0.0, 4.0, 10.0]), MOTIONS, "s")
    assert exposure.integral("local", 3.5, 4.5) == pytest.approx(0.5 * 10 + 0.5 * 30)
    tiny = exposure.mean(2.0, 2.01)  # overlap × work = 0.1 N·m: CS still weighed
    assert tiny.cross_shear_work_weighted == pytest.approx(0.1)
    with pytest.raises(ArgumentError, match=r"^boundaries: expected 3 increasing cycles, got shape \(2,\)$"):
        Exposure("1", np.array([0.0, 4.0]), MOTIONS, "s")

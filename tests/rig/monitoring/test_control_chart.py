"""The control chart's laws by hand-computed values: baseline mean and spread, the EWMA and its two limits, alarms and notices.

Baseline (cycles 10-30): x = 1.0, 1.2, 0.8 mm with s = 0.1 mm: mean 1.0, sample deviation 0.2 (the estimates' own
RMS error 0.1 is smaller, so σ₀ = 0.2). With λ = 0.2, L = 3 the limits' half-width after k monitoring snapshots is
3·0.2·√(0.2/1.8·(1 − 0.8^{2k})): 0.12 at k = 1, 0.6·√(0.0656) = 0.153675 at k = 2.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError
from hipsim.rig.monitoring.control_chart import chart
from hipsim.rig.monitoring.findings import missing_cycles

R_H = 10.0  # mm
CYCLES = [0, 10, 20, 30, 40, 50]
BASELINE = (10, 30)


def _chart(x2, x3, alarm_rise=0.01, worst=1.0, s=0.1):
    # The hand values below are of a three-snapshot baseline: set so (the default needs five).
    return chart(CYCLES, [5.0, 1.0, 1.2, 0.8, x2, x3], [s] * 6, R_H, BASELINE, alarm_rise, worst, baseline_min=3)


def test_baseline_mean_spread_and_phases():
    c = _chart(1.5, 1.5)
    assert list(c.phase) == ["running-in", "baseline", "baseline", "baseline", "monitoring", "monitoring"]
    assert c.mean == pytest.approx(1.0) and c.spread == pytest.approx(0.2) and c.baseline_count == 3
    assert c.change[4] == pytest.approx(0.05)  # (1.5 − 1.0) / 10
    assert c.change_std[4] == pytest.approx(math.sqrt(0.01 + 0.04 / 3) / R_H)
    # Running-in is shown (its change is large) but never flagged.
    assert c.change[0] == pytest.approx(0.4) and c.flag[0] == "" and np.isnan(c.ewma[0])


def test_the_spread_is_never_below_the_estimates_own_error():
    assert _chart(1.5, 1.5, s=0.3).spread == pytest.approx(0.3)  # RMS 0.3 above the sample deviation 0.2


def test_ewma_and_both_limits_by_hand():
    c = _chart(1.5, 1.5)
    assert c.ewma[4] == pytest.approx(1.1) and c.ewma[5] == pytest.approx(1.18)
    assert c.upper[4] == pytest.approx(1.12) and c.lower[4] == pytest.approx(0.88)
    assert c.upper[5] == pytest.approx(1.153675, abs=1e-6) and c.lower[5] == pytest.approx(0.846325, abs=1e-6)
    # k = 1: z = 1.1 inside 1.12; k = 2: z = 1.18 beyond 1.1537: significant, and a change of 0.05 > 0.01.
    assert list(c.signal[4:]) == [0, 1] and list(c.flag[4:]) == ["", "alarm"] and list(c.alarm) == [0] * 5 + [1]
    assert c.threshold == pytest.approx((1.0 - 0.1, 1.0 + 0.1))  # μ₀ ∓ D·r_h


def test_a_fall_is_flagged_as_a_rise_is():
    c = _chart(0.5, 0.5)
    assert c.ewma[5] == pytest.approx(0.82) and list(c.signal[4:]) == [0, -1] and c.flag[5] == "alarm"


def test_significant_below_the_threshold_is_a_notice():
    assert _chart(1.5, 1.5, alarm_rise=0.06).flag[5] == "notice"
    assert _chart(0.5, 0.5, alarm_rise=0.06).flag[5] == "notice"


def test_the_worst_case_of_two_stations_doubles_the_change():
    # The mean up 0.05: up to 0.10 in one station. Against D = 0.08 that is an alarm; alone (worst 1) a notice.
    assert _chart(1.5, 1.5, alarm_rise=0.08, worst=2.0).flag[5] == "alarm"
    assert _chart(1.5, 1.5, alarm_rise=0.08).flag[5] == "notice"
    assert _chart(1.5, 1.5, alarm_rise=0.12, worst=2.0).flag[5] == "notice"
    assert _chart(1.5, 1.5, alarm_rise=0.08, worst=2.0).threshold == pytest.approx((0.6, 1.4))


def test_a_snapshot_without_an_estimate_is_skipped_by_the_ewma():
    c = chart(CYCLES + [60], [5.0, 1.0, 1.2, 0.8, math.nan, 1.5, 1.5], [0.1] * 7, R_H, BASELINE, baseline_min=3)
    assert np.isnan(c.ewma[4]) and c.ewma[5] == pytest.approx(1.1) and c.ewma[6] == pytest.approx(1.18)


def test_no_chart_before_the_baseline_minimum():
    c = chart([0, 10, 20], [1.0, 1.1, 1.2], [0.1] * 3, R_H, (10, 30), baseline_min=3)
    assert math.isnan(c.mean) and "2 of the 3" in c.note and not c.alarm.any()


def test_the_baseline_needs_five_snapshots_by_default():
    # Issue 47: three baseline snapshots gave notices and early alarms. Four (10..40) are refused, five charted.
    x = [1.0, 1.1, 0.9, 1.05, 0.95, 3.0, 3.0]
    four = chart([0, 10, 20, 30, 40, 60, 70], x, [0.1] * 7, R_H, (10, 40))
    assert math.isnan(four.mean) and "4 of the 5" in four.note and "--baseline-min 4" in four.note
    assert not four.alarm.any()
    five = chart([10, 20, 30, 40, 50, 60, 70], x, [0.1] * 7, R_H, (10, 50))
    assert five.baseline_count == 5 and five.mean == pytest.approx(1.0) and five.note == ""
    assert five.flag[-1] == "alarm"  # 3.0 mm against 1.0: far beyond
    # --baseline-min 4 charts the four.
    assert chart([0, 10, 20, 30, 40, 60, 70], x, [0.1] * 7, R_H, (10, 40), baseline_min=4).baseline_count == 4


@pytest.mark.parametrize("value", [1, 0, -3, 2.5, True])
def test_a_baseline_minimum_below_two_is_refused(value):
    with pytest.raises(ArgumentError, match="baseline_min"):
        chart(CYCLES, [1.0] * 6, [0.1] * 6, R_H, BASELINE, baseline_min=value)


@pytest.mark.parametrize(("name", "value"), [("alarm_rise", 0.0), ("worst", 0.5)])
def test_bad_options_refused(name, value):
    options = {"alarm_rise": 0.01, "worst": 1.0} | {name: value}
    with pytest.raises(ArgumentError, match=name):
        chart(CYCLES, [1.0] * 6, [0.1] * 6, R_H, BASELINE, options["alarm_rise"], options["worst"])


@pytest.mark.parametrize(
    ("cycles", "missing"),
    [
        ([0, 250, 500, 1000, 1500], [750, 1250]),  # two gone: the spacing is still 250
        ([0, 250, 500, 1250], [750, 1000]),
        ([0, 100, 205, 300, 390], []),  # irregular, no gap beyond 1.5 spacings
        ([0, 250], []),  # too few to know the spacing
    ],
)
def test_missing_snapshots_by_hand(cycles, missing):
    assert missing_cycles(cycles) == missing

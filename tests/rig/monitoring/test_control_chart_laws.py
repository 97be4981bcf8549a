"""hipsim.rig.monitoring.control_chart pinned by hand: baseline mean and spread, the EWMA, its limits, the alarms.

Seven snapshots: one in running-in, three in the baseline (cycles 500 000 to
1 000 000, both ends included), three after. Every number below is worked out
from the formulas of the module's description with λ = 0.2, L = 3:
λ/(2 − λ) = 1/9, and the limit's factor √(1/9·(1 − 0.8^{2k})) is 0.2, 0.256125,
0.286328 for k = 1, 2, 3.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from hipsim.exceptions import ArgumentError
from hipsim.rig.monitoring import control_chart
from hipsim.rig.monitoring.control_chart import (
    DEFAULT_ALARM_RISE,
    DEFAULT_BASELINE,
    EWMA_L,
    EWMA_LAMBDA,
    MIN_BASELINE,
    parse_baseline,
)


def chart(*args: Any, **options: Any) -> control_chart.Chart:
    """The chart with the three-snapshot baseline these hand values are of (the default needs five)."""
    return control_chart.chart(*args, **({"baseline_min": 3} | options))


CYCLES = [100_000, 500_000, 750_000, 1_000_000, 1_100_000, 1_200_000, 1_300_000]
#: Running-in far off (never flagged), baseline 10.0, 10.2, 9.8 mm, then 10.5, 11.0, 10.0 mm.
ESTIMATE = [20.0, 10.0, 10.2, 9.8, 10.5, 11.0, 10.0]
HIP_RADIUS_MM = 25.0


def test_the_defaults():
    assert (EWMA_LAMBDA, EWMA_L, MIN_BASELINE) == (0.2, 3.0, 5)
    assert DEFAULT_BASELINE == (500_000, 1_000_000) and DEFAULT_ALARM_RISE == 0.01


def test_the_chart_by_hand():
    c = chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM)
    assert list(c.phase) == ["running-in"] + ["baseline"] * 3 + ["monitoring"] * 3
    assert c.baseline_count == 3 and c.note == ""
    # μ₀ = (10.0 + 10.2 + 9.8)/3 = 10; σ₀ = √((0² + 0.2² + 0.2²)/2) = 0.2 (above the RMS error 0.1).
    assert c.mean == pytest.approx(10.0, abs=1e-12)
    assert c.spread == pytest.approx(0.2, rel=1e-12)
    # z₁ = 0.2·10.5 + 0.8·10 = 10.1; z₂ = 0.2·11 + 0.8·10.1 = 10.28; z₃ = 0.2·10 + 0.8·10.28 = 10.224.
    np.testing.assert_allclose(c.ewma[4:], [10.1, 10.28, 10.224], rtol=1e-12)
    assert np.isnan(c.ewma[:4]).all() and np.isnan(c.upper[:4]).all() and np.isnan(c.lower[:4]).all()
    # Limits 10 ± 3·0.2·(0.2, 0.256125, 0.286328), both sides.
    limits = [10.0 + 0.6 * math.sqrt((1 - 0.8 ** (2 * k)) / 9) for k in (1, 2, 3)]
    np.testing.assert_allclose(limits, [10.12, 10.153675, 10.171797], rtol=1e-6)
    np.testing.assert_allclose(c.upper[4:], limits, rtol=1e-12)
    np.testing.assert_allclose(c.lower[4:], [20.0 - u for u in limits], rtol=1e-12)
    # Change of μ_h: (x − 10)/25 → 0.02, 0.04, 0; its deviation √(0.1² + 0.2²/3)/25 = 0.0061101.
    np.testing.assert_allclose(c.change[4:], [0.02, 0.04, 0.0], atol=1e-12)
    np.testing.assert_allclose(c.change_std, math.sqrt(0.01 + 0.04 / 3) / 25.0, rtol=1e-12)
    # k = 1: z 10.1 under 10.12, no alarm; k = 2: 10.28 over 10.1537 and the change 0.04 over 0.01: alarm;
    # k = 3: 10.224 over 10.1718 (significant) but the change 0 is harmless: a notice, not an alarm.
    # Running-in at 20 mm: never flagged.
    assert list(c.alarm) == [0, 0, 0, 0, 0, 1, 0]
    assert list(c.flag) == ["", "", "", "", "", "alarm", "notice"]
    assert list(c.signal) == [0, 0, 0, 0, 0, 1, 1]
    # The engineering threshold on the estimate: 10 ∓ 0.01·25 = 9.75 and 10.25 mm (one station: worst = 1).
    assert c.threshold == pytest.approx((9.75, 10.25), rel=1e-12)


def test_the_spread_never_below_the_estimates_own_error():
    # Baseline standard errors 0.3 mm (RMS 0.3) above the sample deviation 0.2: σ₀ = 0.3.
    # The RMS, not the mean: errors 0.1, 0.1, 0.5 have RMS √(0.27/3) = 0.3 (mean 0.233).
    c = chart(CYCLES, ESTIMATE, [0.1, 0.1, 0.1, 0.5, 0.1, 0.1, 0.1], HIP_RADIUS_MM)
    assert c.spread == pytest.approx(0.3, rel=1e-12)
    # The first limits: 10 ± 3·0.3·0.2 = 9.82 and 10.18.
    assert c.upper[4] == pytest.approx(10.18, rel=1e-12)
    assert c.lower[4] == pytest.approx(9.82, rel=1e-12)


def test_other_weight_width_and_rise():
    # λ = 0.5, L = 2, D = 0.05: z₁ = 0.5·10.5 + 0.5·10 = 10.25, z₂ = 10.625, z₃ = 10.3125;
    # limit factor √(0.5/1.5·(1 − 0.5^{2k})): k = 1 √(1/3·3/4) = 0.5, so 10 + 2·0.2·0.5 = 10.2.
    c = chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, lam=0.5, width=2.0, alarm_rise=0.05)
    np.testing.assert_allclose(c.ewma[4:], [10.25, 10.625, 10.3125], rtol=1e-12)
    assert c.upper[4] == pytest.approx(10.2, rel=1e-12) and c.lower[4] == pytest.approx(9.8, rel=1e-12)
    # Changes 0.02, 0.04, 0 never exceed 0.05: no alarm although z is above its limit.
    assert not c.alarm.any()
    assert c.threshold == pytest.approx((10.0 - 0.05 * 25.0, 10.0 + 0.05 * 25.0))
    # With D = 0.03 the second snapshot (change 0.04) alarms.
    assert list(chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, alarm_rise=0.03).alarm) == [0, 0, 0, 0, 0, 1, 0]


def test_another_baseline_window():
    # Baseline (0, 600 000): the first two snapshots only, fewer than 3: no chart yet.
    c = chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, baseline=(0, 600_000))
    assert c.baseline_count == 2 and math.isnan(c.mean) and math.isnan(c.spread) and all(map(math.isnan, c.threshold))
    assert c.note == (
        "baseline incomplete: 2 of the 3 snapshots it needs within cycles 0-600000; the chart starts once it has them "
        "(widen --baseline or log snapshots more often; --baseline-min 2 would chart on fewer, with notices and early "
        "alarms)"
    )
    assert np.isnan(c.ewma).all() and np.isnan(c.change).all() and np.isnan(c.change_std).all()
    assert not c.alarm.any() and c.alarm.dtype.kind == "i" and c.alarm.size == 7
    assert list(c.phase[:2]) == ["baseline", "baseline"] and c.phase[2] == "monitoring"


def test_the_alarm_rise_must_be_a_positive_number():
    for bad in (0.0, -0.01, math.nan, math.inf, "0.01"):
        with pytest.raises(ArgumentError, match="a positive rise of the hip friction coefficient"):
            chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, alarm_rise=bad)  # wrong types on purpose


def test_parse_baseline():
    assert parse_baseline("500000:1000000") == (500_000, 1_000_000)
    assert parse_baseline("500_000:1_000_000") == (500_000, 1_000_000)
    assert parse_baseline("1e6:2e6") == (1_000_000, 2_000_000)
    assert parse_baseline("0:0") == (0, 0)
    for bad in ("5:3", "-1:3", "abc", "1:2:3", "1", ":5", "1:x"):
        with pytest.raises(ArgumentError, match="FROM:TO in cycles"):
            parse_baseline(bad)


def test_a_fall_is_flagged_and_the_mean_of_two_stations_counts_twice():
    # Baseline 10.0, 10.2, 9.8 (μ₀ 10, σ₀ 0.2), then 9.5, 9.0: z₁ = 0.2·9.5 + 0.8·10 = 9.9 (above the lower
    # limit 10 − 0.12 = 9.88: nothing); z₂ = 0.2·9 + 0.8·9.9 = 9.72 below 10 − 0.153675: significant, falling.
    # Its change (9 − 10)/25 = −0.04: an alarm at D = 0.01. With D = 0.05 one station's −0.04 is a notice,
    # but as the mean of two stations (worst = 2) it is up to −0.08 in one of them: an alarm.
    cycles, x = CYCLES[:6], [20.0, 10.0, 10.2, 9.8, 9.5, 9.0]
    c = chart(cycles, x, [0.1] * 6, HIP_RADIUS_MM)
    np.testing.assert_allclose(c.ewma[4:], [9.9, 9.72], rtol=1e-12)
    assert list(c.signal) == [0, 0, 0, 0, 0, -1] and list(c.flag) == ["", "", "", "", "", "alarm"]
    one = chart(cycles, x, [0.1] * 6, HIP_RADIUS_MM, alarm_rise=0.05)
    two = chart(cycles, x, [0.1] * 6, HIP_RADIUS_MM, alarm_rise=0.05, worst=2.0)
    assert one.flag[5] == "notice" and two.flag[5] == "alarm"
    # The threshold on the estimate halves with the worst case: 10 ∓ 0.05·25/2.
    assert two.threshold == pytest.approx((9.375, 10.625), rel=1e-12)


def test_an_incomplete_baseline_leaves_every_column_blank():
    # Beside the test above: the limits and signal are blank too, the flags empty texts, the worst case kept.
    c = chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, baseline=(0, 600_000), worst=2.0)
    assert np.isnan(c.lower).all() and np.isnan(c.upper).all()
    assert list(c.signal) == [0] * 7 and c.signal.dtype.kind == "i"
    assert list(c.flag) == [""] * 7 and c.flag.dtype == object
    assert c.worst == 2.0


def test_on_a_limit_or_on_the_threshold_is_not_beyond():
    # λ = 1, L = 1: z = x and the limit is μ₀ ± σ₀. Baseline 9, 10, 11: μ₀ = 10, σ₀ = √((1 + 0 + 1)/2) = 1 (above
    # the errors' 0), so the limits are 9 and 11 exactly. 11 and 9 lie on them: not significant; 11.5 and 8.5 are.
    cycles = [500_000, 750_000, 1_000_000, 1_100_000, 1_200_000, 1_300_000, 1_400_000]
    x = [9.0, 10.0, 11.0, 11.0, 9.0, 11.5, 8.5]
    c = chart(cycles, x, [0.0] * 7, HIP_RADIUS_MM, lam=1.0, width=1.0)
    assert (c.mean, c.spread, c.worst) == (10.0, 1.0, 1.0)
    assert chart(cycles, x, [0.0] * 7, HIP_RADIUS_MM, worst=2.0).worst == 2.0
    assert list(c.upper[3:]) == [11.0] * 4 and list(c.lower[3:]) == [9.0] * 4
    assert list(c.signal) == [0, 0, 0, 0, 0, 1, -1]
    # The change 1.5/25 = 0.06 either way: against D = 0.06 it is on the threshold, not beyond: notices.
    on = chart(cycles, x, [0.0] * 7, HIP_RADIUS_MM, lam=1.0, width=1.0, alarm_rise=0.06)
    assert list(on.flag[5:]) == ["notice", "notice"]
    assert list(chart(cycles, x, [0.0] * 7, HIP_RADIUS_MM, lam=1.0, width=1.0, alarm_rise=0.059).flag[5:]) == [
        "alarm",
        "alarm",
    ]


def test_integer_inputs_chart_as_floats():
    # Cycles, estimates and errors given as whole numbers: the same chart as given as floats.
    cycles = [500_000, 750_000, 1_000_000, 1_100_000]
    whole = chart(cycles, [9, 10, 11, 14], [0, 0, 0, 0], HIP_RADIUS_MM)
    floats = chart(
        [float(c) for c in cycles],  # cycles as floats, on purpose
        [9.0, 10.0, 11.0, 14.0],
        [0.0] * 4,
        HIP_RADIUS_MM,
    )
    np.testing.assert_array_equal(whole.ewma, floats.ewma)
    assert whole.ewma[3] == pytest.approx(0.2 * 14 + 0.8 * 10, rel=1e-15)  # 10.8, above 10 + 3·1·0.2
    assert list(whole.flag) == list(floats.flag) == ["", "", "", "alarm"]


@pytest.mark.parametrize("bad", [0.5, math.nan, math.inf])
def test_the_worst_case_factor_is_at_least_one(bad):
    with pytest.raises(ArgumentError) as refused:
        chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, worst=bad)
    assert str(refused.value) == (
        f"worst: expected the worst station's change per change of the estimate, at least 1, got {bad!r}"
    )
    assert (refused.value.name, refused.value.value) == ("worst", bad)


def test_a_bad_alarm_rise_is_named_whole():
    with pytest.raises(ArgumentError) as refused:
        chart(CYCLES, ESTIMATE, [0.1] * 7, HIP_RADIUS_MM, alarm_rise=-0.01)
    assert (
        str(refused.value)
        == "alarm_rise: expected a positive rise of the hip friction coefficient, e.g. 0.01, got -0.01"
    )
    assert (refused.value.name, refused.value.value) == ("alarm_rise", -0.01)


@pytest.mark.parametrize("bad", ["5:3", "1:2:3", "1", "x:y"])
def test_a_bad_baseline_is_named_whole(bad):
    with pytest.raises(ArgumentError) as refused:
        parse_baseline(bad)
    assert (
        str(refused.value) == f"baseline: expected FROM:TO in cycles, 0 ≤ FROM ≤ TO, e.g. 500000:1000000, got {bad!r}"
    )
    assert (refused.value.name, refused.value.value) == ("baseline", bad)

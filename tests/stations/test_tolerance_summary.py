"""A tolerance study's summary, by hand: the 95th percentiles over the draws per platform, the families' shares
(hipsim/stations/tolerance_summary.py). The draws are numbers written here, not drawn machines."""

from __future__ import annotations

import jsonschema
import numpy as np
import pytest

from hipsim.stations.tolerance import ToleranceResult
from hipsim.stations.tolerance_summary import SensitivityRow, ToleranceSummary, family_shares, tolerance_summary


def _result() -> ToleranceResult:
    """101 draws; draw k's RMS is k + 1 degrees, + 100·angle, + 1000 on platform 2; its peak twice that."""
    k = np.arange(101.0)[:, None, None, None]
    j = np.array([0.0, 1000.0])[None, None, :, None]
    a = np.array([0.0, 100.0, 200.0])[None, None, None, :]
    rms = np.radians(k + 1 + j + a) * np.ones((1, 1, 2, 3))
    rng = np.random.default_rng(3)
    order = rng.permutation(101)  # the draws in any order
    rows = [
        {"value": "lever_11", "chain": "11", "family": "lever", "rms_deg": [0.1, 0.2, 0.3], "share": 0.2},
        {"value": "ujoint_12", "chain": "12", "family": "ujoint", "rms_deg": [0.1, 0.0, 0.0], "share": 0.5},
        {"value": "lever_21", "chain": "21", "family": "lever", "rms_deg": [0.0, 0.1, 0.0], "share": 0.25},
    ]
    return ToleranceResult({"lever": 1e-4, "ujoint": 5e-5}, ("2",), rms[order], 2 * rms[order], {"2": rows}, 7)


def test_the_95th_percentile_per_platform_and_angle():
    summary = tolerance_summary(_result(), 40)
    (control,) = summary.controls
    m1, m2 = control.platforms
    assert (m1.platform, m2.platform) == (1, 2)
    # 1 … 101 sorted, linear between order statistics: the 95th percentile is at rank 0.95·100 = 95 → value 96
    assert m1.rms_p95_deg == pytest.approx((96.0, 196.0, 296.0), rel=1e-12)
    assert m2.rms_p95_deg == pytest.approx((1096.0, 1196.0, 1296.0), rel=1e-12)
    assert m1.peak_p95_deg == pytest.approx((192.0, 392.0, 592.0), rel=1e-12)
    assert summary.draws == 101 and summary.seed == 7 and summary.samples_per_draw == 40
    assert summary.bands_mm == pytest.approx({"lever": 0.1, "ujoint": 0.05})
    jsonschema.validate(summary.to_json(), ToleranceSummary.json_schema())


def test_family_shares_add_a_familys_values_largest_first():
    rows = tolerance_summary(_result(), 40).controls[0].sensitivity
    assert rows[1] == SensitivityRow("ujoint_12", "12", "ujoint", (0.1, 0.0, 0.0), 0.5)
    shares = family_shares(rows)
    assert list(shares) == ["ujoint", "lever"] and shares["lever"] == pytest.approx(0.45)
    assert list(family_shares(rows[:1] + rows[2:])) == ["lever"]


def test_the_95th_percentile_interpolates_between_draws():
    """20 draws of 1 … 20°: rank 0.95·19 = 18.05, so 19 + 0.05·(20 − 19) = 19.05° (not a draw's own value)."""
    rms = np.radians(np.arange(1.0, 21.0))[::-1, None, None, None] * np.ones((1, 1, 2, 3))
    result = ToleranceResult({"lever": 1e-4}, ("1",), rms, rms, {"1": []}, 0)
    (control,) = tolerance_summary(result, 10).controls
    assert control.platforms[0].rms_p95_deg == pytest.approx((19.05,) * 3, rel=1e-12)
    assert control.family_share == {} and control.sensitivity == ()


def test_each_control_reads_its_own_draws_and_rows():
    """Controls "1" and "both": draw k's RMS k + 1° under "1", k + 101° under "both" (peaks 10 times), 21 draws:
    the 95th percentile at rank 0.95·20 = 19, the 20th value."""
    k = np.arange(21.0)[:, None, None, None]
    rms = np.radians(k + 1 + np.array([0.0, 100.0])[None, :, None, None]) * np.ones((1, 1, 2, 3))
    rows = {
        "1": [{"value": "slider_21", "chain": "21", "family": "slider", "rms_deg": [0.5, 0.25, 0.125], "share": 1.0}],
        "both": [{"value": "centre_x_1", "chain": "centre 1", "family": "centre", "rms_deg": [0, 0, 1], "share": 1.0}],
    }
    result = ToleranceResult({"slider": 2e-4}, ("1", "both"), rms, 10 * rms, rows, 3)
    one, both = tolerance_summary(result, 5).controls
    assert (one.control, both.control) == ("1", "both")
    assert one.platforms[1].rms_p95_deg == pytest.approx((20.0,) * 3, rel=1e-12)
    assert both.platforms[0].rms_p95_deg == pytest.approx((120.0,) * 3, rel=1e-12)
    assert both.platforms[1].peak_p95_deg == pytest.approx((1200.0,) * 3, rel=1e-12)
    assert one.sensitivity == (SensitivityRow("slider_21", "21", "slider", (0.5, 0.25, 0.125), 1.0),)
    assert both.sensitivity[0].rms_deg == (0.0, 0.0, 1.0) and both.family_share == {"centre": 1.0}
    assert tolerance_summary(result, 5).bands_mm == pytest.approx({"slider": 0.2})


def test_a_tolerance_study_states_no_verdict_and_says_what_it_reported():
    from hipsim.records import Level, exit_status
    from hipsim.stations.tolerance_summary import tolerance_verdict

    verdict = tolerance_verdict(ToleranceSummary(40, 7, 100, {"levers": 0.05}, ()))
    assert verdict.level == Level.NOT_MADE and exit_status([verdict]) == 0
    assert verdict.judged == (
        "manufacturing tolerances: the attitude errors of 40 machine(s) drawn within the bands (--control none), "
        "their 95th percentiles and each tolerance's share"
    )
    assert verdict.not_judged == "the errors against an acceptance limit (none is set)"
    assert dict(verdict.numbers) == {"draws": 40.0}

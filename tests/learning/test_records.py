"""What a learning step reports (hipsim.learning.records): errors per platform, convergence, the ISO verdicts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.learning.records import Convergence, LearnSummary, PlatformErrors, platform_errors, station_verdict
from hipsim.motion.iso_compliance import Tolerances
from hipsim.motion.trajectories import iso14242


def test_platform_errors_by_hand():
    t = np.array([0.0, 0.1, 0.2, 0.3])
    e = np.full((4, 2, 3), np.nan)
    # platform 2, in degrees: α = (1, −3, 1, 1): RMS √3, peak −3 at 0.1 s; β = (0, 0, 2, 0): RMS 1, peak 2 at 0.2 s;
    # γ = 0: RMS 0, peak 0 at the first sample
    e[:, 1] = np.radians(np.array([[1, 0, 0], [-3, 0, 0], [1, 2, 0], [1, 0, 0]], dtype=float))
    (two,) = platform_errors(t, e, learned_from=(2,))  # platform 1's NaN errors: not measured, left out
    assert two.platform == 2 and two.controlled
    assert two.rms_deg == pytest.approx((math.sqrt(3.0), 1.0, 0.0), rel=1e-12)
    assert two.peak_deg == pytest.approx((-3.0, 2.0, 0.0), rel=1e-12)  # signed, at the largest magnitude
    assert two.peak_at_s == (0.1, 0.2, 0.0)
    assert two.rms_total_deg == pytest.approx(math.sqrt((3.0 + 1.0 + 0.0) / 3.0), rel=1e-12)
    e[:, 0] = 0.0
    one, two = platform_errors(t, e, learned_from=(2,))
    assert one.platform == 1 and not one.controlled and one.rms_deg == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("model", "data", "converges"),
    [(0.0, None, True), (0.999, None, True), (1.0, None, False), (0.5, 0.999, True), (0.5, 1.0, False)],
)
def test_convergence_needs_every_known_figure_strictly_below_one(model, data, converges):
    assert Convergence(model, data, None if data is None else 1.0, "").converges is converges


def _summary(errors: tuple[PlatformErrors, ...]) -> LearnSummary:
    return LearnSummary(
        1, "both", (1.0, 1.0), 1.0, None, 0.0, 1.0, 4, 1, True, errors, Convergence(0.0, 1.5, 2.0, "n"), None, ()
    )


def test_the_controlled_rms_is_over_the_learned_platforms_only():
    a = PlatformErrors(1, True, (3.0, 0.0, 0.0), (0.0,) * 3, (0.0,) * 3)  # total √3
    b = PlatformErrors(2, True, (0.0, 0.0, 3.0), (0.0,) * 3, (0.0,) * 3)  # total √3
    c = PlatformErrors(2, False, (30.0, 30.0, 30.0), (0.0,) * 3, (0.0,) * 3)
    assert _summary((a, b)).controlled_rms_deg() == pytest.approx(math.sqrt(3.0), rel=1e-12)
    assert _summary((a, c)).controlled_rms_deg() == pytest.approx(math.sqrt(3.0), rel=1e-12)
    assert math.isnan(_summary((c,)).controlled_rms_deg())
    d = PlatformErrors(1, True, (1.0, 1.0, 1.0), (0.0,) * 3, (0.0,) * 3)  # total 1
    # the RMS of the platforms' totals √3 and 1, √((3 + 1)/2) = √2, not their mean (√3 + 1)/2
    assert _summary((d, b)).controlled_rms_deg() == pytest.approx(math.sqrt(2.0), rel=1e-12)
    document = _summary((a,)).to_json()
    assert document["converges"] is False  # the data figure 1.5
    assert document["errors"][0]["rms_deg"] == (3.0, 0.0, 0.0)


def test_a_station_verdict_on_the_iso_motion_passes_and_one_on_a_half_motion_fails():
    iso = iso14242(rate=100.0)
    passed = station_verdict(2, iso.t, iso.q, iso.Fe, "log")
    assert passed.platform == 2 and passed.verdict == "PASS" and passed.failing == () and passed.reason == ""
    assert max(passed.worst_deg) < 0.1
    half = station_verdict(0, iso.t, 0.5 * iso.q, iso.Fe, "log")
    assert half.verdict == "FAIL" and half.failing
    assert half.worst_deg[0] > 5.0  # α: half of its 21.5° amplitude, off the waveform by about that


def test_a_station_verdict_not_made_says_why():
    verdict = station_verdict(1, np.zeros(3), np.zeros((3, 2)), np.zeros(3), "log")  # angles of the wrong shape
    assert verdict.verdict == "not made" and "do not match" in verdict.reason
    assert all(math.isnan(x) for x in verdict.worst_deg)


def test_a_station_verdict_uses_the_tolerances_given_and_its_worst_per_angle_in_order():
    """Half the ISO motion is off the waveform by half of each angle's largest magnitude (ISO 14242-1: flexion +25°,
    adduction +7°, rotation −10°): 12.5°, 3.5°, 5°; within tolerances of 15° it passes, within the default 3° not."""
    iso = iso14242(rate=100.0)
    wide = station_verdict(2, iso.t, 0.5 * iso.q, iso.Fe, "log", Tolerances(alpha=15.0, beta=15.0, gamma=15.0))
    assert (wide.platform, wide.verdict, wide.failing, wide.reason) == (2, "PASS", (), "")
    assert wide.worst_deg == pytest.approx((12.5, 3.5, 5.0), abs=1e-3)
    narrow = station_verdict(2, iso.t, 0.5 * iso.q, iso.Fe, "log", Tolerances(alpha=15.0, beta=3.0, gamma=15.0))
    assert (narrow.verdict, narrow.failing) == ("FAIL", ("beta",))


def test_a_verdict_not_made_names_the_station_or_the_desired_motion():
    station = station_verdict(1, np.zeros(3), np.zeros((3, 2)), np.zeros(3), "log")
    assert (station.platform, station.verdict, station.failing) == (1, "not made", ())
    assert station.reason == "log, station 1: times (3,), angles (3, 2) and load (3,) do not match"
    assert len(station.worst_deg) == 3 and all(math.isnan(x) for x in station.worst_deg)
    desired = station_verdict(0, np.zeros(3), np.zeros((3, 2)), np.zeros(3), "log")
    assert desired.platform == 0 and desired.reason.startswith("log, the desired motion: times (3,)")

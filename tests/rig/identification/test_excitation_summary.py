"""The excitation's verdict against the rig's limits, by hand at the boundary of every comparison, and its records."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from hipsim.records import Level
from hipsim.rig.identification.excitation import Limits
from hipsim.rig.identification.excitation_summary import CalibrationExcitationSummary, ExcitationPeaks, limits_verdict

LIMITS = Limits(
    max_angle=math.radians(30.0),
    min_load=300.0,
    max_load=3000.0,
    max_speed=0.35,
    max_acceleration=2.5,
    torque_limit=0.6,
    min_cond_inv=0.25,
)
#: Every peak exactly at its limit in file units (the limits' SI times the unit's factor, as the verdict converts them:
#: 30° comes back from radians as 29.999999999999996): a peak equal to its limit passes.
AT = ExcitationPeaks(
    math.degrees(LIMITS.max_angle),
    LIMITS.max_speed * 1e3,
    LIMITS.max_acceleration * 1e3,
    0.25,
    torque_Nmm=LIMITS.torque_limit * 1e3,
    load_min_N=300.0,
    load_max_N=3000.0,
)


def test_every_peak_at_its_limit_passes_with_zero_margins():
    verdict = limits_verdict(AT, LIMITS)
    assert verdict.level is Level.PASS and verdict.not_judged == ""
    assert verdict.judged == "the motion's peaks against the rig's limits: each of 7 within"
    margins = {k: v for k, v in verdict.numbers.items() if "_margin" in k}
    assert margins == dict.fromkeys(margins, 0.0) and len(margins) == 7
    assert verdict.numbers["speed_limit_mm_s"] == pytest.approx(350.0) and verdict.numbers["load_min_peak_N"] == 300.0


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"angle_deg": 30.0}, "angle 30 beyond its limit 30 deg"),  # 4e-15 past 29.999999999999996
        ({"speed_mm_s": 350.01}, "speed 350 beyond its limit 350 mm_s"),
        ({"acceleration_mm_s2": 2500.1}, "acceleration 2500 beyond"),
        ({"cond_inv_min": 0.2499}, "cond_inv 0.2499 beyond its limit 0.25"),  # a lower limit: below fails
        ({"torque_Nmm": 600.01}, "torque 600 beyond its limit 600 Nmm"),
        ({"load_max_N": 3000.5}, "load_max 3000 beyond"),
        ({"load_min_N": 299.5}, "load_min 299.5 beyond its limit 300 N"),  # a lower limit
        ({"speed_mm_s": math.nan}, "speed nan beyond"),  # what cannot be compared fails
    ],
)
def test_a_peak_past_its_limit_fails_naming_it(change, named):
    verdict = limits_verdict(replace(AT, **change), LIMITS)
    assert verdict.level is Level.FAIL and verdict.failed and named in verdict.judged, verdict.judged
    assert verdict.judged.count("beyond") == 1  # only the one that broke


def test_margins_by_hand_and_what_a_calibration_motion_leaves_unjudged():
    peaks = ExcitationPeaks(12.0, 200.0, 1000.0, 0.5)  # a calibration motion: no torque, a constant load
    verdict = limits_verdict(peaks, LIMITS)
    assert verdict.level is Level.PASS and verdict.judged.endswith("each of 4 within")
    assert verdict.numbers["angle_margin_deg"] == pytest.approx(18.0) and verdict.numbers["speed_margin_mm_s"] == 150.0
    assert verdict.numbers["cond_inv_margin"] == pytest.approx(0.25)  # peak minus limit: a lower limit
    assert not any(k.startswith(("torque", "load")) for k in verdict.numbers)
    assert verdict.not_judged.startswith("torque, load_max, load_min: not computed")
    assert peaks.to_json() == {
        "angle_deg": 12.0,
        "speed_mm_s": 200.0,
        "acceleration_mm_s2": 1000.0,
        "cond_inv_min": 0.5,
    }


def test_the_calibration_motion_prints_for_under_its_key():
    verdict = limits_verdict(AT, LIMITS)
    summary = CalibrationExcitationSummary("calibration", 0.2, 5, 10.0, 100.0, AT, verdict)
    document = summary.to_json()
    assert document["for"] == "calibration" and "for_" not in document and summary.level is Level.PASS
    assert "for" in CalibrationExcitationSummary.json_schema()["required"]


def test_each_broken_limit_is_named_with_its_unit_and_joined_in_order():
    """Three limits broken at once, each sentence whole: a unit after the limit where there is one, none after the
    singularity measure's; joined by "; " in the checks' order."""
    peaks = replace(AT, acceleration_mm_s2=2600.0, cond_inv_min=0.2, load_max_N=3100.0)
    verdict = limits_verdict(peaks, LIMITS)
    assert verdict.judged == (
        "the motion's peaks against the rig's limits: acceleration 2600 beyond its limit 2500 mm_s2; "
        "cond_inv 0.2 beyond its limit 0.25; load_max 3100 beyond its limit 3000 N"
    )
    assert verdict.numbers["acceleration_margin_mm_s2"] == pytest.approx(-100.0)
    assert verdict.numbers["load_max_margin_N"] == -100.0 and verdict.numbers["cond_inv_margin"] == pytest.approx(-0.05)

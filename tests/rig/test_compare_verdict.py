"""The model-versus-rig acceptance verdict, by hand (hipsim/rig/compare_verdict.py)."""

from __future__ import annotations

import math

import pytest

from hipsim.records import Level, exit_status
from hipsim.rig.compare_verdict import acceptance_verdict


@pytest.mark.parametrize(
    ("worst", "level"),
    [(0.05, Level.PASS), (math.nextafter(0.05, 1.0), Level.FAIL), (0.2, Level.FAIL), (0.0, Level.PASS)],
)
def test_every_motor_within_the_accepted_share_inclusive(worst, level):
    for motor in ("1", "2", "3"):  # the worst one anywhere decides
        errors = {"1": 0.01, "2": 0.02, "3": 0.03} | {motor: worst}
        verdict = acceptance_verdict(errors, 0.05)
        assert verdict.level == level and exit_status([verdict]) == (1 if level == Level.FAIL else 0)
        assert verdict.numbers[f"relative_rms_error_{motor}"] == worst and verdict.numbers["accept"] == 0.05


def test_the_sentence_counts_the_failing_motors_and_no_threshold_judges_nothing():
    verdict = acceptance_verdict({"1": 0.06, "2": 0.07, "3": 0.01}, 0.05)
    assert verdict.judged == "2 of 3 motors exceed the accepted 5 % RMS error"
    open_ = acceptance_verdict({"1": 0.5, "2": 0.7, "3": 0.9}, None)
    assert open_.level == Level.NOT_MADE and exit_status([open_]) == 0 and "--accept" in open_.judged


NOT_JUDGED = "the peak errors and the errors per gait phase (shown, not judged)"


def test_each_verdict_whole_with_its_numbers():
    errors = {"1": 0.01, "2": 0.02, "3": 0.03}
    passed = acceptance_verdict(errors, 0.05)
    assert (passed.level, passed.judged, passed.not_judged) == (
        Level.PASS,
        "every motor's RMS error is within 5 % of its measured RMS torque",
        NOT_JUDGED,
    )
    numbers = {"relative_rms_error_1": 0.01, "relative_rms_error_2": 0.02, "relative_rms_error_3": 0.03}
    assert dict(passed.numbers) == numbers | {"accept": 0.05}
    failed = acceptance_verdict(errors, 0.015)
    assert (failed.level, failed.judged, failed.not_judged) == (
        Level.FAIL,
        "2 of 3 motors exceed the accepted 1.5 % RMS error",
        NOT_JUDGED,
    )
    assert dict(failed.numbers) == numbers | {"accept": 0.015}
    open_ = acceptance_verdict(errors, None)
    assert (open_.level, open_.judged, open_.not_judged) == (
        Level.NOT_MADE,
        "no acceptance threshold given (--accept PERCENT)",
        NOT_JUDGED,
    )
    assert dict(open_.numbers) == numbers


def test_a_motor_whose_error_is_not_a_number_fails():
    verdict = acceptance_verdict({"1": math.nan, "2": 0.0, "3": 0.0}, 0.05)
    assert verdict.level == Level.FAIL and verdict.judged.startswith("1 of 3 motors")

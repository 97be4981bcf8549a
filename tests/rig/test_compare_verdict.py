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

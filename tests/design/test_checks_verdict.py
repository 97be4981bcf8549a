"""A drive's checks: each at its bound, and the verdict over them (hipsim/design/checks.py), by hand."""

from __future__ import annotations

import math

import pytest

from hipsim.design.checks import Check, _check, checks_verdict
from hipsim.records import Level, exit_status


@pytest.mark.parametrize(
    ("value", "passed", "margin"),
    [(10.0, True, 0.0), (math.nextafter(10.0, 11.0), False, None), (8.0, True, 0.2), (12.5, False, -0.25)],
)
def test_a_max_check_passes_up_to_its_limit(value, passed, margin):
    check = _check(1, "peak_curve", value, 10.0)
    assert check.passed is passed
    if margin is not None:
        assert check.margin == pytest.approx(margin, abs=1e-15)


@pytest.mark.parametrize(("value", "passed"), [(2.0, True), (math.nextafter(2.0, 0.0), False), (4.0, True)])
def test_a_min_check_passes_from_its_limit_up(value, passed):
    check = _check(2, "screw_life", value, 2.0)  # a "min" check: the life must reach what is required
    assert check.passed is passed
    assert check.margin == pytest.approx(1 - 2.0 / value)


def _c(module, margin, passed, name="peak_curve"):
    return Check(module, name, 1.0, 1.0, margin, passed)


def test_the_verdict_fails_on_one_failing_check_and_names_the_binding_one():
    checks = (_c(1, 0.4, True), _c(2, -0.1, False), _c(3, 0.05, True), _c(1, None, None, "s1_rms"))
    verdict = checks_verdict(checks, "M1")
    assert verdict.level == Level.FAIL and exit_status([verdict]) == 1
    assert "2 of 3 checks of M1 pass" in verdict.judged and "LN2, margin -0.1" in verdict.judged
    assert verdict.numbers == {"checks_made": 3.0, "checks_failed": 1.0, "binding_margin": -0.1}
    assert verdict.not_judged.startswith("not checked for want of data: ")


def test_the_verdict_passes_when_every_check_made_passes_and_is_open_without_one():
    passing = checks_verdict((_c(1, 0.4, True), _c(2, 0.0, True)))
    assert passing.level == Level.PASS and passing.numbers["binding_margin"] == 0.0 and exit_status([passing]) == 0
    none = checks_verdict((_c(1, None, None),))
    assert none.level == Level.NOT_MADE and exit_status([none]) == 0
    assert checks_verdict(()).level == Level.NOT_MADE

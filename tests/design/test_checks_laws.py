"""A drive's checks at their edges (hipsim/design/checks.py): a check of no data, zero limits and values, the binding
and the first failing check, and a drive that gives no figure at all, every sentence whole."""

from __future__ import annotations

import math

import pytest
from drive_support import RPM, constant_side, only

import hipsim
from hipsim.design.checks import (
    CHECKS,
    FAILURE_ORDER,
    Check,
    _check,
    binding_check,
    checks_verdict,
    drive_checks,
    first_failure,
    margin_order,
)
from hipsim.machine.drive_parts import Drive, Motor
from hipsim.motion.trajectories import iso14242
from hipsim.records import Level


@pytest.fixture(scope="module")
def run():
    return hipsim.analyse(hipsim.load_parameters(), iso14242(rate=100))


def test_a_check_without_its_figures():
    unchecked = _check(1, "s1_rms", 5, None, "the detail", "iso", missing="")
    assert unchecked == Check(1, "s1_rms", 5.0, None, None, None, "the detail", "iso")
    assert isinstance(unchecked.value, float)
    missing = _check(2, "s1_rms", 5.0, 7, "the detail", "iso", missing="no S1 curve")
    assert missing == Check(2, "s1_rms", 5.0, 7.0, None, None, "not checked: no S1 curve", "iso")
    assert isinstance(missing.limit, float)
    assert _check(3, "stroke", None, 2.0) == Check(3, "stroke", None, 2.0, None, None, "", "")


def test_zero_limits_and_values():
    """A max check against a limit of 0: passes (margin 1) only with nothing asked; a min check of a value of 0 passes
    (margin 1) only when nothing is required."""
    assert (_check(1, "stroke", 0.0, 0.0).margin, _check(1, "stroke", 0.0, 0.0).passed) == (1.0, True)
    assert (_check(1, "stroke", -1.0, 0.0).margin, _check(1, "stroke", -1.0, 0.0).passed) == (1.0, True)
    assert (_check(1, "stroke", 0.5, 0.0).margin, _check(1, "stroke", 0.5, 0.0).passed) == (-math.inf, False)
    assert (_check(1, "stroke", 1.0, -1.0).margin, _check(1, "stroke", 1.0, -1.0).passed) == (-math.inf, False)
    assert (_check(1, "screw_life", 0.0, 0.0).margin, _check(1, "screw_life", 0.0, 0.0).passed) == (1.0, True)
    assert (_check(1, "screw_life", 0.0, -1.0).margin, _check(1, "screw_life", 0.0, -1.0).passed) == (1.0, True)
    assert (_check(1, "screw_life", 0.0, 2.0).margin, _check(1, "screw_life", 0.0, 2.0).passed) == (-math.inf, False)
    assert _check(1, "screw_life", 1.0, 4.0).margin == -3.0 and _check(1, "screw_life", 4.0, 1.0).margin == 0.75
    made = _check(1, "stroke", 3, 4, "d", "t")
    assert (made.margin, made.passed, made.detail, made.trajectory) == (0.25, True, "d", "t")
    assert type(made.margin) is float and type(made.passed) is bool


def test_the_binding_and_the_first_failing_check():
    checks = [
        _check(1, "stroke", 5.0, 4.0),  # margin −0.25
        _check(2, "stroke", 6.0, 4.0),  # margin −0.5
        _check(3, "max_speed", 5.5, 5.0),  # margin −0.1
        _check(1, "peak_curve", 8.0, 4.0),  # margin −1
        _check(2, "s1_rms", 1.0, None),  # not made
    ]
    assert margin_order(checks[4]) == math.inf and margin_order(checks[0]) == -0.25
    assert binding_check(checks) is checks[3]
    assert binding_check([checks[4]]) is None and binding_check([]) is None
    # The top speed first, whatever the margins; then the worst module of the first failing kind.
    assert first_failure(checks) is checks[2]
    assert first_failure(checks[:2]) is checks[1]
    assert first_failure([checks[0], checks[3]]) is checks[3]  # the peak curve comes before the stroke
    assert first_failure([_check(1, "stroke", 1.0, 4.0), checks[4]]) is None
    assert FAILURE_ORDER[0] == "max_speed" and set(FAILURE_ORDER) == set(CHECKS) and len(FAILURE_ORDER) == len(CHECKS)


def test_a_check_s_kind():
    check = _check(2, "max_speed", 3000, 4000, "d", "iso")
    assert check.kind is CHECKS["max_speed"]
    assert (check.kind.label, check.kind.unit, check.kind.bound) == ("peak motor speed", "rpm", "max")


def test_the_verdict_s_sentences_whole():
    checks = [
        _check(1, "stroke", 3.0, 4.0),
        _check(2, "max_speed", 5.0, 4.0),
        _check(3, "s1_rms", 1.0, None, missing="x"),
    ]
    verdict = checks_verdict(checks, "motor A")
    assert verdict.level == Level.FAIL
    assert verdict.judged == "1 of 2 checks of motor A pass; binding: peak motor speed, LN2, margin -0.25"
    assert verdict.not_judged == "not checked for want of data: RMS torque under the S1 curve at the mean speed"
    assert dict(verdict.numbers) == {"checks_made": 2.0, "checks_failed": 1.0, "binding_margin": -0.25}
    passed = checks_verdict(checks[:1])
    assert passed.level == Level.PASS and passed.not_judged == ""
    assert passed.judged == "1 of 1 checks of the drive pass; binding: carriage stroke, LN1, margin +0.25"
    none = checks_verdict(checks[2:], "motor B")
    assert (none.level, none.judged) == (Level.NOT_MADE, "no check of motor B could be made")
    assert none.not_judged.startswith("not checked for want of data: RMS torque")
    assert checks_verdict([]).judged == "no check of the drive could be made" and checks_verdict([]).not_judged == ""


def test_a_drive_of_no_figures_says_what_each_check_needs(run):
    """A motor known by name only, no amplifier, no screw: every check unchecked and why, the values still shown."""
    side = constant_side(run, speed=1500 * RPM, torque=0.3, axial=200.0)
    checks = drive_checks(side, Drive(Motor("bare")))
    assert len(checks) == 3 * len(CHECKS) and [c.module for c in checks[:: len(CHECKS)]] == [1, 2, 3]
    expected = {
        "peak_curve": "no peak torque curve",
        "s1_rms": "no S1 curve",
        "max_speed": "no top speed",
        "inertia_ratio": "no rotor inertia",
        "winding_rise": "needs thermal_resistance_K_W, torque_constant_Nm_A and winding_resistance_ohm, or an S1 curve",
        "amplifier_peak_current": "no torque constant",
        "amplifier_rms_current": "no torque constant",
        "regen_energy": "no dc bus energy given",
        "regen_power_mean": "no braking power given",
        "regen_power_peak": "no braking peak power given",
        "screw_life": "no dynamic load rating C_a",
        "critical_speed": "needs root_diameter_mm, free_length_mm and end_fixing",
        "buckling": "needs root_diameter_mm, free_length_mm and end_fixing",
        "stroke": "no usable stroke given",
        "axial_force": "no permissible axial load given",
    }
    for module in (1, 3):
        for key, words in expected.items():
            check = only(checks, key, module)
            assert (check.detail, check.passed, check.margin) == (f"not checked: {words}", None, None), key
            assert check.trajectory == run.trajectory.name
    assert only(checks, "peak_curve").value == pytest.approx(300.0) and only(
        checks, "s1_rms", 2
    ).value == pytest.approx(300.0)
    assert only(checks, "max_speed").value == pytest.approx(1500.0) and only(checks, "max_speed").limit is None
    assert only(checks, "inertia_ratio").value is None and only(checks, "amplifier_peak_current").value is None
    assert only(checks, "buckling", 3).value == pytest.approx(200.0) and only(
        checks, "axial_force"
    ).value == pytest.approx(200.0)
    assert (
        only(checks, "critical_speed").value == pytest.approx(only(checks, "critical_speed").value)
        and only(checks, "critical_speed").limit is None
    )
    rules = Drive(Motor("bare")).rules
    assert only(checks, "inertia_ratio").limit == rules.inertia_ratio_max
    assert only(checks, "winding_rise").limit == rules.winding_rise_max
    assert only(checks, "screw_life").limit == rules.life_target_cycles
    assert checks_verdict(checks).level == Level.NOT_MADE

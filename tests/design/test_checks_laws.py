"""A drive's checks at their edges (hipsim/design/checks.py): a check of no data, zero limits and values, the binding
and the first failing check, and a drive that gives no figure at all, every sentence whole."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from drive_support import RPM, constant_side, curve, only

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
from hipsim.design.demand import ScrewSide
from hipsim.machine.drive_parts import Amplifier, Drive, LeadScrew, Motor, SizingRules
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
    assert (_check(1, "screw_life", 0.0, 0.5).margin, _check(1, "screw_life", 0.0, 0.5).passed) == (-math.inf, False)
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
    two = checks_verdict([*checks, _check(1, "stroke", 1.0, None, missing="y")])
    assert two.not_judged == (
        "not checked for want of data: RMS torque under the S1 curve at the mean speed, carriage stroke"
    )


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


# ---------------------------------------------------------------------------
# A drive with every figure given: every check made, its detail read whole (numbers and units worked out by hand)

STEEL_E, STEEL_RHO = 2.06e11, 7850.0  # [Pa], [kg/m³]: the screw steel's figures


def _full_side(run) -> ScrewSide:
    """100 samples of 10 ms, the last one flagged (no weight, so 0.99 s counted) holding values that must be ignored;
    the trajectory holds 2 test cycles. Module 1: 1500 rpm against −0.3 N·m (braking), 200 N; module 2: 0.3 N·m for
    the first half second, 0.1 N·m after; module 3: 0.3 N·m accelerating at 100 rad/s²."""
    n = len(run.t)
    w = np.full(n, 0.01)
    w[-1] = 0.0
    speed = np.full((n, 3), 1500 * RPM)
    torque = np.full((n, 3), 0.3)
    torque[:, 0] = -0.3
    torque[50:, 1] = 0.1
    acceleration = np.zeros((n, 3))
    acceleration[:, 2] = 100.0
    inertia = np.full((n, 3), 1e-4)
    inertia[30, 0] = 1.23499e-4  # the worst weighted pose: 1.23 kg·cm², a hair under rounding up
    inertia[60, 0] = np.nan  # a pose the model could not reach: never the worst
    inertia[-1, 0] = 5e-4  # flagged: not counted
    L = np.empty((n, 2, 3))
    L[:, 0, :] = 0.1 + 0.001 * np.arange(n)[:, None]  # 98 mm over the samples counted
    L[-1, 0, :] = 0.5  # flagged
    L[:, 1, :] = 0.3 + 0.002 * np.arange(n)[:, None]  # the second platform: not the stroke checked
    run = dataclasses.replace(run, L=L)
    return ScrewSide(run, 2.0, w, speed, acceleration, torque, np.full((n, 3), 200.0), inertia)


def test_a_drive_of_every_figure_reads_each_check_whole(run):
    motor = Motor(
        "full",
        continuous=curve([0, 3000], [0.5, 0.4]),
        peak=curve([0, 3000, 4000], [1.0, 1.0, 0.6]),
        rotor_inertia=2.34499e-5,  # 0.234 kg·cm², a hair under rounding up
        torque_constant=0.4,
        winding_resistance=4.0,
        thermal_resistance=2.0,
        thermal_time_constant=0.1,
    )
    amplifier = Amplifier(
        peak_current=2.0, continuous_current=0.5, dc_bus_energy=20.0, braking_power=40.0, braking_peak_power=100.0
    )
    screw = LeadScrew(
        "s",
        dynamic_load_rating=10_000.0,
        preload=100.0,
        root_diameter=0.0129,
        free_length=0.35,
        end_fixing="fixed-supported",
        stroke=0.2,
        axial_force=800.0,
    )
    rules = SizingRules(
        inertia_ratio_max=6.0,
        life_target_cycles=1e6,
        winding_rise_max=50.0,
        critical_speed_factor=0.7,
        buckling_factor=0.4,
    )
    checks = drive_checks(_full_side(run), Drive(motor, amplifier, screw=screw), rules)
    assert all(c.passed is not None for c in checks)

    def whole(name, value, limit, detail, module=1):
        check = only(checks, name, module)
        assert (check.value, check.limit, check.detail) == (pytest.approx(value), pytest.approx(limit), detail), name
        assert check.trajectory == run.trajectory.name
        return check

    omega = 1500 * 2 * math.pi / 60  # [rad/s]
    whole("peak_curve", 300.0, 1000.0, "at 1500 rpm, t = 0.000 s")
    whole("s1_rms", 300.0, 450.0, "mean speed 1500 rpm")  # S1 at 1500 rpm: halfway from 0.5 to 0.4 N·m
    assert whole("max_speed", 1500.0, 4000.0, "").passed  # the top speed: the peak curve's end
    # Inertia: the worst weighted, reachable pose (sample 30), in kg·cm² (1 kg·m² = 10⁴ kg·cm²).
    ratio = whole("inertia_ratio", 1.23499e-4 / 2.34499e-5, 6.0, "load 1.23 kg·cm² at t = 0.300 s, rotor 0.234 kg·cm²")
    assert ratio.passed
    # Winding: H = R_th·3/2·R_pp/k_t²·τ² = 2·1.5·4/0.16·τ² = 75 K/(N·m)²·τ².
    whole("winding_rise", 75 * 0.09, 50.0, "peak of the periodic cycle; mean 6.75 K; R_th given")
    mean_2 = 75 * (0.5 * 0.09 + 0.49 * 0.01) / 0.99  # module 2: 0.3 N·m for 0.5 s, 0.1 N·m for 0.49 s
    rise_2 = only(checks, "winding_rise", 2)
    assert (
        rise_2.detail
        == f"peak of the periodic cycle; mean {mean_2:.3g} K; R_th given"
        == ("peak of the periodic cycle; mean 3.78 K; R_th given")
    )
    assert mean_2 < rise_2.value < 75 * 0.09  # τ_th = 0.1 s: the peak between the mean and the hot half's 6.75 K
    whole("amplifier_peak_current", 0.75, 2.0, "")
    assert whole("amplifier_rms_current", 0.75, 0.5, "").passed is False
    whole("amplifier_peak_current", (0.3 + 2.34499e-5 * 100.0) / 0.4, 2.0, "", module=3)  # the rotor accelerated too
    # Regeneration: 0.3 N·m·157.08 rad/s = 47.12 W braking for 0.99 s, over 2 cycles.
    assert whole("regen_energy", 0.3 * omega * 0.99 / 2, 20.0, "").passed is False
    assert whole("regen_power_mean", 0.3 * omega, 40.0, "").passed is False
    assert whole("regen_power_peak", 0.3 * omega, 100.0, "").passed
    # Screw life (ISO 3408-5, preload 100 N, F = 200 N ≤ 2^1.5·100 N): the loaded half and the other.
    f1 = 100.0 * (1 + 200.0 / (2**1.5 * 100.0)) ** 1.5
    f2 = f1 - 200.0
    life = sum(((10_000.0 / f) ** 3 * 1e6) ** (-10 / 9) for f in (f1, f2)) ** (-9 / 10)
    equivalent = 10_000.0 / (life / 1e6) ** (1 / 3)
    revolutions = 25.0 * 0.99 / 2  # 25 rev/s for 0.99 s over 2 cycles
    assert f"{life:.3g} {equivalent:.0f}" == "9.01e+10 223"
    whole(
        "screw_life", life / revolutions, 1e6, "9.01e+10 rev at 12.4 rev/cycle; equivalent load 223 N (preload 100 N)"
    )
    # Whirling: λ²/l²·d₂/4·√(E/ρ) with λ = 3.9266 (fixed–supported); buckling: m·π²·E·(π d₂⁴/64)/l², m = 2.046.
    n_cr = 3.9266**2 / 0.35**2 * 0.0129 / 4 * math.sqrt(STEEL_E / STEEL_RHO) * 60 / (2 * math.pi)  # [rpm]
    assert n_cr == pytest.approx(19_857, rel=1e-4)
    whole("critical_speed", 1500.0, 0.7 * n_cr, "0.7 × critical speed")
    f_k = 2.046 * math.pi**2 * STEEL_E * math.pi * 0.0129**4 / 64 / 0.35**2
    whole("buckling", 200.0, 0.4 * f_k, "0.4 × Euler load")
    assert whole("stroke", 98.0, 200.0, "").passed  # mm, the flagged sample and the second platform left out
    whole("axial_force", 200.0, 800.0, "")


def test_the_worst_point_of_the_peak_curve_and_beyond_its_top_speed(run):
    """1000 rpm at 0.3 N·m but at t = 0.5 s, 5000 rpm: past the curve's 4000 rpm end. Idle there, the worst point is
    any other (the first); pulling there, it is that one."""
    side = constant_side(run, speed=1000 * RPM, torque=0.3)
    side.speed[50] = 5000 * RPM
    side.torque[50] = 0.0
    peak = Motor("m", peak=curve([0, 3000, 4000], [1.0, 1.0, 0.6]))
    idle = only(drive_checks(side, Drive(peak)), "peak_curve")
    assert (idle.value, idle.limit, idle.detail) == (pytest.approx(300.0), 1000.0, "at 1000 rpm, t = 0.000 s")
    side.torque[50] = 0.3
    pulling = only(drive_checks(side, Drive(peak)), "peak_curve")
    assert (pulling.limit, pulling.margin, pulling.detail) == (
        0.0,
        -math.inf,
        "at 5000 rpm (beyond the curve's top speed), t = 0.500 s",
    )


def test_a_motor_without_torque_constant_or_thermal_figures(run):
    """R_th and R_pp without k_t: the rise scaled from the S1 stall torque; the currents unchecked. A k_t without an
    amplifier: the currents say which rating is missing. An S1 curve of no stall torque: no rise at all."""
    side = constant_side(run, speed=1500 * RPM, torque=0.3)
    motor = Motor("m", continuous=curve([0, 3000], [0.6, 0.5]), thermal_resistance=2.0, winding_resistance=4.0)
    checks = drive_checks(side, Drive(motor))
    rise = only(checks, "winding_rise")
    assert rise.value == pytest.approx(100.0 * (0.3 / 0.6) ** 2)  # rated 100 K at the 0.6 N·m stall torque
    assert rise.detail == "mean (no thermal time constant given); mean 25 K; R_th from the S1 stall torque at 100 K"
    assert only(checks, "amplifier_peak_current").detail == "not checked: no torque constant"
    with_kt = drive_checks(side, Drive(Motor("m", torque_constant=0.5)))
    assert only(with_kt, "amplifier_peak_current").detail == "not checked: no amplifier peak current"
    assert only(with_kt, "amplifier_rms_current").detail == "not checked: no amplifier continuous current"
    assert only(with_kt, "amplifier_peak_current").value == pytest.approx(0.6)
    no_stall = only(drive_checks(side, Drive(Motor("m", continuous=curve([0, 3000], [0.0, 0.5])))), "winding_rise")
    assert no_stall.passed is None and no_stall.detail.startswith("not checked: needs thermal_resistance_K_W")


def test_a_slow_screw_s_life_in_cycles(run):
    """Half a revolution per cycle (30 rpm for 1 s): the life in cycles is twice the life in revolutions."""
    side = constant_side(run, speed=30 * RPM, torque=0.1, axial=500.0)
    check = only(
        drive_checks(side, Drive(Motor("m"), screw=LeadScrew("s", dynamic_load_rating=10_000.0))), "screw_life"
    )
    assert check.value == pytest.approx((10_000.0 / 500.0) ** 3 * 1e6 / 0.5)
    assert check.detail == "8e+09 rev at 0.5 rev/cycle; equivalent load 500 N (preload 0 N)"

"""The checks of a drive along a run (hipsim.design.checks): each against a hand calculation on a constant or simple duty."""

import math

import numpy as np
import pytest
from drive_support import RPM, constant_side, curve, only

import hipsim
from hipsim.design.checks import CHECKS, drive_checks
from hipsim.design.demand import ScrewSide, reflected_inertia, screw_side
from hipsim.machine.drive_parts import Amplifier, Drive, Gearbox, LeadScrew, Motor
from hipsim.motion.trajectories import iso14242


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def run(params):
    return hipsim.analyse(params, iso14242(rate=100))  # 100 samples, 1 s, periodic


# ---------------------------------------------------------------------------
# Motor checks against hand calculations


def test_torque_curves_speed_and_currents_on_a_constant_duty(run):
    motor = Motor(
        "m",
        continuous=curve([0, 3000], [0.5, 0.4]),
        peak=curve([0, 3000, 4000], [1.0, 1.0, 0.6]),
        torque_constant=0.5,
        rotor_inertia=1e-4,
    )
    amplifier = Amplifier(peak_current=2.0, continuous_current=0.5)
    checks = drive_checks(constant_side(run, speed=1500 * RPM, torque=0.3), Drive(motor, amplifier))
    s1 = only(checks, "s1_rms")
    assert s1.value == pytest.approx(300.0) and s1.limit == pytest.approx(450.0)  # S1 at 1500 rpm: halfway 0.5 → 0.4
    assert s1.margin == pytest.approx(1 - 300 / 450) and s1.passed
    peak = only(checks, "peak_curve")
    assert peak.value == pytest.approx(300.0) and peak.limit == pytest.approx(1000.0)
    speed = only(checks, "max_speed")
    assert speed.value == pytest.approx(1500.0) and speed.limit == pytest.approx(4000.0)  # the peak curve's end
    assert only(checks, "amplifier_peak_current").value == pytest.approx(0.6)
    rms_current = only(checks, "amplifier_rms_current")
    assert (
        rms_current.value == pytest.approx(0.6)
        and rms_current.passed is False
        and rms_current.margin == pytest.approx(1 - 0.6 / 0.5)
    )


def test_the_worst_point_under_a_falling_peak_curve(run):
    """Constant torque, speed rising through the cycle: the worst point is the fastest, where the curve is lowest."""
    side = constant_side(run, speed=0.0, torque=0.5)
    ramp = np.linspace(0.0, 3500.0, 100)[:, None] * RPM * np.ones(3)
    side = ScrewSide(
        side.run, 1.0, side.weights, ramp, side.acceleration, side.torque, side.axial_load, side.load_inertia
    )
    peak = curve([0, 3000, 4000], [1.0, 1.0, 0.6])
    check = only(drive_checks(side, Drive(Motor("m", peak=peak))), "peak_curve")
    assert check.limit == pytest.approx((1.0 - 0.4 * 500 / 1000) * 1e3)  # 0.8 N·m at 3500 rpm
    assert check.value == pytest.approx(500.0) and check.passed and "3500 rpm" in check.detail
    beyond = only(drive_checks(side, Drive(Motor("m", peak=curve([0, 3000], [1.0, 1.0])))), "peak_curve")
    assert beyond.limit == 0.0 and beyond.passed is False and beyond.margin == -math.inf  # past the curve's end


def test_regenerated_energy_and_power_of_a_braking_cycle(run):
    """Torque held against the motion for 1 s: the motor brakes at τ·ω throughout."""
    tau, omega = 0.3, 150.0
    side = constant_side(run, speed=omega, torque=-tau, cycles=2.0)  # the 1 s trajectory holds two test cycles
    amplifier = Amplifier(dc_bus_energy=20.0, braking_power=40.0, braking_peak_power=100.0)
    checks = drive_checks(side, Drive(Motor("m"), amplifier))
    assert only(checks, "regen_energy").value == pytest.approx(tau * omega * 1.0 / 2)  # per cycle
    assert only(checks, "regen_power_mean").value == pytest.approx(tau * omega)
    assert only(checks, "regen_power_peak").value == pytest.approx(tau * omega)
    assert only(checks, "regen_energy").passed is False and only(checks, "regen_power_peak").passed is True
    motoring = drive_checks(constant_side(run, speed=omega, torque=tau), Drive(Motor("m"), amplifier))
    assert only(motoring, "regen_energy").value == 0.0


def test_winding_rise_of_a_constant_torque(run):
    """ΔT = R_th·(3/2)·R_pp·(τ/k_t)², the same at every instant of a constant duty."""
    motor = Motor("m", torque_constant=0.5, winding_resistance=4.0, thermal_resistance=2.0, thermal_time_constant=600.0)
    check = only(drive_checks(constant_side(run, speed=100.0, torque=0.3), Drive(motor)), "winding_rise")
    assert check.value == pytest.approx(2.0 * 1.5 * 4.0 * (0.3 / 0.5) ** 2, rel=1e-9)
    assert check.limit == 100.0 and check.passed
    # Without R_th: the S1 stall torque is rated at the rated rise, so ΔT = 100 K·(τ/T_0)².
    from_s1 = only(
        drive_checks(constant_side(run, 100.0, 0.3), Drive(Motor("m", continuous=curve([0, 3000], [0.6, 0.5])))),
        "winding_rise",
    )
    assert from_s1.value == pytest.approx(100.0 * (0.3 / 0.6) ** 2)


def test_missing_data_says_what_is_missing(run):
    checks = drive_checks(constant_side(run, 100.0, 0.3), Drive(Motor("bare")))
    for name in (
        "peak_curve",
        "s1_rms",
        "inertia_ratio",
        "winding_rise",
        "screw_life",
        "critical_speed",
        "amplifier_peak_current",
    ):
        check = only(checks, name)
        assert check.passed is None and check.margin is None and check.detail.startswith("not checked: "), name
    assert "rotor inertia" in only(checks, "inertia_ratio").detail
    assert {c.name for c in checks} == set(CHECKS)


# ---------------------------------------------------------------------------
# Lead screw checks


def test_screw_life_of_a_constant_load_and_speed(run):
    """ISO 3408-5 without preload: L10 = (C_a/F)³·10⁶ rev; in test cycles, divided by the revolutions per cycle."""
    speed, force, rating = 1200 * RPM, 500.0, 10_000.0
    screw = LeadScrew("s", dynamic_load_rating=rating)
    check = only(
        drive_checks(constant_side(run, speed, 0.1, axial=force), Drive(Motor("m"), screw=screw)), "screw_life"
    )
    revolutions_per_cycle = 1200 / 60 * 1.0  # 20 rev in the 1 s cycle
    assert check.value == pytest.approx((rating / force) ** 3 * 1e6 / revolutions_per_cycle, rel=1e-12)
    assert check.limit == 5e6 and check.passed and check.margin == pytest.approx(1 - 5e6 / check.value)


def test_screw_checks_use_the_screw_speed_and_the_axial_load(run):
    screw = LeadScrew(
        "s", root_diameter=0.0129, free_length=0.35, end_fixing="fixed-supported", axial_force=400.0, stroke=0.2
    )
    gearbox = Gearbox("belt", ratio=2.0)
    checks = drive_checks(
        constant_side(run, 1000 * RPM, 0.1, axial=-450.0), Drive(Motor("m"), gearbox=gearbox, screw=screw)
    )
    assert only(checks, "critical_speed").value == pytest.approx(1000.0)  # the screw's speed, not the motor's 2000 rpm
    assert only(checks, "buckling").value == pytest.approx(450.0)
    axial = only(checks, "axial_force")
    assert axial.value == pytest.approx(450.0) and axial.passed is False


# ---------------------------------------------------------------------------
# Reflected inertia, through a gearbox


def test_inertia_ratio_check_reflects_through_the_gearbox(params, run):
    side = screw_side(run)
    motor = Motor("m", rotor_inertia=2e-5)
    gearbox = Gearbox("g", ratio=2.0, efficiency=0.95, inertia=1e-5)
    check = only(drive_checks(side, Drive(motor, gearbox=gearbox)), "inertia_ratio", module=2)
    M = reflected_inertia(params, run.trajectory)
    assert check.value == pytest.approx((M[:, 1, 1].max() / 4 + 1e-5) / 2e-5, rel=1e-12)
    assert check.limit == 10.0

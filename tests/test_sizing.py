"""Drive sizing (issue 14): every check against a hand calculation, the reflected inertia against the kinetic energy, the ranking."""

import math
import re

import numpy as np
import pytest

import hipsim
from hipsim.design.sizing import (
    CHECKS,
    ScrewSide,
    axial_screw_load,
    buckling_load,
    critical_speed,
    drive_checks,
    motor_duty,
    motor_thrust,
    rank_drives,
    reflected_inertia,
    screw_life,
    screw_side,
    sizing,
    winding_rise,
)
from hipsim.analytic import kinematics, mechanical_energy
from hipsim.analytic.inverse_kinematics import slider_heights
from hipsim.machine.drive import Amplifier, Drive, Gearbox, LeadScrew, Motor, SizingRules, TorqueSpeedCurve
from hipsim.motion.trajectories import Trajectory, iso14242

RPM = 2 * math.pi / 60  # rad/s per rpm


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module")
def run(params):
    return hipsim.analyse(params, iso14242(rate=100))  # 100 samples, 1 s, periodic


def constant_side(run, speed, torque, axial=0.0, acceleration=0.0, inertia=1e-4, cycles=1.0) -> ScrewSide:
    """Screw-shaft demands held constant over the run's 1 s (100 samples of 10 ms): closed forms apply."""
    n = len(run.t)
    full = lambda x: np.full((n, 3), float(x))  # noqa: E731
    return ScrewSide(run, cycles, np.full(n, 0.01), full(speed), full(acceleration), full(torque), full(axial), full(inertia))


def only(checks, name, module=1):
    (check,) = [c for c in checks if c.name == name and c.module == module]
    return check


def curve(speeds_rpm, torques_Nm):
    return TorqueSpeedCurve(np.asarray(speeds_rpm, dtype=float) * RPM, torques_Nm)


# ---------------------------------------------------------------------------
# The two forces along a screw


def test_motor_thrust_and_axial_screw_load_differ_by_the_screw_rotor_and_friction(params):
    rough = params.replace(screw_coulomb=0.05, screw_viscous=2e-4)
    run = hipsim.analyse(rough, iso14242(rate=200))
    thrust, load = motor_thrust(run), axial_screw_load(run)
    t = run.torques
    speed = t.motor_speed
    friction = 0.05 * speed / np.sqrt(speed**2 + rough.friction.epsilon**2) + 2e-4 * speed
    np.testing.assert_allclose((thrust - load) * rough.lead / (2 * math.pi), t.screws + friction, rtol=1e-10, atol=1e-12)
    assert np.abs(thrust - load).max() > 20.0  # the difference is not small on this machine: 50 N·mm of friction alone is 31 N


# ---------------------------------------------------------------------------
# The motor's duty through a gearbox


def test_motor_torque_through_a_gearbox_with_rotor_inertia(run):
    motor = Motor("m", rotor_inertia=2e-5)
    gearbox = Gearbox("g", ratio=2.0, efficiency=0.9, inertia=1e-5)
    driving = motor_duty(constant_side(run, speed=100.0, torque=0.4, acceleration=50.0), Drive(motor, gearbox=gearbox))
    # Driving: τ_m = τ/(i·η) + (J_m + J_g)·i·θ̈ = 0.4/1.8 + 3e-5·2·50.
    assert driving.torque == pytest.approx(np.full((100, 3), 0.4 / 1.8 + 3e-3))
    assert driving.speed == pytest.approx(np.full((100, 3), 200.0))
    # Driven back (torque against the motion): τ_m = τ·η/i.
    regenerating = motor_duty(constant_side(run, speed=100.0, torque=-0.4), Drive(motor, gearbox=gearbox))
    assert regenerating.torque == pytest.approx(np.full((100, 3), -0.4 * 0.9 / 2))
    assert regenerating.power == pytest.approx(np.full((100, 3), -0.18 * 200.0))


# ---------------------------------------------------------------------------
# Motor checks against hand calculations


def test_torque_curves_speed_and_currents_on_a_constant_duty(run):
    motor = Motor(
        "m", continuous=curve([0, 3000], [0.5, 0.4]), peak=curve([0, 3000, 4000], [1.0, 1.0, 0.6]),
        torque_constant=0.5, rotor_inertia=1e-4,
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
    assert rms_current.value == pytest.approx(0.6) and rms_current.passed is False and rms_current.margin == pytest.approx(1 - 0.6 / 0.5)


def test_the_worst_point_under_a_falling_peak_curve(run):
    """Constant torque, speed rising through the cycle: the worst point is the fastest, where the curve is lowest."""
    side = constant_side(run, speed=0.0, torque=0.5)
    ramp = np.linspace(0.0, 3500.0, 100)[:, None] * RPM * np.ones(3)
    side = ScrewSide(side.run, 1.0, side.weights, ramp, side.acceleration, side.torque, side.axial_load, side.load_inertia)
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
    from_s1 = only(drive_checks(constant_side(run, 100.0, 0.3), Drive(Motor("m", continuous=curve([0, 3000], [0.6, 0.5])))), "winding_rise")
    assert from_s1.value == pytest.approx(100.0 * (0.3 / 0.6) ** 2)


def test_winding_rise_of_a_square_wave_has_the_first_order_closed_form():
    """Loss on for half the period, off for the other half: the periodic peak is H/(1 + a), a = exp(−T/2τ)."""
    period, tau, H = 2.0, 1.5, 50.0
    n = 2000
    heating = np.where(np.arange(n) < n // 2, H, 0.0)[:, None]
    mean, peak = winding_rise(heating, np.full(n, period / n), tau)
    a = math.exp(-period / 2 / tau)
    assert mean[0] == pytest.approx(H / 2)
    assert peak[0] == pytest.approx(H / (1 + a), rel=1e-9)
    _, no_time_constant = winding_rise(heating, np.full(n, period / n), None)
    assert no_time_constant[0] == pytest.approx(H / 2)


def test_missing_data_says_what_is_missing(run):
    checks = drive_checks(constant_side(run, 100.0, 0.3), Drive(Motor("bare")))
    for name in ("peak_curve", "s1_rms", "inertia_ratio", "winding_rise", "screw_life", "critical_speed", "amplifier_peak_current"):
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
    check = only(drive_checks(constant_side(run, speed, 0.1, axial=force), Drive(Motor("m"), screw=screw)), "screw_life")
    revolutions_per_cycle = 1200 / 60 * 1.0  # 20 rev in the 1 s cycle
    assert check.value == pytest.approx((rating / force) ** 3 * 1e6 / revolutions_per_cycle, rel=1e-12)
    assert check.limit == 5e6 and check.passed and check.margin == pytest.approx(1 - 5e6 / check.value)


def test_screw_life_with_a_preloaded_double_nut():
    """F₁ = F_pr(1 + F/(2^1.5 F_pr))^1.5, F₂ = F₁ − F; L = (L₁^(-10/9) + L₂^(-10/9))^(-9/10)."""
    force, preload, rating = 500.0, 300.0, 10_000.0
    n = 50
    life, equivalent = screw_life(np.full(n, force), np.full(n, 100.0), np.full(n, 0.02), rating, preload)
    f1 = preload * (1 + force / (2**1.5 * preload)) ** 1.5
    f2 = f1 - force
    l1, l2 = (rating / f1) ** 3 * 1e6, (rating / f2) ** 3 * 1e6
    assert life == pytest.approx((l1 ** (-10 / 9) + l2 ** (-10 / 9)) ** (-9 / 10), rel=1e-12)
    assert equivalent == pytest.approx(rating / (life / 1e6) ** (1 / 3))
    # A load beyond 2^1.5·F_pr lifts one half off: the other carries it all.
    life, _ = screw_life(np.full(n, 1000.0), np.full(n, 100.0), np.full(n, 0.02), rating, preload)
    assert life == pytest.approx((rating / 1000.0) ** 3 * 1e6)


def test_screw_life_under_a_load_that_changes_direction():
    """Half the revolutions pulling, half pushing, no preload: each flank sees half; L = L_F·2^(1/9)... by the combination rule."""
    force, rating = 400.0, 8000.0
    load = np.where(np.arange(100) < 50, force, -force)
    life, _ = screw_life(load, np.full(100, 50.0), np.full(100, 0.01), rating)
    each = (rating / (0.5 * force**3) ** (1 / 3)) ** 3 * 1e6  # each flank: cubic mean over all revolutions
    assert life == pytest.approx((2 * each ** (-10 / 9)) ** (-9 / 10), rel=1e-12)


@pytest.mark.parametrize(
    "fixing, thk_speed, thk_buckling",
    # Ball-screw makers' chart factors (safety factors 0.8 and 0.5 included): n = f·d₂/l²·10⁷ rpm, P = η·d₂⁴/l²·10⁴ N (mm).
    [("fixed-free", 3.4, 1.3), ("supported-supported", 9.7, 5.1), ("fixed-supported", 15.1, 10.2), ("fixed-fixed", 21.9, 20.3)],
)
def test_critical_speed_and_buckling_match_the_makers_charts(fixing, thk_speed, thk_buckling):
    d, l = 12.9, 350.0  # mm
    screw = LeadScrew("s", root_diameter=d * 1e-3, free_length=l * 1e-3, end_fixing=fixing)
    rules = SizingRules()
    assert rules.critical_speed_factor * critical_speed(screw) / RPM == pytest.approx(thk_speed * d / l**2 * 1e7, rel=0.02)
    assert rules.buckling_factor * buckling_load(screw) == pytest.approx(thk_buckling * d**4 / l**2 * 1e4, rel=0.05)


def test_screw_checks_use_the_screw_speed_and_the_axial_load(run):
    screw = LeadScrew("s", root_diameter=0.0129, free_length=0.35, end_fixing="fixed-supported", axial_force=400.0, stroke=0.2)
    gearbox = Gearbox("belt", ratio=2.0)
    checks = drive_checks(constant_side(run, 1000 * RPM, 0.1, axial=-450.0), Drive(Motor("m"), gearbox=gearbox, screw=screw))
    assert only(checks, "critical_speed").value == pytest.approx(1000.0)  # the screw's speed, not the motor's 2000 rpm
    assert only(checks, "buckling").value == pytest.approx(450.0)
    axial = only(checks, "axial_force")
    assert axial.value == pytest.approx(450.0) and axial.passed is False


# ---------------------------------------------------------------------------
# Reflected inertia


def test_reflected_inertia_is_the_kinetic_energy_inertia_along_the_cycle(params):
    trajectory = iso14242(rate=200)
    M = reflected_inertia(params, trajectory)
    np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), rtol=0, atol=1e-12 * np.abs(M).max())
    speed = hipsim.analyse(params, trajectory).torques.motor_speed
    kinetic, _ = mechanical_energy(params, kinematics(params, trajectory), lever_spin=True)
    np.testing.assert_allclose(0.5 * np.einsum("ni,nij,nj->n", speed, M, speed), kinetic, rtol=1e-10)


def test_each_modules_load_inertia_is_the_energy_of_moving_that_motor_alone(params):
    """M_θ,ii = 2·KE when only screw i turns at 1 rad/s: q̇ from finite differences of the slider heights."""
    q = iso14242(rate=8).q
    h = 1e-6
    G = np.stack([(slider_heights(params, q + h * e)[:, 0] - slider_heights(params, q - h * e)[:, 0]) / (2 * h) for e in np.eye(3)], axis=-1)
    G *= 2 * math.pi / params.lead
    M = reflected_inertia(params, Trajectory(np.arange(8) * 0.1, q, np.zeros_like(q), np.zeros_like(q), np.full(8, 300.0)))
    for i in range(3):
        qd = np.linalg.solve(G, np.eye(3)[i])
        alone = Trajectory(np.arange(8) * 0.1, q, qd, np.zeros_like(q), np.full(8, 300.0))
        kinetic, _ = mechanical_energy(params, kinematics(params, alone), lever_spin=True)
        np.testing.assert_allclose(M[:, i, i], 2 * kinetic, rtol=1e-7)


def test_inertia_ratio_check_reflects_through_the_gearbox(params, run):
    side = screw_side(run)
    motor = Motor("m", rotor_inertia=2e-5)
    gearbox = Gearbox("g", ratio=2.0, efficiency=0.95, inertia=1e-5)
    check = only(drive_checks(side, Drive(motor, gearbox=gearbox)), "inertia_ratio", module=2)
    M = reflected_inertia(params, run.trajectory)
    assert check.value == pytest.approx((M[:, 1, 1].max() / 4 + 1e-5) / 2e-5, rel=1e-12)
    assert check.limit == 10.0


# ---------------------------------------------------------------------------
# The lead: recomputed, not rescaled


def test_each_screw_lead_reruns_the_model(params):
    trajectory = iso14242(rate=100)
    motor = (Motor("m", peak=TorqueSpeedCurve([0.0], [5.0]), rotor_inertia=1e-4), None)
    screws = [LeadScrew("p5", lead=0.005), LeadScrew("p20", lead=0.020, inertia=80e-6)]
    candidates = rank_drives(params, [(trajectory, 1.0)], [motor], screws)
    by_screw = {c.drive.screw.name: c for c in candidates}
    for screw in screws:
        machine = params.replace(lead=screw.lead, **({"screw_inertia": screw.inertia} if screw.inertia else {}))
        direct = sizing(hipsim.analyse(machine, trajectory), Drive(motor[0], screw=screw))
        expected = {(c.module, c.name): c.value for c in direct.checks if c.value is not None}
        got = {(c.module, c.name): c.value for c in by_screw[screw.name].checks if c.value is not None}
        assert got == pytest.approx(expected, rel=1e-12, nan_ok=True)
    peak5 = only(by_screw["p5"].checks, "peak_curve").value
    peak20 = only(by_screw["p20"].checks, "peak_curve").value
    # Rescaling the 20 mm torques by 5/20 would miss the screw inertia and the changed reflected inertia.
    assert abs(peak5 - peak20 * 5 / 20) > 0.01 * peak5


# ---------------------------------------------------------------------------
# Ranking


def test_an_undersized_and_a_right_motor_rank_with_the_binding_constraint_named(params):
    small = Motor("small", continuous=curve([0, 3000], [1.0, 1.0]), peak=curve([0, 3000], [0.25, 0.25]), rotor_inertia=1e-4)
    right = Motor("right", continuous=curve([0, 3000], [1.3, 1.2]), peak=curve([0, 5000], [3.8, 3.0]), rotor_inertia=1e-4)
    trajectory = iso14242(rate=200)
    candidates = rank_drives(params, [(trajectory, 1.0)], [(small, None), (right, None)])
    assert [c.drive.motor.name for c in candidates] == ["right", "small"]
    assert candidates[0].passed is True and candidates[1].passed is False
    binding = candidates[1].binding
    assert binding.name == "peak_curve" and binding.module == 1  # motor 1 needs over 431 N·mm, 250 N·mm on offer
    run = hipsim.analyse(params, trajectory)
    rotor = 1e-4 * 2 * math.pi / params.lead * run.Ldd[:, 0, 0]  # the motor also turns its own rotor
    assert binding.value == pytest.approx(np.abs(run.torques.total[:, 0] + rotor).max() * 1e3, rel=1e-12)
    assert binding.limit == pytest.approx(250.0) and binding.margin == pytest.approx(1 - binding.value / 250.0)
    assert candidates[0].margin > 0 > candidates[1].margin


def test_the_published_machine_sizing_names_a_binding_check(params):
    size = sizing(hipsim.analyse(params, iso14242(rate=200)), Drive(Motor("m", rotor_inertia=14e-6)))
    assert size.binding.name == "inertia_ratio" and size.passed is False  # 2.8 kg·cm² on a 0.14 kg·cm² rotor
    document = size.as_dict()
    assert document["binding"]["name"] == "inertia_ratio" and len(document["checks"]) == 3 * len(CHECKS)


# ---------------------------------------------------------------------------
# The command line: hipsim size


MOTORS = """\
name,s1_torque_Nm,peak_speed_rpm,peak_torque_Nm,rotor_inertia_kgcm2
small,1.0,0;3000,0.25;0.25,1.0
right,1.3,0;5000,3.8;3.0,1.0
"""


def test_size_ranks_a_catalogue(tmp_path, capsys):
    from hipsim.cli import main

    motors = tmp_path / "motors.csv"
    motors.write_text(MOTORS)
    screws = tmp_path / "screws.csv"
    screws.write_text("name,lead_mm,dynamic_load_rating_N\nten,10,9000\n")
    assert main(["size", "--rate", "200", "--catalogue", str(motors), "--screws", str(screws)]) == 0
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if re.match(r"[12]\s{2,}", line)]
    assert lines[0].split()[1] == "right" and "pass" in lines[0]
    assert lines[1].split()[1] == "small" and "FAIL" in lines[1] and "torque under the peak curve" in lines[1] and "LN1" in lines[1]
    assert "Every check of rank 1: right + ten" in out
    assert main(["size", "--rate", "200", "--catalogue", str(motors), "--format", "json", "--top", "1"]) == 0
    import json

    document = json.loads(capsys.readouterr().out)
    assert [c["motor"] for c in document["candidates"]] == ["right"]


def test_size_checks_one_drive_and_fails_with_status_1(tmp_path, capsys):
    from importlib import resources

    from hipsim.cli import main

    drive = str(resources.files("hipsim.models").joinpath("drive_example.toml"))
    assert main(["size", "--rate", "200", "--drive", drive]) == 1  # the example 200 W motor fails the 10:1 inertia rule
    out = capsys.readouterr().out
    assert "-> FAIL; binding: load-to-rotor inertia ratio (worst pose), LN1" in out
    assert main(["size", "--rate", "200", "--drive", drive, "--inertia-ratio", "25"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["--screws", "s.csv"], "--screws applies to a catalogue"),
        (["--drive", "d.toml", "--catalogue", "m.csv"], "either --drive"),
        (["--without-iso"], "--trajectory"),
        (["--life-cycles", "-3"], "--life-cycles"),
        (["--catalogue", "missing.csv"], "no such motor catalogue"),
    ],
)
def test_size_refuses_bad_options_in_one_line(tmp_path, capsys, monkeypatch, arguments, message):
    from hipsim.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["size", "--rate", "100", *arguments]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1

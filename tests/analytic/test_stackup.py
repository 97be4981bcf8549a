"""The intermediate chain's stack-up (``[geometry] spline_seat_mm``): m_1's centre rides ẑ·(R_2 − I)·e up and down with m_2.

Checked against a hand route (tests/stations_synthetic.py, SciPy rotations and a difference Newton), against the
Pinocchio per-chain model with m_1's centre frozen where the stack-up puts it, and bit for bit against today's
machine when the seat is zero.
"""

import math

import numpy as np
import pytest
from stations_synthetic import deviated, motion, reference_attitude, reference_carriages

import hipsim
from hipsim.analytic.engine import AnalyticModel
from hipsim.analytic.stations import carriage_sensitivities, carriages_for_platform, platform_attitude
from hipsim.exceptions import MissingDependencyError, ParameterError
from hipsim.machine.chains import ChainGeometry, stackup_lift
from hipsim.stations import deviations as dv
from hipsim.stations.commands import station_commands
from hipsim.stations.tolerance import error_sensitivity, half_widths, sensitivity_table

PARAMS = hipsim.load_parameters()
CHAINS = deviated(seed=3)  # the chains built to ±0.3 mm
SEAT = np.array([0.2e-3, -0.3e-3, 0.25e-3])
STACKED = PARAMS.replace(geometry=CHAINS.replace(spline=SEAT))


def test_the_lift_by_hand():
    e = 1e-3
    cases = [  # (seat, m_2's [α, β, γ] in degrees, lift in m): ẑᵀR = (−sin β, cos β·sin α, cos β·cos α)
        ([0.0, e, 0.0], [30.0, 0.0, 0.0], 0.5e-3),
        ([e, 0.0, 0.0], [0.0, 30.0, 0.0], -0.5e-3),
        ([0.0, 0.0, e], [60.0, 0.0, 0.0], -0.5e-3),
        ([e, e, e], [0.0, 0.0, 40.0], 0.0),  # a turn about Z lifts nothing
    ]
    for seat, angles, lift in cases:
        assert stackup_lift(np.array(seat), np.radians([angles]))[0] == pytest.approx(lift, abs=1e-18)


def test_zero_seat_is_todays_machine_bit_for_bit():
    t, q = motion(300, seed=2)
    zero = PARAMS.replace(geometry=CHAINS.replace(spline=np.zeros(3)))
    today = PARAMS.replace(geometry=CHAINS)
    for control in ("1", "2", "both"):
        a, b = station_commands(zero, t, q, control), station_commands(today, t, q, control)
        assert np.array_equal(a.carriages, b.carriages) and np.array_equal(a.attitudes, b.attitudes)
    # and the file that says so reads back as today's machine
    assert PARAMS.replace(geometry=zero.geometry).chains.stacked is False


@pytest.mark.parametrize("control", [2, 1])
def test_commands_and_attitudes_agree_with_the_hand_route(control):
    t, q = motion(40, seed=5, scale_deg=3.0)
    run = station_commands(STACKED, t, q, str(control))
    L = reference_carriages(PARAMS, STACKED.geometry, 2, q) if control == 2 else run.carriages
    np.testing.assert_allclose(run.carriages, L, rtol=0, atol=1e-13)
    hand = np.stack([reference_attitude(PARAMS, STACKED.geometry, j, run.carriages, q) for j in (1, 2)], axis=1)
    np.testing.assert_allclose(run.attitudes, hand, rtol=0, atol=1e-12)
    if control == 1:  # the hand route's carriages for m_1 at q, its centre lifted by m_2's attitude there
        np.testing.assert_allclose(
            reference_carriages(PARAMS, STACKED.geometry, 1, q, hand[:, 1]), run.carriages, rtol=0, atol=1e-13
        )
    # The stack-up matters: the follower moves by far more than the agreement.
    plain = station_commands(PARAMS.replace(geometry=CHAINS), t, q, str(control))
    assert np.abs(run.attitudes - plain.attitudes).max() > 1e-5


def test_forward_and_inverse_round_trip_through_the_public_functions():
    _, q = motion(30, seed=6, scale_deg=3.0)
    L = carriages_for_platform(STACKED, q, 1)
    np.testing.assert_allclose(platform_attitude(STACKED, L, 1, q0=q[0]), q, rtol=0, atol=1e-12)


def _engines():
    from hipsim.closed_chain.engine import PinocchioModel

    out = [PinocchioModel]
    try:
        from hipsim.mujoco_engine import MujocoModel
    except (ImportError, MissingDependencyError):
        return out
    return out + [MujocoModel]


@pytest.mark.parametrize("engine", _engines(), ids=lambda e: e.__name__)
def test_pinocchio_and_mujoco_with_the_centre_frozen_where_the_stack_up_puts_it(engine):
    """Per pose: the per-chain model whose m_1 centre sits at the lift m_2's attitude gives: the same carriages."""
    cycle = hipsim.iso14242(rate=100)
    for k in (12, 61):
        pose = cycle.slice(slice(k, k + 1))
        L = carriages_for_platform(STACKED, pose.q, 1)
        q2 = platform_attitude(STACKED, L, 2, q0=pose.q[0])
        lift = stackup_lift(SEAT, q2 * PARAMS.angle_signs)[0]
        centre = CHAINS.centre.copy()
        centre[0, 2] += lift
        frozen = PARAMS.replace(geometry=CHAINS.replace(centre=centre, control=1))
        run = engine(frozen).run(pose)
        assert abs(lift) > 1e-5
        np.testing.assert_allclose(run.L[:, 0], L, rtol=0, atol=1e-12)


def test_the_sensitivity_of_the_seat_by_finite_differences():
    _, q = motion(6, seed=8, scale_deg=3.0)
    x = STACKED.geometry.as_vector()
    L = carriages_for_platform(STACKED, q, 1)
    q2 = platform_attitude(STACKED, L, 2, q0=q[0])
    S = carriage_sensitivities(STACKED, q, 1, q2)
    h = 1e-7
    for k in range(48, 51):
        step = np.zeros(x.size)
        step[k] = h

        def at(v):
            return carriages_for_platform(PARAMS.replace(geometry=ChainGeometry.from_vector(v)), q, 1)

        # The fixed point feeds the lift back through m_2's attitude (∂Δz/∂q_2·∂q_2/∂L ~ |e|/50 mm ≈ 1e-5): left out.
        np.testing.assert_allclose(S[:, :, k], (at(x + step) - at(x - step)) / (2 * h), rtol=1e-4, atol=1e-9)


def test_the_tolerance_sensitivity_names_the_seat():
    cycle = hipsim.iso14242(rate=50)
    widths = half_widths({"spline": 0.3e-3, "lever": 0.3e-3})
    S = error_sensitivity(PARAMS, cycle.q, "2")
    rows = sensitivity_table(S, widths, platforms=(0,))
    seat = [row for row in rows if row["family"] == "spline"]
    assert [row["value"] for row in seat] and {row["value"] for row in seat} == {
        "spline_x_1",
        "spline_y_1",
        "spline_z_1",
    }
    assert all(row["chain"] == "intermediate" for row in seat) and max(row["share"] for row in seat) > 0.01
    # m_2 controlled: its own values never move it, the seat moves only m_1
    assert np.all(S[:, 1, :, 48:] == 0.0) and np.abs(S[:, 0, :, 48:]).max() > 0


def test_the_seat_is_in_the_vector_and_its_family():
    assert dv.names()[48:] == ("spline_x_1", "spline_y_1", "spline_z_1")
    assert dv.family("spline_y_1") == "spline" and dv.platform_of("spline_z_1") == 1
    assert STACKED.geometry is not None
    machine = dv.machine(PARAMS, STACKED.geometry.as_vector())
    assert machine.geometry is not None and math.isclose(machine.geometry.spline[1], SEAT[1])


def _sines(rate: float = 4000.0) -> hipsim.Trajectory:
    """Three angles, each two sines of its own frequencies (all motors move, in every combination), 1 s, ISO load."""
    t = np.arange(int(rate)) / rate
    amp, freq, phase = np.radians([[12.0, 6.0, 9.0], [4.0, 3.0, 5.0]]), [[1.0, 1.6, 0.7], [2.3, 3.1, 2.9]], [0.3, 1.1]
    q, qd, qdd = (np.zeros((len(t), 3)) for _ in range(3))
    for a, f, ph in zip(amp, np.asarray(freq) * 2 * np.pi, phase):
        arg = f * t[:, None] + ph
        q += a * np.sin(arg)
        qd += a * f * np.cos(arg)
        qdd -= a * f**2 * np.sin(arg)
    return hipsim.Trajectory(t, q, qd, qdd, hipsim.iso14242(rate=rate).Fe, name="sines")


@pytest.mark.parametrize(("motion_of", "control"), [("iso", 2), ("sines", 2), ("iso", 1), ("sines", 1)])
def test_power_balance_of_the_analytic_dynamics_with_a_stack_up(motion_of, control):
    """Σ τ·θ̇ = dE/dt + friction power + F_e·ż_1, E from the bodies' motion: the coupling through the seat is right
    (control = 1: m_2 and the lift follow m_1 through the coupled rates)."""
    from hipsim.analytic.chain_dynamics import chain_mechanical_energy, chain_motion

    params = STACKED.replace(sjoint_viscous=0.02, ujoint_coulomb=0.05)
    seat = np.array([1e-3, 2e-3, -1e-3])
    big = params.replace(geometry=params.geometry.replace(spline=seat, control=control))
    trajectory = hipsim.iso14242(rate=4000) if motion_of == "iso" else _sines()
    run = AnalyticModel(big).run(trajectory)
    motion = chain_motion(big, trajectory)
    kinetic, potential = chain_mechanical_energy(big, motion)
    assert motion.lift is not None
    zd = motion.lift[1]
    power = np.sum(run.torques.total * run.torques.motor_speed, axis=1) - run.torques.friction_power
    dE = np.gradient(kinetic + potential, trajectory.t[1] - trajectory.t[0])
    assert np.abs(power - dE - trajectory.Fe * zd)[2:-2].max() < 1e-5 * np.abs(power).max()
    # The load's work is not small: leaving it out breaks the balance by far more than the tolerance.
    assert np.abs(trajectory.Fe * zd).max() > 1e-2 * np.abs(power).max()
    # The lever centres' velocities are the derivative of their positions (the lift's translation included).
    kin = motion.platforms[0]
    centre = 0.5 * (kin.a[:, 0] + kin.b[:, 0])
    fd = np.gradient(centre, trajectory.t, axis=0)
    assert np.abs(fd - kin.v_l[:, 0])[2:-2].max() < 1e-6


def _at(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """m_1's motion by hand: q = a·sin(ωt + φ) per angle, its exact rates and accelerations, each (N, 3)."""
    a, w, ph = np.radians([9.0, 4.0, 7.0]), np.array([5.0, 7.0, 3.0]), np.array([0.3, 1.2, 2.0])
    arg = w * t[:, None] + ph
    return a * np.sin(arg), a * w * np.cos(arg), -a * w**2 * np.sin(arg)


def test_the_coupled_rates_with_m1_controlled_by_finite_differences():
    """control = 1 with a stack-up: L̇, L̈ and m_2's q̇_2, q̈_2 against central differences of the positions."""
    from hipsim.analytic.stations import stacked_motion

    machine = STACKED.replace(geometry=STACKED.geometry.replace(spline=np.array([1e-3, 2e-3, -1e-3])))
    t, h = np.array([0.1, 0.4, 0.7]), 1e-5
    L, Ld, Ldd, (q2, qd2, qdd2) = stacked_motion(machine, *_at(t))
    minus, plus = stacked_motion(machine, *_at(t - h)), stacked_motion(machine, *_at(t + h))
    np.testing.assert_allclose((plus[0] - minus[0]) / (2 * h), Ld, rtol=0, atol=1e-8 * np.abs(Ld).max())
    np.testing.assert_allclose((plus[1] - minus[1]) / (2 * h), Ldd, rtol=0, atol=1e-7 * np.abs(Ldd).max())
    np.testing.assert_allclose((plus[3][0] - minus[3][0]) / (2 * h), qd2, rtol=0, atol=1e-8 * np.abs(qd2).max())
    np.testing.assert_allclose((plus[3][1] - minus[3][1]) / (2 * h), qdd2, rtol=0, atol=1e-7 * np.abs(qdd2).max())
    # The positions: m_1 at its motion for those carriages, m_2 its forward kinematics.
    np.testing.assert_allclose(platform_attitude(machine, L, 1, q0=_at(t)[0][0]), _at(t)[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(platform_attitude(machine, L, 2, q0=q2[0]), q2, rtol=0, atol=1e-12)
    # Without the coupling (m_2 held, as platform_jacobian's m_1) L̇ would be off by far more than the check.
    plain = machine.replace(geometry=machine.geometry.replace(spline=np.zeros(3)))
    from hipsim.analytic.stations import platform_motion

    assert np.abs(platform_motion(plain, *_at(t), 1)[1] - Ld).max() > 1e-4 * np.abs(Ld).max()


def test_the_follower_m1_on_a_stacked_machine_by_finite_differences():
    """follower_motion of m_1 (control = 2) with a stack-up: its rates against differences of its attitudes."""
    from hipsim.analytic.stations import follower_motion, platform_motion

    t, h = np.array([0.2, 0.5]), 1e-5
    machine = STACKED.replace(geometry=STACKED.geometry.replace(spline=np.array([1e-3, 2e-3, -1e-3])))

    def follower(times):
        return follower_motion(machine, *platform_motion(machine, *_at(times), 2), 1, guess=_at(times)[0])

    q1, qd1, qdd1 = follower(t)
    minus, plus = follower(t - h), follower(t + h)
    np.testing.assert_allclose((plus[0] - minus[0]) / (2 * h), qd1, rtol=0, atol=1e-8 * np.abs(qd1).max())
    np.testing.assert_allclose((plus[1] - minus[1]) / (2 * h), qdd1, rtol=0, atol=1e-7 * np.abs(qdd1).max())


def test_tolerance_monte_carlo_of_the_seat_agrees_with_first_order():
    from hipsim.stations.tolerance import parse_tolerances, tolerance_draws

    cycle = hipsim.iso14242(rate=50)
    bands = parse_tolerances("spline=0.5")
    result = tolerance_draws(PARAMS, cycle.t, cycle.q, bands, ("2", "1"), draws=60, seed=2, workers=0)
    for c, control in enumerate(("2", "1")):
        follower = 2 - int(control)  # m_1 under control 2, m_2 under control 1
        mean_square = (result.rms[:, c, follower] ** 2).mean(axis=0)
        S = error_sensitivity(PARAMS, cycle.q, control)
        expected = ((S[:, follower] ** 2).mean(axis=0) @ (half_widths(bands) ** 2 / 3)).ravel()
        assert np.abs(mean_square[2] / expected[2] - 1) < 0.25, (control, mean_square / expected)
        assert np.all(result.rms[:, c, 1 - follower] < 1e-12)  # the controlled platform exact on every machine


def test_calibrate_estimates_the_seat_of_a_hidden_stacked_machine():
    """Logs of a hidden machine with a stack-up, made by the hand route: the seat comes out within its posterior."""
    from stations_synthetic import synthetic_log

    from hipsim.stations import CalibrationLog, calibrate

    truth = STACKED.geometry.replace(spline=np.array([0.4e-3, -0.6e-3, 0.3e-3]))
    logs = []
    for k in range(2):
        t, L, _, sensors = synthetic_log(PARAMS, truth, 1200, seed=60 + k, noise_deg=0.05)
        logs.append(CalibrationLog(f"log{k}", t, L, sensors))
    fit = calibrate(logs, PARAMS)
    seat, std = fit.theta[48:], fit.theta_std[48:]
    assert np.all(fit.determined[48:]), std  # std at most half the prior (0.25 mm): seen, if weakly by 2,400 samples
    assert np.all(np.abs(seat - truth.spline) < 4 * std), (seat, truth.spline, std)
    assert "spline_x_1" not in fit.unseen


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("spline_seat_mm = [0.1, 0]", r"geometry\.spline_seat_mm.*expected \[x, y, z\] in mm, got \[0\.1, 0\]"),
        ("spline_seat_mm = [0.1, 0, 80]", r"geometry\.spline_seat_mm.*at most 50 mm, got \[0\.1, 0, 80\]"),
        ('spline_seat_mm = [0.1, 0, "x"]', r"geometry\.spline_seat_mm"),
    ],
)
def test_a_bad_seat_is_refused_by_name(tmp_path, table, message):
    from hipsim.machine.toml_writer import parameter_toml

    path = tmp_path / "bad.toml"
    path.write_text(parameter_toml(PARAMS) + "[geometry]\n" + table + "\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=message) as caught:
        hipsim.load_parameters(path)
    assert "bad.toml" in str(caught.value) and "\n" not in str(caught.value)


def test_the_seat_reads_back_from_the_written_file(tmp_path):
    from hipsim.machine.toml_writer import parameter_toml

    path = tmp_path / "stacked.toml"
    path.write_text(parameter_toml(STACKED), encoding="utf-8")
    again = hipsim.load_parameters(path)
    assert np.array_equal(again.geometry.spline, STACKED.geometry.spline)
    np.testing.assert_allclose(again.geometry.as_vector(), STACKED.geometry.as_vector(), rtol=1e-13, atol=0)


def test_a_calibration_motion_is_designed_for_a_stacked_machine():
    from hipsim.stations.excitation import calibration_excitation

    design = calibration_excitation(STACKED, seeds=1)
    assert np.isfinite(design.condition_number) and design.peaks.cond_inv_min > 0.2


def test_the_stations_command_on_a_stacked_machine(tmp_path):
    from hipsim.cli.main import main

    out = tmp_path / "run"
    seat = "geometry.spline_seat_mm=[0.3, 0.5, 0.2]"
    assert main(["stations", "--set", seat, "--rate", "100", "--out", str(out), "--summary-format", "json"]) == 0
    table = np.genfromtxt(out / "stations.csv", delimiter=",", names=True)
    rms = {a: np.sqrt(np.mean(table[f"err_{a}_1_deg"] ** 2)) for a in ("alpha", "beta", "gamma")}
    assert rms["gamma"] > 10 * max(rms["alpha"], rms["beta"]) > 0  # the stack-up's fingerprint: about Z
    assert np.all(table["err_gamma_2_deg"] == 0.0)  # m_2 controlled, exact


def test_control_1_names_the_time_where_m2_cannot_follow():
    """Four times the ISO angles: m_2 leaves its assembly mode; the error names that sample's time, not t = 0."""
    from hipsim.exceptions import PoseError

    cycle = hipsim.iso14242(rate=50)
    wild = hipsim.Trajectory(cycle.t, 4 * cycle.q, 4 * cycle.qd, 4 * cycle.qdd, cycle.Fe, name="wild")
    machine = STACKED.replace(geometry=STACKED.geometry.replace(control=1))
    with pytest.raises(PoseError, match=r"wild, t = .*platform 2 under m_1's stack-up") as caught:
        AnalyticModel(machine).run(wild)
    assert caught.value.time == cycle.t[caught.value.index] > 0

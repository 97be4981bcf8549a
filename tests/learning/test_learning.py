"""The learning law (hipsim.learning): its filter, its gains, and learning on a machine as built from its own logs."""

from __future__ import annotations

import numpy as np
import pytest
from learning_synthetic import Rig, drive
from stations_synthetic import deviated

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.learning import LearningLaw, first_command, learning_step
from hipsim.learning.filters import apply_response, frequencies, lag_response, periodic_derivatives, q_response
from hipsim.learning.law import data_spectral_radius, gain_matrices, model_spectral_radius, update
from hipsim.learning.step import CycleLog, phase_average, shifted_mismatch_deg
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations.commands import station_commands
from hipsim.stations.sensitivity import inverse3, reading_rate

RATE = 500.0


@pytest.fixture(scope="module")
def drawing():
    return load_parameters()


@pytest.fixture(scope="module")
def desired():
    return iso14242(rate=RATE)


@pytest.fixture(scope="module")
def geometry():
    return deviated(seed=3, size_mm=0.3)


# --- The filters -----------------------------------------------------------------------------


def test_q_is_a_fourth_order_butterworth_forwards_and_backwards():
    f = np.array([0.0, 10.0, 20.0, 5.0])
    # 1/(1 + (f/fc)^8): 1, 1/2 at the cutoff, 1/257 an octave above, 256/257 an octave below
    assert q_response(f, 10.0) == pytest.approx([1.0, 0.5, 1.0 / 257.0, 256.0 / 257.0], rel=1e-15)
    assert np.all(q_response(f, None) == 1.0)


def test_a_lag_on_a_sine_is_the_hand_computed_sine():
    n, period, tau = 400, 2.0, 0.05
    t = np.arange(n) * period / n
    w = 2 * np.pi * 3 / period  # the third harmonic
    out = apply_response(np.sin(w * t), lag_response(frequencies(n, period), tau))
    # sin(wt) / (1 + iwτ) = (sin wt − wτ cos wt) / (1 + w²τ²)
    assert out == pytest.approx((np.sin(w * t) - w * tau * np.cos(w * t)) / (1 + (w * tau) ** 2), abs=1e-14)


def test_periodic_derivatives_of_a_cosine():
    n, period = 256, 0.8
    t = np.arange(n) * period / n
    w = 2 * np.pi * 5 / period
    d1, d2 = periodic_derivatives(np.cos(w * t), period)
    assert d1 == pytest.approx(-w * np.sin(w * t), abs=1e-10 * w)
    assert d2 == pytest.approx(-w * w * np.cos(w * t), abs=1e-10 * w * w)


def test_phase_average_of_three_periods_and_a_short_log():
    grid = np.arange(10) * 0.1
    t = np.arange(30) * 0.1 + 0.02  # starts 0.02 s into the phase
    values = np.sin(2 * np.pi * t) + np.repeat([0.0, 1.0, 5.0], 10)  # each period offset by its own constant
    averaged, periods = phase_average(t, values, grid, 1.0, "log")
    assert periods == 3
    # the mean offset is 2; between samples the interpolation of a sine is linear: check at the grid's own phases
    exact = np.sin(2 * np.pi * grid) + 2.0
    assert np.abs(averaged - exact).max() < 0.1  # linear interpolation over 0.1 s of a unit sine
    with pytest.raises(TrajectoryError, match="shorter than one period"):
        phase_average(t[:9], values[:9], grid, 1.0, "log")


# --- The gains and the figures on the model ----------------------------------------------------


def test_gain_inverts_the_controlled_platforms_map(drawing, desired, geometry):
    model = drawing.replace(geometry=geometry)
    K = gain_matrices(model, desired.q[:50], LearningLaw("1"))
    A = inverse3(reading_rate(model, desired.q[:50], 1))
    assert np.matmul(K[:, 0], A) == pytest.approx(np.broadcast_to(np.eye(3), (50, 3, 3)), abs=1e-12)
    assert np.all(K[:, 1] == 0.0)


def test_both_on_the_drawing_splits_by_the_weights(drawing, desired):
    K = gain_matrices(drawing, desired.q[:20], LearningLaw("both", weights=(1.0, 3.0)))
    D = reading_rate(drawing, desired.q[:20], 2)  # both platforms alike: K_j = w_j/(w_1 + w_2)·∂L/∂q
    assert K[:, 0] == pytest.approx(0.25 * D, rel=1e-9, abs=1e-15)
    assert K[:, 1] == pytest.approx(0.75 * D, rel=1e-9, abs=1e-15)


def test_model_figure_is_one_minus_the_gain():
    assert model_spectral_radius(LearningLaw(gain=0.5)) == 0.5
    assert model_spectral_radius(LearningLaw(gain=2.5)) == 1.5


# --- Learning on a machine as built ------------------------------------------------------------


def _learn(model, rig, law, runs):
    base = first_command(model, rig.desired, law)
    command, errors, true_runs = base.carriages, [], []
    for k in range(runs):
        log, true = rig.run(command)
        errors.append(np.degrees(rig.desired.q[:, None] - true))
        true_runs.append(true)
        step = learning_step(model, rig.desired, log, law, base, cycle=k)
        command = step.command.carriages
    return errors, step


def test_model_equal_to_plant_without_noise_changes_nothing(drawing, desired, geometry):
    machine = drawing.replace(geometry=geometry)
    rig = Rig(drawing, geometry, desired)
    law = LearningLaw("2")
    base = first_command(machine, desired, law)
    log, _ = rig.run(base.carriages)
    step = learning_step(machine, desired, log, law, base)
    assert np.abs(step.command.carriages - base.carriages).max() < 1e-12  # 1e-9 mm
    assert step.summary.update is not None
    assert max(step.summary.update.change_peak_mm) < 1e-9


def test_learning_from_its_own_logs_reaches_the_noise_floor(drawing, desired, geometry):
    rig = Rig(drawing, geometry, desired, lag_s=0.01, noise_deg=0.05, seed=1)
    errors, step = _learn(drawing, rig, LearningLaw("2"), 6)
    rms = [float(np.sqrt(np.mean(e[:, 1] ** 2))) for e in errors]  # the controlled platform m_2, true attitude
    assert rms[0] > 0.3  # the drawing's command on the machine as built, the drive lagging: far off
    assert rms[1] < rms[0] / 5 and rms[2] < rms[1]  # monotone while above the floor
    assert min(rms[1:6]) < 0.02 and rms[-1] < 0.02
    assert (
        step.summary.convergence.data is not None and step.summary.convergence.data < 0.5
    )  # a 10 ms lag at a 1 Hz cycle, Q at 10 Hz


def test_both_comes_within_five_percent_of_the_best_carriages(drawing, desired, geometry):
    rig = Rig(drawing, geometry, desired, lag_s=0.01, noise_deg=0.05, seed=2)
    errors, _ = _learn(drawing, rig, LearningLaw("both"), 5)
    best = station_commands(drawing.replace(geometry=geometry), desired.t, desired.q, "both")
    best_sse = float(np.sum(np.degrees(best.errors) ** 2))
    assert float(np.sum(errors[-1] ** 2)) <= 1.05 * best_sse


def test_a_divergent_gain_is_refused(drawing, desired, geometry):
    rig = Rig(drawing, geometry, desired)
    log, _ = rig.run(first_command(drawing, desired, LearningLaw("2")).carriages)
    with pytest.raises(ArgumentError, match="1.5 ≥ 1, it diverges"):
        learning_step(drawing, desired, log, LearningLaw("2", gain=2.5))


def test_a_drive_that_would_make_the_step_diverge_is_refused(drawing, desired, geometry):
    # A 100 ms dead time: at 2 Hz |1 − e^{−iωd}| = 2 sin(0.2π) = 1.18, times Q(2 Hz) ≈ 1 at a 10 Hz cutoff
    rig = Rig(drawing, geometry, desired, delay_samples=int(0.1 * RATE))
    log, _ = rig.run(first_command(drawing, desired, LearningLaw("2")).carriages)
    with pytest.raises(TrajectoryError, match="would diverge"):
        learning_step(drawing, desired, log, LearningLaw("2"))
    # Q at 2 Hz and γ = 1/2: at 1 Hz |1 − e^{−i0.2π}/2| = 0.66, at 2 Hz 0.97·Q = 0.49: the same log then converges
    step = learning_step(drawing, desired, log, LearningLaw("2", q_cutoff=2.0, gain=0.5))
    assert step.summary.convergence.data is not None and step.summary.convergence.data < 1.0


def test_mismatch_at_the_best_shift():
    t = np.arange(100) / 100
    a = np.stack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t), 0 * t], axis=1)
    assert shifted_mismatch_deg(a, np.roll(a, 7, axis=0)) < 1e-12  # a delay is no mismatch
    # another frequency: sin 2πt against sin 4πt has no shift that fits; RMS √(1/2 + 1/2)/√3 rad per entry
    b = np.stack([np.sin(4 * np.pi * t), np.cos(2 * np.pi * t), 0 * t], axis=1)
    assert shifted_mismatch_deg(a, b) == pytest.approx(np.degrees(np.sqrt(1 / 3)), rel=1e-9)


def test_a_log_of_another_frequency_is_refused(drawing, desired, geometry):
    other = iso14242(rate=RATE, frequency=1.25)
    rig = Rig(drawing, geometry, other)
    log, _ = rig.run(station_commands(drawing, other.t, other.q, "2").carriages)
    long = CycleLog(
        np.concatenate([log.t, log.t + 0.8]),
        np.tile(log.encoders, (2, 1)),
        np.tile(log.commands, (2, 1)),
        np.tile(log.sensors, (2, 1, 1)),
    )
    with pytest.raises(TrajectoryError, match="not a run of it"):
        learning_step(drawing, desired, long, LearningLaw("2"))


def test_update_of_a_constant_error_is_gamma_k_e():
    n = 64
    K = np.zeros((n, 2, 3, 3))
    K[:, 1] = 2.0 * np.eye(3)
    errors = np.full((n, 2, 3), np.nan)
    errors[:, 1] = [0.1, -0.2, 0.3]
    learned = update(np.full((n, 3), 1e-3), errors, K, LearningLaw("2", gain=0.5, drive_lag=0.02), 1.0)
    # Q(0) = 1 and G_m⁻¹(0) = 1: u + γ·K·e = 1e-3 + 0.5·2·e, at every sample
    assert learned == pytest.approx(np.broadcast_to([0.101, -0.199, 0.301], (n, 3)), abs=1e-15)


def test_the_models_lag_makes_the_drive_figure_small():
    n, period = 1000, 1.0
    t = np.arange(n) / n
    commands = np.stack([np.cos(2 * np.pi * k * t) for k in (1, 2, 3)], axis=1)
    encoders = drive(commands, 1.0 / n, lag_s=0.05)  # a discrete lag, stepped: not the law's DFT
    blind, at = data_spectral_radius(commands, encoders, LearningLaw("2"), period)
    # |1 − G| at 3 Hz of a 50 ms lag: ωτ/√(1 + ω²τ²) = 0.686; Q(3 Hz) ≈ 1
    assert blind == pytest.approx(0.686, abs=0.01) and at == 3.0
    known, _ = data_spectral_radius(commands, encoders, LearningLaw("2", drive_lag=0.05), period)
    assert known < 0.02  # what is left: the discrete filter's half-step against the continuous lag


def test_a_log_on_the_commands_clock_late_in_a_test(drawing, desired, geometry):
    rig = Rig(drawing, geometry, desired, lag_s=0.01)
    law = LearningLaw("2")
    log, _ = rig.run(first_command(drawing, desired, law).carriages)
    late = CycleLog(log.t + 3600.0, log.encoders, log.commands, log.sensors)  # an hour into the test: phase t mod T
    a, b = learning_step(drawing, desired, log, law), learning_step(drawing, desired, late, law)
    assert np.abs(a.command.carriages - b.command.carriages).max() < 1e-12


def test_a_motion_that_is_not_iso_is_said_apart_from_the_stations(drawing, desired, geometry):
    from hipsim.motion.trajectories import Trajectory

    half = Trajectory(desired.t, desired.q * 0.5, desired.qd * 0.5, desired.qdd * 0.5, desired.Fe, "half", True)
    machine = drawing.replace(geometry=geometry)
    rig = Rig(drawing, geometry, half)
    law = LearningLaw("2")
    log, _ = rig.run(first_command(machine, half, law).carriages)  # m_2 exact: the model is the machine
    summary = learning_step(machine, half, log, law).summary
    assert summary.desired is not None
    assert summary.desired.verdict == "FAIL" and summary.desired.worst_deg[0] > 5.0  # α: half of 21.5° amplitude
    station2 = next(s for s in summary.stations if s.platform == 2)
    assert station2.worst_deg == pytest.approx(summary.desired.worst_deg, abs=1e-6)  # it went through that motion

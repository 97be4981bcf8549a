"""One learning step (hipsim.learning.step): a log averaged per phase, the mismatch at the best shift, the refusals,
and learning on a machine as built from its own logs (the law's pieces: test_filters.py, test_law.py)."""

from __future__ import annotations

import numpy as np
import pytest
from learning_synthetic import Rig
from stations_synthetic import deviated

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.learning import LearningLaw, first_command, learning_step
from hipsim.learning.step import CycleLog, first_summary, learn_cycles, phase_average, shifted_mismatch_deg
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.stations.commands import station_commands

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


# --- The step's own refusals and the loop over cycles, on a 100-sample period ----------------------


def test_a_log_of_the_wrong_shape_names_the_field():
    with pytest.raises(ArgumentError, match="sensors"):
        CycleLog(np.zeros(4), np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3)))
    with pytest.raises(ArgumentError, match="encoders"):
        CycleLog(np.zeros(4), np.zeros((3, 3)), np.zeros((4, 3)), np.zeros((4, 2, 3)))


def test_the_model_figure_refuses_a_gain_of_two_and_takes_one_just_below():
    short = iso14242(rate=100.0)
    with pytest.raises(ArgumentError, match="1 ≥ 1, it diverges"):
        first_summary(short, LearningLaw("2", gain=2.0))
    summary = first_summary(short, LearningLaw("2", gain=1.999))
    assert summary.convergence.model == pytest.approx(0.999) and summary.cycle == 0 and summary.update is None
    assert summary.period_s == pytest.approx(1.0, rel=1e-12) and summary.samples == 100  # 100 samples 0.01 s apart


def test_the_desired_motion_must_be_one_whole_period():
    from hipsim.motion.trajectories import Trajectory

    short = iso14242(rate=100.0)
    once = Trajectory(short.t, short.q, short.qd, short.qdd, short.Fe, "once", False)
    with pytest.raises(TrajectoryError, match="one whole period"):
        first_summary(once, LearningLaw("2"))
    three = Trajectory(short.t[:3], short.q[:3], short.qd[:3], short.qdd[:3], short.Fe[:3], "three", True)
    with pytest.raises(TrajectoryError, match="4 samples or more"):
        first_summary(three, LearningLaw("2"))


def test_cycles_on_the_model_itself_learn_nothing_and_say_so_each_cycle(drawing):
    short = iso14242(rate=100.0)
    law = LearningLaw("2")
    lines: list[str] = []

    def model_itself(command):  # the machine is the model: it does what the model predicts
        return CycleLog(command.t, command.carriages, command.carriages, command.attitudes, True, "model")

    with pytest.raises(ArgumentError, match="cycles"):
        learn_cycles(model_itself, drawing, short, law, 0)
    steps, logs = learn_cycles(model_itself, drawing, short, law, 2, notify=lines.append)
    assert [s.summary.cycle for s in steps] == [1, 2] and len(logs) == 2
    assert len(lines) == 2 and lines[0].startswith("cycle 1: learned platforms' RMS error")
    base = first_command(drawing, short, law)
    assert np.abs(steps[-1].command.carriages - base.carriages).max() < 1e-12
    assert steps[-1].summary.controlled_rms_deg() < 1e-9

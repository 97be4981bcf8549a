"""One learning step from a cycle's log, the model's first command, and the loop over cycles on any machine.

- :class:`CycleLog`: what a cycle of the machine gave (the carriage commands,
  the encoders, the attitude sensors), on its own clock;
- :func:`phase_average`: a log of one or several periods onto the desired
  motion's samples, averaged per phase;
- :func:`first_command`: cycle 0, the model's own command (``hipsim stations``);
- :func:`learning_step`: the law of :mod:`~hipsim.learning.law` on one log:
  the next command and its :class:`~hipsim.learning.records.LearnSummary`;
- :func:`learn_cycles`: cycles run by a caller's ``runner`` (a simulated plant,
  or anything else that returns a :class:`CycleLog`), learned from one to the next.

The log's ``t_s`` is on the command's clock: a sample's phase is t mod T
(T the desired motion's period), as a command written by ``hipsim learn``
(one period from t = 0) replayed cycle after cycle gives it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..arrays import readonly
from ..exceptions import ArgumentError, TrajectoryError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..stations.commands import StationMotion, attitudes, station_commands
from .law import LearningLaw, data_spectral_radius, gain_matrices, model_spectral_radius, update
from .records import Convergence, LearnSummary, StationVerdict, UpdateChange, platform_errors, station_verdict

__all__ = [
    "MATCH_LIMIT_DEG",
    "CycleLog",
    "CycleRunner",
    "LearnStep",
    "first_command",
    "first_summary",
    "learn_cycles",
    "learning_step",
    "phase_average",
    "shifted_mismatch_deg",
]

#: A learned platform whose measured motion is this far in [deg] RMS from the desired one even at its best time shift
#: (a drive's lag shifts the motion; another trajectory or frequency cannot be shifted onto it) did not run it.
MATCH_LIMIT_DEG = 2.0


@dataclass(frozen=True, eq=False)
class CycleLog:
    """A run of the machine: one or more periods of a command, SI.

    Attributes:
        t: sample times in [s] on the command's clock, (N,), increasing.
        encoders: the carriage readings in [m], (N, 3).
        commands: the carriage commands that produced them in [m], (N, 3) (the encoders where not logged).
        sensors: both platforms' measured attitudes in [rad], (N, 2, 3) (NaN for a platform without a sensor).
        commands_logged: whether ``commands`` were logged.
        source: the log's name, for messages.
    """

    t: np.ndarray
    encoders: np.ndarray
    commands: np.ndarray
    sensors: np.ndarray
    commands_logged: bool = True
    source: str = "log"

    def __post_init__(self):
        n = np.shape(self.t)[0]
        for name, shape in (("t", (n,)), ("encoders", (n, 3)), ("commands", (n, 3)), ("sensors", (n, 2, 3))):
            value = np.asarray(getattr(self, name), dtype=float)
            if value.shape != shape:
                raise ArgumentError(name, value, f"shape {shape}")
            object.__setattr__(self, name, readonly(value))


def phase_average(t: np.ndarray, values: np.ndarray, grid: np.ndarray, period: float, source: str) -> tuple:
    """Values (N, ...) at times t (N,) [s], averaged per phase onto one period's times ``grid`` (M,) [s].

    The log's whole periods, counted from its first sample (a sample's step beyond its last covers it), are each
    interpolated linearly at the grid's phases and averaged.

    Returns:
        (averaged values (M, ...), the number of periods averaged).

    Raises:
        TrajectoryError: the log is shorter than a period.
    """
    t = np.asarray(t, dtype=float)
    step = (t[-1] - t[0]) / (len(t) - 1) if len(t) > 1 else 0.0
    covered = t[-1] - t[0] + step
    periods = int(math.floor(covered / period + 1e-6))
    if periods < 1:
        raise TrajectoryError(
            f"the log covers {covered:.6g} s, shorter than one period of the desired motion ({period:.6g} s)",
            source=source,
        )
    span = periods * period
    use = t < t[0] + span - 1e-9 * period
    flat = np.asarray(values, dtype=float)[use].reshape(int(use.sum()), -1)
    queries = (grid[None, :] + period * np.arange(periods)[:, None]).ravel()
    out = np.stack([np.interp(queries, t[use], flat[:, c], period=span) for c in range(flat.shape[1])], axis=1)
    out = out.reshape(periods, len(grid), -1).mean(axis=0)
    return out.reshape((len(grid),) + np.shape(values)[1:]), periods


def shifted_mismatch_deg(desired: np.ndarray, measured: np.ndarray) -> float:
    """The RMS in [deg] of desired − measured (N, 3) [rad], one period each, at the circular time shift that makes it least."""
    a, b = np.asarray(desired, dtype=float), np.asarray(measured, dtype=float)
    # Σ|a(t) − b(t + s)|² = Σ|a|² + Σ|b|² − 2·Σ a(t)·b(t + s): the cross term for every shift s by the DFT
    cross = np.fft.irfft(np.sum(np.conj(np.fft.rfft(a, axis=0)) * np.fft.rfft(b, axis=0), axis=1), n=len(a))
    least = max(float(np.sum(a * a) + np.sum(b * b) - 2.0 * cross.max()), 0.0)
    return float(np.degrees(np.sqrt(least / a.size)))


def first_command(model: Parameters, desired: Trajectory, law: LearningLaw) -> StationMotion:
    """Cycle 0: the model's own carriage command for the desired motion (``hipsim stations --control``)."""
    return station_commands(model, desired.t, desired.q, law.control, law.weights, source=desired.name)


@dataclass(frozen=True, eq=False)
class LearnStep:
    """A learning step's outcome: the next command (with the model's prediction of both attitudes) and its summary.

    Attributes:
        command: the next cycle's carriage commands and what the model predicts each platform does with them.
        learned: the learned correction u_{k+1} over the model's command in [m], (N, 3).
        measured: both platforms' measured attitudes per phase in [rad], (N, 2, 3) (NaN without a sensor).
        summary: the record.
    """

    command: StationMotion
    learned: np.ndarray
    measured: np.ndarray
    summary: LearnSummary


def _period(desired: Trajectory) -> float:
    n = len(desired)
    if n < 4 or not desired.periodic:
        raise TrajectoryError("the desired motion must be one whole period (periodic, 4 samples or more)", desired.name)
    return float(desired.t[-1] - desired.t[0]) * n / (n - 1)


def learning_step(
    model: Parameters,
    desired: Trajectory,
    log: CycleLog,
    law: LearningLaw,
    base: StationMotion | None = None,
    cycle: int | None = None,
) -> LearnStep:
    """The next command from a cycle's log: u_{k+1} = Q(u_k + L·e_k) (:mod:`hipsim.learning.law`).

    Args:
        model: the controller's machine.
        desired: the desired motion, one period (periodic), its load for the stations' ISO verdicts.
        log: the cycle(s) the machine ran.
        law: the law.
        base: the model's own command (:func:`first_command`), if already made.
        cycle: the logged cycle's number, for the summary.

    Raises:
        TrajectoryError: the log shorter than a period, its motion not the desired one (a learned platform's error
            above :data:`MATCH_LIMIT_DEG`), its sensors missing for a learned platform.
            Also a drive whose measured response makes the step diverge.
        ArgumentError: a gain that diverges on the model.
    """
    period = _period(desired)
    rho_model = _model_figure(law)
    base = first_command(model, desired, law) if base is None else base
    grid = desired.t - desired.t[0]
    stacked = np.concatenate([log.encoders, log.commands, log.sensors.reshape(len(log.t), 6)], axis=1)
    averaged, periods = phase_average(log.t - desired.t[0], stacked, grid, period, log.source)
    encoders, commands, sensors = averaged[:, :3], averaged[:, 3:6], averaged[:, 6:].reshape(-1, 2, 3)
    errors = desired.q[:, None, :] - sensors
    convergence = _convergence(rho_model, commands, encoders, law, period, log.commands_logged)
    if not convergence.converges:
        raise TrajectoryError(
            f"the step would diverge: with the drive's response measured in the log (encoders/commands), "
            f"‖Q(I − L·P)‖ = {convergence.data:.3g} ≥ 1 at {convergence.data_at_Hz:.3g} Hz (lower the gain or Q's "
            "cutoff, or give the model the drive's lag)",
            log.source,
        )
    for j in law.platforms:
        if not np.all(np.isfinite(sensors[:, j - 1])):
            raise TrajectoryError(
                f"no attitude sensor of platform {j}, which --control {law.control} learns from", log.source
            )
        rms = shifted_mismatch_deg(desired.q, sensors[:, j - 1])
        if rms > MATCH_LIMIT_DEG:
            raise TrajectoryError(
                f"platform {j}'s measured motion is {rms:.3g}° RMS off the desired motion at its best time shift "
                f"(more than {MATCH_LIMIT_DEG:g}°): the log is not a run of it (another trajectory or frequency?)",
                log.source,
            )
    learned_before = commands - base.carriages
    K = gain_matrices(model, desired.q, law)
    learned = update(learned_before, errors, K, law, period)
    next_L = base.carriages + learned
    if not np.all(np.isfinite(next_L)):
        k = int(np.argmax(~np.all(np.isfinite(next_L), axis=1)))
        raise TrajectoryError(f"the next command is not finite at t = {desired.t[k]:.6g} s", log.source)
    guess = np.where(np.isfinite(sensors), sensors, desired.q[:, None, :])
    predicted = attitudes(model, next_L, guess, desired.t, desired.name)
    command = StationMotion(desired.t, desired.q, next_L, predicted, law.control, law.weights)
    change = (learned - learned_before) * 1e3
    stations: tuple[StationVerdict, ...] = ()
    if desired.Fe.any():
        stations = tuple(
            station_verdict(j, desired.t, sensors[:, j - 1], desired.Fe, log.source)
            for j in (1, 2)
            if np.all(np.isfinite(sensors[:, j - 1]))
        )
    summary = LearnSummary(
        cycle,
        law.control,
        law.weights,
        law.gain,
        law.q_cutoff,
        law.drive_lag * 1e3,
        period,
        len(desired),
        periods,
        log.commands_logged,
        platform_errors(desired.t, errors, law.platforms),
        convergence,
        UpdateChange(_rms(change), _peak(change), _rms(learned * 1e3), _peak(learned * 1e3)),
        stations,
        station_verdict(0, desired.t, desired.q, desired.Fe, desired.name) if desired.Fe.any() else None,
    )
    return LearnStep(command, readonly(learned), readonly(sensors), summary)


def _rms(x: np.ndarray) -> tuple[float, float, float]:
    a, b, c = np.sqrt(np.mean(x**2, axis=0))
    return float(a), float(b), float(c)


def _peak(x: np.ndarray) -> tuple[float, float, float]:
    a, b, c = np.abs(x).max(axis=0)
    return float(a), float(b), float(c)


def _convergence(rho_model, commands, encoders, law, period, logged) -> Convergence:
    if not logged:
        return Convergence(rho_model, None, None, "no commands in the log: the drive's response is not measured")
    rho, at = data_spectral_radius(commands, encoders, law, period)
    if not math.isfinite(rho):
        return Convergence(rho_model, None, None, "no harmonic of the command strong enough to measure the drive on")
    return Convergence(rho_model, rho, at, "the drive's response (encoders/commands) per harmonic of the cycle")


def _model_figure(law: LearningLaw) -> float:
    """‖Q(I − L·P)‖ on the model; a gain for which it is ≥ 1 is refused (:class:`ArgumentError` naming ``gain``)."""
    rho = model_spectral_radius(law)
    if rho >= 1.0:
        raise ArgumentError(
            "gain", law.gain, f"a learning gain in (0, 2): ‖Q(I − L·P)‖ on the model is {rho:.3g} ≥ 1, it diverges"
        )
    return rho


def first_summary(desired: Trajectory, law: LearningLaw) -> LearnSummary:
    """The summary of cycle 0 (no run yet): the law and its figure on the model.

    Raises:
        ArgumentError: a gain that diverges on the model.
    """
    rho = _model_figure(law)
    return LearnSummary(
        0,
        law.control,
        law.weights,
        law.gain,
        law.q_cutoff,
        law.drive_lag * 1e3,
        _period(desired),
        len(desired),
        0,
        False,
        (),
        Convergence(rho, None, None, "cycle 0: no run to measure the drive on"),
        None,
        (),
    )


#: Runs one period of a command on a machine and returns its log: the seam a plant (simulated or real) plugs into.
CycleRunner = Callable[[StationMotion], CycleLog]


def learn_cycles(
    runner: CycleRunner,
    model: Parameters,
    desired: Trajectory,
    law: LearningLaw,
    cycles: int,
    notify: Callable[[str], None] | None = None,
) -> tuple[list[LearnStep], list[CycleLog]]:
    """Run ``cycles`` cycles, each command learned from the cycle before (the first the model's own).

    Args:
        runner: runs a command (one period) and returns what the machine did (:class:`CycleLog`).
        model: the controller's machine.
        desired: the desired motion, one period.
        law: the law.
        cycles: how many cycles to run, ≥ 1.
        notify: called with one line per cycle, or None.

    Returns:
        The steps (step k learned from cycle k, numbered from 1) and the cycles' logs.
    """
    if cycles < 1:
        raise ArgumentError("cycles", cycles, "at least 1")
    base = first_command(model, desired, law)
    command = base
    steps, logs = [], []
    for k in range(1, cycles + 1):
        log = runner(command)
        step = learning_step(model, desired, log, law, base, cycle=k)
        steps.append(step)
        logs.append(log)
        command = step.command
        if notify is not None:
            notify(f"cycle {k}: learned platforms' RMS error {step.summary.controlled_rms_deg():.4g}°")
    return steps, logs

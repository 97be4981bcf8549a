"""A cycle runner on a simulated servo loop: what ``hipsim simulate --learn`` learns on.

:func:`servo_runner` makes the :data:`~hipsim.learning.step.CycleRunner` that
:func:`~hipsim.learning.step.learn_cycles` calls once a cycle. A command (the
carriages of one period) becomes the reference the servo loop tracks: the
motion it gives the model's controlled platform (forward kinematics through
the model, rates and accelerations from the period's exact derivatives,
:func:`hipsim.analytic.stations.follower_motion`), tracked by the augmented PD
(workspace PD plus the model's inverse-dynamics torque along that
reference: the feed-forward learned in carriage positions and in torque). Each
cycle starts on the reference's state at t = 0 and runs one period; the log
has the reference carriages as commands, the plant's carriages as encoders
and the plant's attitude as both sensors (today's plants turn both
platforms alike).

The seam: any function taking a command and returning a
:class:`~hipsim.learning.step.CycleLog` is a runner. :func:`machine_runner`
is the one on the machine as built (per-chain plant, the controller knowing
only its model, closed through encoders or an attitude sensor:
:func:`hipsim.control.machine_loop.run_machine`); its log's sensors are both
platforms' true attitudes (plus the sensor's noise), so a platform the
drawing-model predicts wrongly shows its real error.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..analytic.stations import carriages_for_platform, follower_motion
from ..control.controllers import AugmentedPD
from ..control.simulation import Simulation, simulate
from ..engine import Plant
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory, interpolator
from ..stations.commands import StationMotion
from .filters import periodic_derivatives
from .step import CycleLog, CycleRunner

__all__ = ["machine_runner", "reference_motion", "servo_runner"]


def reference_motion(model: Parameters, command: StationMotion, load: np.ndarray, period: float) -> Trajectory:
    """The motion a periodic carriage command gives the model's controlled platform: q, q̇, q̈ in [rad], [rad/s], [rad/s²].

    Args:
        model: the controller's machine.
        command: one period of carriage commands (with the model's predicted attitudes as the starting guess).
        load: the axial load in [N] at the command's samples, (N,).
        period: the period in [s].
    """
    platform = model.geometry.control if model.geometry is not None else 2
    Ld, Ldd = periodic_derivatives(command.carriages, period)
    q, qd, qdd = follower_motion(
        model, command.carriages, Ld, Ldd, platform, t=command.t, guess=command.attitudes[:, platform - 1]
    )
    return Trajectory(command.t, q, qd, qdd, load, "learned reference", periodic=True)


def servo_runner(
    plant: Plant,
    model: Parameters,
    load: np.ndarray,
    period: float,
    servo_rate: float | None = None,
    runs: list[Simulation] | None = None,
) -> CycleRunner:
    """A runner: one period of the augmented PD on ``plant`` tracking the reference each command gives.

    Args:
        plant: the machine being driven (today's plants: the drawing, masses and friction set apart by ``--mismatch``).
        model: the controller's machine.
        load: the desired motion's load in [N] at the command's samples, (N,).
        period: the cycle's period in [s].
        servo_rate: the servo rate in [Hz]; default the plant's parameters'.
        runs: a list the runs are appended to (for their tables), or None.
    """
    rate = plant.params.control.servo_rate if servo_rate is None else servo_rate

    def run(command: StationMotion) -> CycleLog:
        reference = reference_motion(model, command, load, period)
        at = interpolator(reference)
        controller = AugmentedPD(model, at, rate, period)
        sim = simulate(plant, controller, at, period, servo_rate=rate, controller_name="augmented-pd (learning)")
        if runs is not None:
            runs.append(sim)
        encoders = carriages_for_platform(plant.params, sim.q, 2)
        t0 = command.t[0]
        commands = np.stack(
            [np.interp(sim.t, command.t - t0, command.carriages[:, i], period=period) for i in range(3)], axis=1
        )
        sensors = np.stack([sim.q, sim.q], axis=1)
        return CycleLog(sim.t + t0, encoders, commands, sensors, True, f"{sim.plant} plant")

    return run


def machine_runner(
    plant,
    model: Parameters,
    control: int,
    feedback: Callable[[int], object],
    load: np.ndarray,
    period: float,
    servo_rate: float,
    sensor_noise: float = 0.0,
    seed: int = 0,
    runs: list | None = None,
) -> CycleRunner:
    """A runner on the machine as built: :func:`~hipsim.control.machine_loop.run_machine`, the model's PD on platform
    ``control`` plus the MODEL's inverse-dynamics torque along the reference each command gives (the feed-forward
    learned in carriage positions and in torque).

    Args:
        plant: the machine as built (a :class:`~hipsim.control.machine_loop.MachinePlant` whose ``[geometry] control``
            is ``control``).
        model: the controller's model (the drawing, a calibrated file).
        control: the controlled platform, 1 or 2.
        feedback: makes the loop's :class:`~hipsim.control.feedback.Feedback` for cycle k (numbered from 1), so that
            a sensor's noise is not the same from cycle to cycle.
        load: the desired motion's load in [N] at the command's samples, (N,).
        period: the cycle's period in [s]; servo_rate: [Hz].
        sensor_noise: the logged attitude sensors' white noise, standard deviation in [rad] (0: exact).
        seed: the logged sensors' noise seed (one generator over all cycles).
        runs: a list the runs (:class:`~hipsim.control.tracking.MachineRun`) are appended to, or None.
    """
    from ..control.machine_loop import ModelPD, controlled_machine, model_feedforward, run_machine

    machine = controlled_machine(model, control)
    rng = np.random.default_rng(seed)
    cycle = [0]

    def run(command: StationMotion) -> CycleLog:
        cycle[0] += 1
        reference = reference_motion(machine, command, load, period)
        at = interpolator(reference)
        feedforward = model_feedforward(model, control, at, servo_rate, period)
        result = run_machine(
            plant,
            ModelPD(model, control),
            feedback(cycle[0]),  # type: ignore[arg-type]
            at,
            period,
            feedforward=feedforward,
            servo_rate=servo_rate,
            controller_name="augmented-pd (learning)",
        )
        if runs is not None:
            runs.append(result)
        t0 = command.t[0]
        commands = np.stack(
            [np.interp(result.t, command.t - t0, command.carriages[:, i], period=period) for i in range(3)], axis=1
        )
        sensors = result.attitudes
        if sensor_noise > 0:
            sensors = sensors + rng.normal(0.0, sensor_noise, sensors.shape)
        return CycleLog(result.t + t0, result.carriages, commands, sensors, True, f"{result.plant} plant")

    return run

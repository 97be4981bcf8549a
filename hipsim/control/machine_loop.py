"""The servo loop on the machine as built: a plant that is one machine, a controller that knows another (its model).

:func:`hipsim.control.simulation.simulate` drives a plant with a controller
that sees the plant's own platform state: plant and model are one machine up
to ``--mismatch``. Here they are two parameter sets:

- the **plant** is the machine as built (per-chain ``[geometry]``, its own
  masses, friction and drive): a :class:`~hipsim.closed_chain.plant.PinocchioPlant`
  or :class:`~hipsim.mujoco_engine.plant.MujocoPlant` built from it (their
  per-chain trees come from the same builder the stations use,
  :attr:`hipsim.machine.parameter_set.Parameters.chains`), or the reduced
  plant on a machine without ``[geometry]``;
- the **controller** (:class:`ModelPD`) knows only its model (the drawing, a
  calibrated or an identified file): its Jacobian, its inverse dynamics for
  the feed-forward (:func:`model_feedforward`), and, through a
  :class:`~hipsim.control.feedback.Feedback`, its forward kinematics to read
  the encoders.

Each servo period: the plant's true carriages and attitudes; what the
feedback makes of them; the PD torques of the model's controlled platform
plus the feed-forward row of the period, limited, held over the period while
the plant integrates (its ``advance``, or RK4 through its ``derivative``).
The loop is a library function taking a plant object, a controller and a
feed-forward array, so that a learning controller can call it run after run
with its own feed-forward.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from ..analytic.chain_dynamics import chain_inverse_dynamics, chain_motion
from ..analytic.stations import carriages_for_platform
from ..engine import Plant
from ..exceptions import ArgumentError, ParameterError, PoseError
from ..machine.chains import CHAIN_LABELS, MAX_DEVIATION
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics.transmission import angle_from_travel
from . import chain_kernel
from .controllers import _gains, feedforward_torques
from .feedback import EncoderFeedback, Feedback, SensorFeedback
from .simulation import _CHUNK, _rk4, _servo_chunks, _unstable, servo_settings
from .tracking import MachineRun

__all__ = ["MachinePlant", "ModelPD", "check_plant", "controlled_machine", "model_feedforward", "run_machine"]


class MachinePlant(Plant, Protocol):
    """A plant the loop reads as the machine's sensors do: the carriages and both platforms' attitudes."""

    def readings(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Carriage readings [m] and rates [m/s], (3,); both platforms' gait angles [rad] and rates [rad/s], (2, 3)."""
        ...


def controlled_machine(params: Parameters, control: int) -> Parameters:
    """``params`` with ``[geometry] control`` set to ``control`` (1 or 2): the platform a trajectory (and a plant's first state) gives.

    The drawing (no ``[geometry]``) is returned as it is: its platforms turn alike.
    """
    if params.geometry is None or params.geometry.control == control:
        return params
    return params.replace(geometry=params.geometry.replace(control=control))


class ModelPD:
    """The workspace PD of the model's controlled platform: τ = (p/2π)·J_c(q)⁻ᵀ·(K_p·Δq + K_d·Δq̇).

    J_c is the controlled platform's Jacobian on the model (on the drawing the
    law of :class:`~hipsim.control.controllers.WorkspacePD`; on a per-chain
    model that platform's own chains; with m_1 controlled on a stacked model,
    L̇ = J_c·ω_1 through the stack-up, :func:`~hipsim.control.chain_kernel.model_pd`).

    Args:
        model: the controller's model of the machine.
        control: the controlled platform, 1 or 2.
        kp, kd: gains per angle in [N·m/rad] and [N·m·s/rad]; default ``model.control``'s.
    """

    def __init__(self, model: Parameters, control: int, kp=None, kd=None):
        if control not in (1, 2) or isinstance(control, bool):
            raise ArgumentError("control", control, "1 (m_1) or 2 (m_2)")
        self.model, self.control = model, int(control)
        self.kp = _gains(model.control.kp if kp is None else kp, "kp")
        self.kd = _gains(model.control.kd if kd is None else kd, "kd")
        self._model = chain_kernel.model_arrays(model, self.control)
        self._lead = float(model.lead)

    def torques(self, q: np.ndarray, qd: np.ndarray, q_desired: np.ndarray, qd_desired: np.ndarray) -> np.ndarray:
        """Motor torques in [N·m], (3,), for measured gait angles q [rad] and rates qd [rad/s] and desired ones, each (3,)."""
        return chain_kernel.model_pd(*self._model, self._lead, q, qd, q_desired, qd_desired, self.kp, self.kd)


def model_feedforward(
    model: Parameters, control: int, desired_at: Callable[[np.ndarray], Trajectory], servo_rate: float, duration: float
) -> np.ndarray:
    """The model's inverse-dynamics motor torques in [N·m], (n, 3), at the middle of each servo period (the augmented PD's).

    On the drawing :func:`~hipsim.control.controllers.feedforward_torques` (as
    :class:`~hipsim.control.controllers.AugmentedPD`); on a per-chain model the
    torques of both platforms when ``control`` follows the desired motion
    (:func:`hipsim.analytic.chain_dynamics.chain_inverse_dynamics`).

    Args:
        model: the controller's model; control: the controlled platform (1, 2).
        desired_at: the desired motion as a function of time in [s].
        servo_rate: [Hz]; duration: [s].
    """
    n = int(round(duration * servo_rate))
    desired = desired_at((np.arange(n) + 0.5) / servo_rate)
    if model.geometry is None:
        return feedforward_torques(model, desired)
    machine = controlled_machine(model, control)
    return chain_inverse_dynamics(machine, chain_motion(machine, desired), desired.Fe).total


def run_machine(
    plant: MachinePlant,
    controller: ModelPD,
    feedback: Feedback,
    desired_at: Callable[[np.ndarray], Trajectory],
    duration: float,
    feedforward: np.ndarray | None = None,
    servo_rate: float | None = None,
    step: float | None = None,
    torque_limit: float | None = None,
    progress: bool = False,
    notify: Callable[[str], None] | None = None,
    controller_name: str = "",
    compiled: bool | None = None,
) -> MachineRun:
    """Run the servo loop of ``controller`` (which knows its model) on ``plant`` (the machine as built).

    Args:
        plant: the machine being driven; it offers ``readings(x)`` (carriages and both platforms' attitudes).
        controller: the model's PD; its ``control`` platform is the one the desired motion gives.
        feedback: what the controller sees (:class:`~hipsim.control.feedback.EncoderFeedback` or
            :class:`~hipsim.control.feedback.SensorFeedback`); its platform must be the controller's.
        desired_at: the desired motion of the controlled platform as a function of time in [s] (its load is the plant's).
        duration: simulated time in [s].
        feedforward: motor torques in [N·m] added in each servo period, (n, 3) (e.g. :func:`model_feedforward`,
            or a learnt one); None for none.
        servo_rate, step, torque_limit: as :func:`hipsim.control.simulation.simulate` (defaults: the model's settings).
        progress, notify, controller_name: as :func:`hipsim.control.simulation.simulate`.
        compiled: run the loop compiled (:mod:`hipsim.control.machine_kernel`), which needs a plant with a
            ``compiled_stepper()`` (the Pinocchio plant on its compiled route), a :class:`ModelPD` and one of the two
            feedbacks (not subclasses); False: the Python loop; None: compiled where possible. The same arithmetic.

    Raises:
        PoseError: naming the time when the desired motion is out of the model's reach, the plant leaves its
            workspace or goes unstable, or the model finds no attitude for what the encoders read.
        ArgumentError: settings out of range, a feed-forward of the wrong shape, a feedback on another platform.
    """
    servo_rate, step, limit = _settings(plant, controller, feedback, servo_rate, step, torque_limit)
    period = 1.0 / servo_rate
    substeps = math.ceil(period / step - 1e-9)
    h = period / substeps
    n = int(round(duration * servo_rate))
    if n < 2:
        raise ArgumentError("duration", duration, f"at least two servo periods ({2 * period:g} s)")
    # A writable C copy whatever the caller gives (model_feedforward returns a read-only Fortran view): numba
    # compiles the loop once per array type, and each compile costs seconds.
    ff = np.zeros((n, 3)) if feedforward is None else np.array(feedforward, dtype=float, order="C")
    if ff.shape != (n, 3):
        raise ArgumentError("feedforward", ff.shape, f"torques of shape ({n}, 3), one row a servo period")
    t = np.arange(n) * period
    desired = desired_at(t)
    _check_reach(controller.model, controller.control, desired)
    loads = np.ascontiguousarray(desired_at(np.arange(n * substeps * 2 + 1) * (h / 2)).Fe)  # a Trajectory's are floats
    advance = getattr(plant, "advance", None) or (lambda *args: _rk4(plant, *args))

    x = plant.initial_state(desired)  # at its first sample (the Plant protocol)
    feedback.start(t, desired.q[0])
    carriages, measured = np.empty((n, 3)), np.empty((n, 3))
    attitudes, rates, speeds = np.empty((n, 2, 3)), np.empty((n, 2, 3)), np.empty((n, 3))
    tau, tau_requested, saturated = np.empty((n, 3)), np.empty((n, 3)), np.zeros(n, dtype=bool)
    name = getattr(plant, "name", type(plant).__name__)  # a plant's name is optional (the Plant protocol)
    desc = f"{name} plant, {controller_name or 'controller'}, {feedback.name}"
    log = (carriages, attitudes, rates, speeds, measured, tau, tau_requested, saturated)
    stepper = plant.compiled_stepper() if hasattr(plant, "compiled_stepper") else None
    can_compile = (
        stepper is not None and type(controller) is ModelPD and type(feedback) in (EncoderFeedback, SensorFeedback)
    )
    if compiled and not can_compile:
        raise ArgumentError(
            "compiled", compiled, "False or None, unless the plant offers compiled_stepper() (the PinocchioPlant)"
        )
    if can_compile and compiled is not False:
        from . import machine_kernel  # imports Pinocchio: only when such a run starts

        compiled_plant: Any = plant  # the PinocchioPlant: its slots in the state
        arguments = (
            compiled_plant.reading_slots,
            compiled_plant.angle_slots[2],  # the plant's own float copy
            feedback.sensing(),
            (*controller._model, controller._lead),
            (controller.kp, controller.kd),
            controller.control - 1,
        )
        for start, stop in _servo_chunks(n, _CHUNK, desc, progress, notify):
            reached = machine_kernel.machine_loop(
                stepper, x, *arguments, start, stop, desired.q, desired.qd, ff, float(limit), loads, h, substeps, log
            )
            if reached != stop:
                if np.all(np.isfinite(x)):
                    raise _no_attitude(feedback, carriages[reached], t, reached)
                raise _unstable(t, reached)
        return _run(plant, name, controller, feedback, controller_name, t, desired, log, h)
    for start, stop in _servo_chunks(n, 500, desc, progress, notify):
        for k in range(start, stop):
            if not np.all(np.isfinite(x)):
                raise _unstable(t, k)
            L, Ld, q, qd = plant.readings(x)
            attitudes[k], rates[k], speeds[k] = q, qd, Ld
            carriages[k], q_seen, qd_seen = feedback.measure(k, t[k], L, Ld, q, qd)
            if not np.all(np.isfinite(q_seen)):
                raise _no_attitude(feedback, carriages[k], t, k)
            measured[k] = q_seen
            wanted = ff[k] + controller.torques(q_seen, qd_seen, desired.q[k], desired.qd[k])
            tau_requested[k] = wanted
            tau[k] = np.clip(wanted, -limit, limit)
            saturated[k] = np.any(np.abs(wanted) > limit)
            x = advance(t[k], x, tau[k], loads[2 * substeps * k : 2 * substeps * (k + 1) + 1], h, substeps)
    return _run(plant, name, controller, feedback, controller_name, t, desired, log, h)


def _settings(
    plant: MachinePlant,
    controller: ModelPD,
    feedback: Feedback,
    servo_rate: float | None,
    step: float | None,
    torque_limit: float | None,
) -> tuple[float, float, float]:
    """(servo rate [Hz], step [s], torque limit [N·m]), the model's where not given, checked with the loop's parts."""
    servo_rate, step, limit = servo_settings(controller.model.control, servo_rate, step, torque_limit)
    if feedback.control != controller.control:
        raise ArgumentError("feedback", feedback.control, f"the controller's platform {controller.control}")
    geometry = plant.params.geometry
    if geometry is not None and geometry.control != controller.control:  # its first state holds that platform
        raise ArgumentError(
            "plant",
            f"a plant whose [geometry] control is {geometry.control}",
            f"a plant built from controlled_machine(params, {controller.control}), whose first state holds the "
            "controlled platform at the desired motion",
        )
    return servo_rate, step, limit


def _no_attitude(feedback: Feedback, reading: np.ndarray, t: np.ndarray, k: int) -> PoseError:
    return PoseError(
        f"the model's forward kinematics finds no attitude of platform {feedback.control} for what the encoders "
        f"read ({', '.join(f'{v * 1e3:.4f}' for v in reading)} mm)",
        float(t[k]),
        k,
    )


def _run(plant, name, controller, feedback, controller_name, t, desired, log, h) -> MachineRun:
    carriages, attitudes, rates, speeds, measured, tau, tau_requested, saturated = log
    return MachineRun(
        t=t,
        desired=desired,
        carriages=carriages,
        attitudes=attitudes,
        rates=rates,
        measured=measured,
        tau=tau,
        tau_requested=tau_requested,
        saturated=saturated,
        motor_speed=angle_from_travel(speeds, plant.params.lead),
        plant=name,
        controller=controller_name,
        feedback=feedback.name,
        control=controller.control,
        step=h,
    )


def _check_reach(model: Parameters, control: int, desired: Trajectory) -> None:
    """The desired motion within the model's reach for its controlled platform, else a PoseError naming the time."""
    L = carriages_for_platform(model, desired.q, control)
    bad = ~np.all(np.isfinite(L), axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise PoseError(
            f"pose out of reach of the model's platform {control}: a lever cannot span the gap from its U-joint to "
            "its platform joint",
            float(desired.t[k]),
            k,
            source=desired.name,
        )


def check_plant(model: Parameters, plant: Parameters, desired: Trajectory, control: int) -> None:
    """Refuse a plant that is not the model's machine as built: another drawing, or one the model's commands cannot drive.

    The plant may deviate from the model chain by chain as a built machine
    deviates from its drawing (each U-joint centre, platform joint, lever length
    and rotation centre within :data:`~hipsim.machine.chains.MAX_DEVIATION` of the
    model's), with its own masses, friction and drive, and the same angle
    conventions; and its controlled platform must reach the desired motion where
    the model puts the carriages for it.

    Args:
        model: the controller's model; plant: the plant's machine.
        desired: the desired motion of the controlled platform; control: that platform (1, 2).

    Raises:
        ParameterError: naming the plant's file and what contradicts the model.
    """
    if not np.array_equal(model.angle_signs, plant.angle_signs):
        raise ParameterError(
            f"the plant's angle signs {plant.angle_signs.tolist()} are not the model's {model.angle_signs.tolist()}: "
            "one machine has one convention",
            key="angles",
            source=plant.source,
        )
    a, b = model.chains, plant.chains
    parts = (
        ("U-joint centre", a.screw_points - b.screw_points),
        ("platform joint", a.platform_points - b.platform_points),
        ("lever length", (a.lever_lengths - b.lever_lengths)[..., None]),
        ("rotation centre", a.centres - b.centres),  # one a platform
    )
    for what, difference in parts:
        off = np.linalg.norm(difference, axis=-1)
        k = int(np.argmax(off))
        if off.flat[k] > MAX_DEVIATION:
            where = f"platform {k + 1}" if what == "rotation centre" else f"chain {CHAIN_LABELS[k]}"
            raise ParameterError(
                f"not the model's machine as built: the {what} of {where} is {off.flat[k] * 1e3:.1f} mm off the "
                f"model's (a built machine deviates by at most {MAX_DEVIATION * 1e3:g} mm; give the plant and the "
                "model of one design)",
                source=plant.source,
            )
    from ..analytic.stations import platform_attitude

    L = carriages_for_platform(model, desired.q, control)
    try:
        _check_reach(model, control, desired)
        platform_attitude(plant, L, control, t=desired.t, q0=desired.q[0], guess=desired.q)
    except PoseError as error:
        raise ParameterError(
            f"the plant's platform {control} cannot follow the carriages the model commands: {error}",
            source=plant.source,
        ) from None

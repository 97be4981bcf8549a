"""Closed-loop simulation: plants (forward dynamics) driven by a servo-rate controller (spec §8).

A plant integrates the machine's forward dynamics under the three motor
torques. Two plants describe the same physics:

- :class:`ReducedPlant`: the 3-DOF model of the platform orientation. The
  analytic inverse dynamics is affine in the angular acceleration,
  τ = M(q)·q̈ + h(q, q̇, F_e), so its value at q̈ = 0 gives h and its values
  at the three unit accelerations give the columns of M, and
  q̈ = M⁻¹·(τ − h). The servo loop needs this for one state at a time, where
  the vectorised model spends its time in Python overhead, so the plant runs
  the same equations compiled by :mod:`hipsim.analytic.kernel`.
- :class:`hipsim.closed_chain.plant.PinocchioPlant`: the closed-chain tree with
  its loop closures enforced by Pinocchio's constrained dynamics.

:func:`simulate` runs the servo loop: at each servo instant the controller
sees the measured state and the desired one and returns torques, which are
limited to the motor torque limit (and counted when they are) and held
constant over the servo period (zero-order hold) while the plant is integrated
with the classic fourth-order Runge–Kutta method at a step no longer than the
period. A plant with an ``advance`` method (the reduced plant) integrates a
whole servo period in one call; for any other plant :func:`simulate` steps
RK4 itself through the plant's ``derivative``. What a plant offers is the
:class:`~hipsim.engine.Plant` protocol (re-exported here).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from ..analytic import kernel as reduced_kernel
from ..analytic.inverse_kinematics import kinematics
from ..analytic.kernel import floats
from ..clock import note_if_slow
from ..engine import Plant
from ..exceptions import ArgumentError, PoseError
from ..files import write_columns
from ..machine.parameter_set import FRICTION_COEFFICIENTS, ControlSettings
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics.transmission import angle_from_travel
from ..physics.units import RPM_PER_RAD_S
from .controllers import AugmentedPD, Sample, WorkspacePD
from .simulation_summary import SimulationSummary, simulation_summary

__all__ = ["Plant", "ReducedPlant", "Simulation", "apply_mismatch", "parse_mismatch", "servo_settings", "simulate"]


class ReducedPlant:
    """Forward dynamics of the 3-DOF reduced model; state x = [q, q̇] in gait angles.

    Args:
        params: the plant's machine.
        lever_spin: give the levers the spin their universal joints impose
            (True, the physics the Pinocchio plant has) or the spec's
            spin-free levers (False).
    """

    name = "reduced"

    def __init__(self, params: Parameters, lever_spin: bool = True):
        self.params = params
        self._lever_spin = bool(lever_spin)
        self._kernel_params = reduced_kernel.kernel_parameters(params, lever_spin)

    @property
    def lever_spin(self) -> bool:
        """Whether the levers spin as their universal joints impose (fixed at construction)."""
        return self._lever_spin

    def mass_and_bias(self, q: np.ndarray, qd: np.ndarray, Fe: float) -> tuple[np.ndarray, np.ndarray]:
        """M(q) in [N·m·s²/rad] (3, 3) and h(q, q̇, F_e) in [N·m] (3,) with τ = M·q̈ + h.

        NaN where a lever cannot reach; :func:`hipsim.analytic.virtual_work.mass_and_bias`
        gives the same along a trajectory and names the time of a bad pose.

        Args:
            q: orientation in [rad], (3,).
            qd: its rate in [rad/s], (3,).
            Fe: load in [N].
        """
        return reduced_kernel.mass_and_bias(
            self._kernel_params, floats(q, (3,), "q"), floats(qd, (3,), "qd"), float(Fe)
        )

    def compiled_kernel(self) -> tuple | None:
        """The parameters of :mod:`hipsim.analytic.kernel` whose equations this plant integrates, for the compiled servo loop.

        None for a subclass: it may change the equations (its derivative, its
        angles, its initial state), which the kernel would not see.
        """
        return self._kernel_params if type(self) is ReducedPlant else None

    def initial_state(self, desired: Trajectory) -> np.ndarray:
        return np.concatenate([desired.q[0], desired.qd[0]])

    def derivative(self, t: float, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        return reduced_kernel.derivative(
            self._kernel_params, floats(x, (6,), "state x"), floats(tau, (3,), "tau"), float(Fe)
        )

    def advance(
        self, t: float, x: np.ndarray, tau: np.ndarray, loads: np.ndarray, h: float, substeps: int
    ) -> np.ndarray:
        """The state after ``substeps`` RK4 steps of h [s] from x at time t [s], under motor torques tau [N·m].

        ``loads`` are the loads F_e in [N] at every half step, (2·substeps + 1,).
        The steps run compiled; a subclass that overrides :meth:`derivative`
        is stepped through its own derivative instead.
        """
        if type(self).derivative is not ReducedPlant.derivative:
            return _rk4(self, t, x, tau, loads, h, substeps)
        x, tau = floats(x, (6,), "state x"), floats(tau, (3,), "tau")
        loads = floats(loads, (2 * substeps + 1,), "loads")
        return reduced_kernel.advance(self._kernel_params, x, tau, loads, float(h), int(substeps))

    def angles(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[:3], x[3:]

    def readings(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The carriages' readings L_1i [m] and rates [m/s], (3,), and both platforms' (alike) gait angles and rates, (2, 3)."""
        from ..analytic.stations import platform_motion

        q, qd = x[None, :3], x[None, 3:]
        L, Ld, _ = platform_motion(self.params, q, qd, np.zeros_like(q), 1)
        return L[0], Ld[0], np.repeat(q, 2, axis=0), np.repeat(qd, 2, axis=0)


@dataclass(frozen=True, eq=False)
class Simulation:
    """A closed-loop run, sampled at the servo instants.

    Attributes:
        t: servo instants in [s], (K,).
        desired: the desired trajectory at those instants.
        q, qd: measured orientation in [rad] and rate in [rad/s], (K, 3).
        tau: torques applied (after the limit) in [N·m], (K, 3).
        tau_requested: torques the controller asked for in [N·m], (K, 3).
        saturated: samples where a torque was limited, (K,).
        motor_speed: motor speeds in [rad/s], (K, 3).
        plant, controller: names, for tables.
        step: the integration step used in [s] (the one asked for, rounded
            down so that whole steps fill a servo period).
    """

    t: np.ndarray
    desired: Trajectory
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    tau_requested: np.ndarray
    saturated: np.ndarray
    motor_speed: np.ndarray
    plant: str = ""
    controller: str = ""
    step: float = math.nan

    @property
    def err(self) -> np.ndarray:
        """Tracking error q_d − q in [rad], (K, 3)."""
        return self.desired.q - self.q

    def summary(self) -> SimulationSummary:
        """Peak and RMS of each angle's error in [deg] and of each motor's torque in [N·mm], peak speeds in [rpm]."""
        return simulation_summary(self)

    def write_csv(self, path) -> Path:
        """Write :meth:`columns` to ``path`` atomically. Returns the path."""
        return write_columns(path, self.columns())

    def columns(self) -> dict[str, np.ndarray]:
        """CSV columns: desired and actual angles, errors, torques and speeds, with units in the names."""
        out = {"t_s": self.t}
        for k, n in enumerate(("alpha", "beta", "gamma")):
            out[f"{n}_des_deg"] = np.degrees(self.desired.q[:, k])
            out[f"{n}_deg"] = np.degrees(self.q[:, k])
            out[f"err_{n}_deg"] = np.degrees(self.err[:, k])
        for i in range(3):
            out[f"tau_{i + 1}_Nmm"] = self.tau[:, i] * 1e3
        for i in range(3):
            out[f"tau_req_{i + 1}_Nmm"] = self.tau_requested[:, i] * 1e3
        for i in range(3):
            out[f"speed_{i + 1}_rpm"] = self.motor_speed[:, i] * RPM_PER_RAD_S
        out["saturated"] = self.saturated.astype(float)
        return out


def servo_settings(
    control: ControlSettings, servo_rate: float | None, step: float | None, torque_limit: float | None
) -> tuple[float, float, float]:
    """(servo rate [Hz], integration step [s], torque limit [N·m]): the given values, else ``control``'s, checked.

    Args:
        control: the parameter set's control settings (``servo_rate``, ``integration_step``, ``torque_limit``).
        servo_rate: servo rate in [Hz], or None for ``control``'s.
        step: integration step in [s], positive and at most one servo period, or None for ``control``'s.
        torque_limit: motor torque limit in [N·m] (inf: none), or None for ``control``'s.
    """
    servo_rate = control.servo_rate if servo_rate is None else servo_rate
    step = control.integration_step if step is None else step
    limit = control.torque_limit if torque_limit is None else torque_limit
    if not servo_rate > 0:
        raise ArgumentError("servo_rate", servo_rate, "a positive rate in Hz")
    if not limit > 0:
        raise ArgumentError("torque_limit", limit, "a positive torque in N·m (inf for none)")
    period = 1.0 / servo_rate
    if not step > 0:
        raise ArgumentError("step", step, "a positive integration step in s")
    if step > period * (1 + 1e-9):
        raise ArgumentError("step", step, f"an integration step no longer than the servo period {period:g} s")
    return servo_rate, step, limit


def _rk4(
    plant: Plant, t: float, x: np.ndarray, tau: np.ndarray, loads: np.ndarray, h: float, substeps: int
) -> np.ndarray:
    """``substeps`` classic RK4 steps of h [s] through ``plant.derivative``; loads at every half step."""
    for s in range(substeps):
        time = t + s * h
        k1 = plant.derivative(time, x, tau, loads[2 * s])
        k2 = plant.derivative(time + h / 2, x + h / 2 * k1, tau, loads[2 * s + 1])
        k3 = plant.derivative(time + h / 2, x + h / 2 * k2, tau, loads[2 * s + 1])
        k4 = plant.derivative(time + h, x + h * k3, tau, loads[2 * s + 2])
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def simulate(
    plant: Plant,
    controller: Callable[[float, Sample, Sample], np.ndarray],
    desired_at: Callable[[np.ndarray], Trajectory],
    duration: float,
    servo_rate: float | None = None,
    step: float | None = None,
    torque_limit: float | None = None,
    initial_state: np.ndarray | None = None,
    progress: bool = False,
    notify: Callable[[str], None] | None = None,
    controller_name: str = "",
    compiled: bool | None = None,
) -> Simulation:
    """Run the servo loop.

    Args:
        plant: the machine being driven.
        controller: ``controller(t, state, desired) -> tau`` in [N·m].
        desired_at: the desired trajectory as a function of time in [s] (its
            load F_e is the load the plant feels).
        duration: simulated time in [s].
        servo_rate: servo rate in [Hz]; default ``plant.params.control.servo_rate``.
        step: integration step in [s], at most one servo period (rounded down so
            that whole steps fill a period); default from the plant's parameters.
        torque_limit: motor torque limit in [N·m]; default from the plant's parameters (inf: none).
        initial_state: the plant state at t = 0; default the desired state.
        progress: show a progress bar (tqdm, on standard error) if the run takes more than two seconds.
        notify: called with a one-line message when the first servo step
            takes more than a second (the numba kernels compiling on a
            machine's first run), so the caller can say so; None for silence.
        controller_name: a name for tables.
        compiled: run the loop compiled (:mod:`hipsim.control.servo_kernel`),
            which needs the controller to be a
            :class:`~hipsim.control.controllers.WorkspacePD` or
            :class:`~hipsim.control.controllers.AugmentedPD` (not subclasses):
            the whole loop for a :class:`ReducedPlant`, the control of each
            period around the plant's ``advance`` for a plant with
            ``angle_slots`` (the Pinocchio plant); False: the Python loop,
            calling the controller every period; None: compiled where possible.

    Returns:
        The run at the servo instants.

    Raises:
        PoseError: naming the time when the desired motion is out of reach or
            singular, or when the plant leaves the workspace or goes unstable.
        ArgumentError: ``compiled=True`` for a plant or controller the compiled loop does not know.
    """
    servo_rate, step, limit = servo_settings(plant.params.control, servo_rate, step, torque_limit)
    period = 1.0 / servo_rate
    substeps = math.ceil(period / step - 1e-9)
    h = period / substeps
    n = int(round(duration * servo_rate))
    if n < 2:
        raise ArgumentError("duration", duration, f"at least two servo periods ({2 * period:g} s)")
    t = np.arange(n) * period
    desired = desired_at(t)
    kinematics(plant.params, desired)  # a desired pose out of reach or singular: a PoseError naming its time
    stage_times = np.arange(n * substeps * 2 + 1) * (h / 2)
    stage_loads = desired_at(stage_times).Fe  # the load at every RK4 stage, precomputed
    kernel = plant.compiled_kernel() if hasattr(plant, "compiled_kernel") else None
    slotted = hasattr(plant, "angle_slots") and hasattr(plant, "advance")
    can_compile = (kernel is not None or slotted) and type(controller) in (WorkspacePD, AugmentedPD)
    if compiled and not can_compile:
        raise ArgumentError(
            "compiled",
            compiled,
            "False, or None, unless the controller is a WorkspacePD or AugmentedPD and the plant a ReducedPlant or one with angle_slots (the PinocchioPlant)",
        )
    use_compiled = can_compile if compiled is None else bool(compiled)

    x = (
        plant.initial_state(desired.slice(slice(0, 1)))
        if initial_state is None
        else np.asarray(initial_state, dtype=float)
    )
    q, qd = np.empty((n, 3)), np.empty((n, 3))
    tau_applied, tau_requested = np.empty((n, 3)), np.empty((n, 3))
    saturated = np.zeros(n, dtype=bool)
    name = getattr(plant, "name", type(plant).__name__)
    desc = f"{name} plant, {controller_name or 'controller'}"
    if use_compiled:
        log = (q, qd, tau_applied, tau_requested, saturated)
        x = floats(x, (6,), "initial_state") if kernel is not None else x
        _compiled_loop(
            plant, kernel, controller, x, t, desired, limit, stage_loads, h, substeps, log, desc, progress, notify
        )
    else:
        advance = getattr(plant, "advance", None) or (lambda *args: _rk4(plant, *args))
        for k, _ in _servo_chunks(n, 1, desc, progress, notify):
            q[k], qd[k] = plant.angles(x)
            if not np.all(np.isfinite(x)):
                raise _unstable(t, k)
            wanted = np.asarray(
                controller(
                    t[k],
                    Sample(q[k].copy(), qd[k].copy()),
                    Sample(desired.q[k], desired.qd[k], desired.qdd[k], float(desired.Fe[k])),
                ),
                dtype=float,
            )
            tau_requested[k] = wanted
            tau_applied[k] = np.clip(wanted, -limit, limit)
            saturated[k] = np.any(np.abs(wanted) > limit)
            x = advance(
                t[k], x, tau_applied[k], stage_loads[2 * substeps * k : 2 * substeps * (k + 1) + 1], h, substeps
            )

    actual = Trajectory(t, q, qd, np.zeros_like(q), desired.Fe, name="actual")
    try:
        motor_speed = angle_from_travel(kinematics(plant.params, actual).Ld[:, 0], plant.params.lead)
    except PoseError as error:
        raise PoseError("the plant left the workspace", error.time, error.index) from None
    return Simulation(t, desired, q, qd, tau_applied, tau_requested, saturated, motor_speed, name, controller_name, h)


def _unstable(t: np.ndarray, k: int) -> PoseError:
    return PoseError(
        "the plant's state is no longer finite: the loop went unstable or the machine left its workspace "
        "(check the gains control.kp_Nm_rad and kd_Nm_s_rad, the integration step and the masses)",
        t[k],
        k,
    )


#: Servo periods per compiled call: a progress bar's tick, ~0.02 s of the compiled loop.
_CHUNK = 2000


def _compiled_loop(
    plant, kernel, controller, x, t, desired, limit, loads, h, substeps, log, desc, progress, notify
) -> None:
    """The servo loop with the built-in controllers compiled (:mod:`hipsim.control.servo_kernel`), filling ``log``.

    A plant with a compiled kernel (the reduced plant; ``kernel``, its
    ``compiled_kernel()``) runs whole chunks of servo periods in one compiled
    call, and so does a plant whose ``compiled_stepper()`` offers its RK4
    steps compiled (the Pinocchio plant on its ``"compiled"`` route,
    :mod:`~hipsim.control.closed_chain_loop`); another plant with
    ``angle_slots`` steps itself through ``advance``, each period's control
    compiled around it.
    """
    from . import servo_kernel  # imports numba: only when a loop runs compiled

    n = len(t)
    x = np.array(x, dtype=float)
    if isinstance(controller, AugmentedPD):
        feedforward, rows, with_feedforward = controller.feedforward, controller.feedforward_rows(t), True
    else:
        feedforward, rows, with_feedforward = np.zeros((1, 3)), np.zeros(n, dtype=np.int64), False
    control = (
        _read_only(desired.q, float),
        _read_only(desired.qd, float),
        _read_only(controller.kp, float),
        _read_only(controller.kd, float),
        _read_only(feedforward, float),
        _read_only(rows, np.int64),
        with_feedforward,
        float(limit),
    )
    loads = np.ascontiguousarray(loads, dtype=float)
    q, qd, tau, tau_requested, saturated = log
    if kernel is not None:
        for start, stop in _servo_chunks(n, _CHUNK, desc, progress, notify):
            reached = servo_kernel.servo_loop(
                kernel, controller._kernel_params, x, start, stop, *control, loads, float(h), int(substeps), *log
            )
            if reached != stop:
                raise _unstable(t, reached)
        return
    angles, rates, signs = (np.ascontiguousarray(a) for a in plant.angle_slots)
    if x.ndim != 1 or max(angles.max(), rates.max()) >= x.size:  # the compiled control reads x there, unchecked
        raise ArgumentError(
            "initial_state",
            x,
            f"a state of the {getattr(plant, 'name', 'plant')} plant, holding its angles at {angles} and rates at {rates}",
        )
    step, machine = 2 * substeps, reduced_kernel.plain_parameters(controller._kernel_params)
    stepper = plant.compiled_stepper() if hasattr(plant, "compiled_stepper") else None
    if stepper is not None:
        if x.shape != stepper[3].shape:  # the compiled steps index the state by its size, unchecked
            raise ArgumentError("initial_state", x, f"a state of the {plant.name} plant, of shape {stepper[3].shape}")
        from . import closed_chain_loop  # imports Pinocchio: only for a plant that offers a compiled RK4

        for start, stop in _servo_chunks(n, _CHUNK, desc, progress, notify):
            reached = closed_chain_loop.stepped_loop(
                stepper, x, angles, rates, signs, machine, start, stop, *control, loads, float(h), int(substeps), *log
            )
            if reached != stop:
                raise _unstable(t, reached)
        return
    for start, stop in _servo_chunks(n, _CHUNK, desc, progress, notify):
        for k in range(start, stop):
            if not servo_kernel.control_period(
                x, angles, rates, signs, machine, k, *control, q, qd, tau, tau_requested, saturated
            ):
                raise _unstable(t, k)
            x = plant.advance(t[k], x, tau[k], loads[step * k : step * (k + 1) + 1], h, substeps)


def _read_only(values, dtype) -> np.ndarray:
    """A C-contiguous read-only view of ``values`` (a copy only where the dtype or layout differs).

    numba compiles a function once per argument type, and a writable and a
    read-only array are two types: gains a controller was given and gains read
    from a parameter file would compile the whole servo loop twice (seconds
    of a machine's first run each) for the same arithmetic.
    """
    view = np.ascontiguousarray(values, dtype=dtype).view()
    view.flags.writeable = False
    return view


def _servo_chunks(n: int, size: int, desc: str, progress: bool, notify: Callable[[str], None] | None):
    """The servo periods 0 … n−1 as (start, stop) chunks of ``size``, the first period alone, with a progress bar from the second on.

    A process's first period calls the numba kernels for the first time, which
    compiles them on a machine's first run (some 15 s): a bar that timed it
    would promise hours. That period is announced as compiling once it takes
    more than a second, and the bar's rate starts after it.
    """
    with note_if_slow(f"{desc}: compiling (first run only) ...", notify):
        yield 0, 1
    with tqdm(desc=desc, unit="servo", initial=1, total=n, disable=not progress, delay=2.0, leave=False) as bar:
        for start in range(1, n, size):
            stop = min(start + size, n)
            yield start, stop
            bar.update(stop - start)


def parse_mismatch(text: str) -> dict[str, float]:
    """``"friction=+20%,masses=-10%"`` → ``{"friction": 0.2, "masses": -0.1}``.

    Raises:
        HipsimError: naming the part that is not ``friction`` or ``masses`` with a percentage.
    """
    out: dict[str, float] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        match = re.fullmatch(r"(friction|masses)\s*=\s*([+-]?\d+(?:\.\d*)?)\s*%", part)
        if not match:
            raise ArgumentError("mismatch", part, "friction=+20% or masses=-10%")
        if match.group(1) in out:
            raise ArgumentError("mismatch", text, f"{match.group(1)} given once")
        out[match.group(1)] = float(match.group(2)) / 100.0
    return out


def apply_mismatch(params: Parameters, friction: float = 0.0, masses: float = 0.0) -> Parameters:
    """A machine whose friction and masses are off by the given fractions (the plant, when the controller has ``params``).

    Args:
        params: the nominal machine.
        friction: relative change of every friction coefficient, e.g. 0.2 for +20 %.
        masses: relative change of every mass and inertia (platforms, levers,
            sliders, screws), e.g. -0.1 for −10 %.
    """
    if friction <= -1 or masses <= -1:
        raise ArgumentError(
            "mismatch",
            {"friction": friction, "masses": masses},
            "fractions above -1 (a mismatch of -100 % or less leaves nothing)",
        )
    f, m = 1.0 + friction, 1.0 + masses
    fr = params.friction
    return params.replace(
        **{name: getattr(fr, name) * f for name in FRICTION_COEFFICIENTS},
        platform_mass=params.platform_mass * m,
        platform_inertia=params.platform_inertia * m,
        lever_mass=params.lever_mass * m,
        lever_inertia=params.lever_inertia * m,
        slider_mass=params.slider_mass * m,
        screw_inertia=params.screw_inertia * m,
    )

"""MuJoCo's forward dynamics as a plant of the servo loop (spec §8).

:class:`MujocoPlant` steps the MJCF of :mod:`hipsim.mujoco_engine.mjcf` with
``mj_step`` and MuJoCo's own integrator: state x = [qpos, qvel] of the 21
joints, the motor torques as the actuators' controls (N·m, gear 2π/p), the
six closures as MuJoCo's soft ``connect`` equalities.

Friction. The friction of spec §4.3 / §7.3 is a state- and load-dependent
force, which MJCF cannot declare (a joint's ``frictionloss`` is a per-DoF
constant). The plant supplies it as MuJoCo's passive force through the
passive-force callback (``mjcb_passive``), so that MuJoCo evaluates it at
every evaluation of the dynamics, every stage of RK4 included, at the
stage's state and the load F_e at the stage's time. Holding it over a step
instead (``qfrc_applied`` set before ``mj_step``, the usual way) makes the
step first-order in friction: at the default settings the augmented PD's
tracking then differs from the Pinocchio plant's by 6.8e-4° rather than
2e-6°. The callback is process-wide in MuJoCo: the plant installs it only
while it steps and restores whatever was there before. The law is
:class:`hipsim.mujoco_engine.friction.FrictionForces`, the inverse dynamics'
own.

Closures. Unlike the Pinocchio plant, whose closures are rigid (a KKT solve
plus a weak Baumgarte term), MuJoCo's are soft: the constraint force is that
of a critically damped spring-damper pulling each gap back with the time
constant of ``solref``, regularised by the impedance of ``solimp``. A gap
therefore opens in proportion to what the closures carry;
:meth:`MujocoPlant.gap_history` reports it at every servo instant of the
run. The README's MuJoCo section gives the gaps and the tracking difference
to the Pinocchio plant measured at the settings offered.
"""

from __future__ import annotations

import math

import numpy as np

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ._dependency import mujoco
from .friction import FrictionForces
from .machine import MujocoMachine
from .mjcf import MjcfSettings, default_solref
from .model import load_model
from .trajectory import kinematics

__all__ = ["MujocoPlant"]


class MujocoPlant:
    """Forward dynamics of the MuJoCo model; state x = [qpos, qvel] (42 numbers).

    Args:
        params: the plant's machine (SI).
        integrator: MuJoCo's integrator, "RK4" (default), "Euler",
            "implicitfast" or "implicit".
        solref: the closures' (time constant [s], damping ratio); None for
            :func:`~hipsim.mujoco_engine.mjcf.default_solref` at the step, re-derived whenever the step changes.
        solimp: the closures' impedance; None for the MJCF default (0.9999, 0.9999, 0.001, 0.5, 2).
        machine: ``load_model(params)`` for these very params, to skip building it.

    The integration step is the one :func:`~hipsim.control.simulation.simulate`
    passes (``params.control.integration_step``, rounded to fill a servo
    period); :meth:`derivative` gives MuJoCo's acceleration at a state for the
    generic RK4 loop, :meth:`advance` steps MuJoCo itself. Not thread-safe.
    """

    name = "mujoco"

    def __init__(
        self,
        params: Parameters,
        integrator: str = "RK4",
        solref: tuple[float, float] | None = None,
        solimp: tuple[float, ...] | None = None,
        machine: MujocoMachine | None = None,
    ):
        self.params = params
        defaults = MjcfSettings()
        self.settings = MjcfSettings(
            timestep=params.control.integration_step,
            integrator=integrator,
            solref=solref,
            solimp=defaults.solimp if solimp is None else tuple(solimp),
        )
        if machine is not None and machine.params is not params:
            raise ArgumentError("machine", machine, "load_model(params) of the same params object")
        self.machine = load_model(params, self.settings) if machine is None else machine
        self.model, self.data = self.machine.model, mujoco.MjData(self.machine.model)
        self._apply_settings(self.settings.timestep)
        self.nq = self.model.nq
        self._angles = self.machine.platform_dof[0].copy()
        self._rates = self._angles + self.nq
        self._signs = np.asarray(params.angle_signs, dtype=float).copy()
        self._rows = 3 * self.model.neq
        self._sites = [(int(self.model.eq_obj1id[k]), int(self.model.eq_obj2id[k])) for k in range(self.model.neq)]
        self._friction = FrictionForces(self.machine)
        self._lifted = self.machine.stackup_dof
        self._loads, self._t0, self._half = [0.0, 0.0], 0.0, 1.0
        self._gap_times: list[float] = []
        self._gaps: list[float] = []

    def _apply_settings(self, step: float) -> None:
        """Integrator, step and closure softness into the compiled model (the step may change per run)."""
        model = self.model
        model.opt.timestep = step
        model.opt.integrator = {
            "Euler": mujoco.mjtIntegrator.mjINT_EULER,
            "RK4": mujoco.mjtIntegrator.mjINT_RK4,
            "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
            "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
        }[self.settings.integrator]
        solref = (
            self.settings.solref if self.settings.solref is not None else default_solref(step, self.settings.integrator)
        )
        model.eq_solref[:] = solref
        model.eq_solimp[:] = self.settings.solimp
        # The servo loop limits the torques (and counts it); the MJCF's ctrlrange must not clamp them again.
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CLAMPCTRL
        self._step = step

    # -- the Plant protocol -------------------------------------------------

    def initial_state(self, desired: Trajectory) -> np.ndarray:
        """The closed state at desired's first sample (closure gap ≤ 1e-13 m, J_c v = 0); clears the gap history."""
        kin = kinematics(self.machine, desired.slice(slice(0, 1)))
        self._gap_times, self._gaps = [], []
        return np.concatenate([kin.q[0], kin.v[0]])

    def derivative(self, t: float, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """[qvel, qacc] with MuJoCo's (soft-constrained) forward dynamics at x, under motor torques tau [N·m] and load Fe [N]."""
        model, data = self.model, self.data
        self._load(x, tau)
        self._loads, self._t0, self._half = [float(Fe), float(Fe)], t, 1.0
        data.time = t
        previous = mujoco.get_mjcb_passive()
        mujoco.set_mjcb_passive(self._passive)
        try:
            mujoco.mj_forward(model, data)
        finally:
            mujoco.set_mjcb_passive(previous)
        return np.concatenate([data.qvel, data.qacc])

    def advance(
        self, t: float, x: np.ndarray, tau: np.ndarray, loads: np.ndarray, h: float, substeps: int
    ) -> np.ndarray:
        """The state after ``substeps`` MuJoCo steps of h [s] from x at time t [s] under motor torques tau [N·m].

        ``loads``: F_e in [N] at every half step, (2·substeps + 1,); friction
        reads it at each evaluation's time (linear between the half steps).
        """
        if h != self._step:
            self._apply_settings(h)
        model, data = self.model, self.data
        self._load(x, tau)
        data.time = t
        self._loads, self._t0, self._half = [float(f) for f in loads], t, h / 2.0
        previous = mujoco.get_mjcb_passive()
        mujoco.set_mjcb_passive(self._passive)
        try:
            mujoco.mj_step(model, data, substeps)
        finally:
            mujoco.set_mjcb_passive(previous)
        x = np.concatenate([data.qpos, data.qvel])
        self._gap_times.append(t + substeps * h)
        self._gaps.append(self._gap(x))
        return x

    def _passive(self, model, data) -> None:
        """mjcb_passive: add the friction forces (and, with a stack-up, the load on m_1's slide) at the evaluation's state and time."""
        loads = self._loads
        u = (data.time - self._t0) / self._half
        k = min(max(int(u), 0), len(loads) - 2)
        Fe = loads[k] + (u - k) * (loads[k + 1] - loads[k])
        self._friction.add(data, Fe, data.qfrc_passive)
        if self._lifted is not None:  # with a stack-up the load presses m_1's centre down its spline's slide
            data.qfrc_passive[self._lifted] -= Fe

    def angles(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gait angles [α, β, γ] in [rad] and their rates in [rad/s], from platform 1's spherical joint."""
        return self._signs * x[self._angles], self._signs * x[self._rates]

    def readings(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The carriages' readings L_1i [m] and rates [m/s], (3,), and both platforms' gait angles [rad] and rates [rad/s], (2, 3)."""
        nq, platforms, sliders = self.nq, self.machine.platform_dof, self.machine.slider_dof
        return x[sliders].copy(), x[sliders + nq].copy(), self._signs * x[platforms], self._signs * x[platforms + nq]

    # -- diagnostics --------------------------------------------------------

    def gap_history(self) -> tuple[np.ndarray, np.ndarray]:
        """The closure gap along the run since :meth:`initial_state`: the times in [s] at the end of each
        :meth:`advance` (the servo instants after the first) and the largest |p₁ − p₂| in [m] there."""
        return np.array(self._gap_times), np.array(self._gaps)

    def _gap(self, x: np.ndarray) -> float:
        """Largest closure gap |p₁ − p₂| in [m] at state x (positions only)."""
        data = self.data
        data.qpos[:] = x[: self.nq]
        mujoco.mj_kinematics(self.model, data)
        sites = data.site_xpos.tolist()
        return max(math.dist(sites[a], sites[b]) for a, b in self._sites)

    def closure_residual(self, x: np.ndarray) -> tuple[float, float]:
        """Largest closure gap |p₁ − p₂| in [m] and closure velocity |J_c v| in [m/s] at state x."""
        self._load(np.asarray(x, dtype=float), np.zeros(3))
        mujoco.mj_fwdPosition(self.model, self.data)
        rows, nv = self._rows, self.model.nv
        gaps = self.data.efc_pos[:rows].reshape(-1, 3)
        J = self.data.efc_J.reshape(self.data.nefc, nv)[:rows]
        rates = (J @ self.data.qvel).reshape(-1, 3)
        return float(np.linalg.norm(gaps, axis=1).max()), float(np.linalg.norm(rates, axis=1).max())

    def _load(self, x: np.ndarray, tau: np.ndarray) -> None:
        data, nq = self.data, self.nq
        data.qpos[:] = x[:nq]
        data.qvel[:] = x[nq:]
        data.ctrl[:] = tau

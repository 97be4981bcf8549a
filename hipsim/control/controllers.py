"""Trajectory-tracking controllers of the servo loop (spec §8).

A controller is any callable ``controller(t, state, desired) -> tau`` that
takes the time t in [s], the measured platform state and the desired one
(each a :class:`Sample`), and returns the three motor torques in [N·m]. The
two of the spec:

- :class:`WorkspacePD`: a platform moment M = K_p·Δq + K_d·Δq̇ from the
  orientation error, mapped to actuator forces through the Jacobian transpose,
  F = J⁻ᵀ·M, then to motor torques (p/2π)·F.
- :class:`AugmentedPD`: the same plus the model's inverse-dynamics torques
  along the desired trajectory, friction compensation included. The
  feed-forward is computed for the whole run in one vectorised call, at the
  middle of each servo period, which compensates the half-period delay of the
  zero-order hold that applies it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..analytic import kernel as reduced_kernel
from ..analytic.inverse_kinematics import kinematics
from ..analytic.kernel import floats
from ..analytic.virtual_work import inverse_dynamics
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory

__all__ = ["AugmentedPD", "Controller", "Sample", "WorkspacePD", "feedforward_torques"]


@dataclass(frozen=True)
class Sample:
    """A platform state at one instant.

    Attributes:
        q: orientation [α, β, γ] in [rad], shape (3,).
        qd: its rate in [rad/s], shape (3,).
        qdd: its second derivative in [rad/s²], shape (3,), when known.
        Fe: load in [N], when known.
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray | None = None
    Fe: float = 0.0


class Controller(Protocol):
    """What :func:`hipsim.control.simulation.simulate` calls once per servo period."""

    def __call__(self, t: float, state: Sample, desired: Sample) -> np.ndarray: ...


class WorkspacePD:
    """Workspace PD: τ = (p/2π)·J(q)⁻ᵀ·(K_p·Δq + K_d·Δq̇).

    Args:
        params: the controller's model of the machine (J, lead, gains from
            ``params.control`` unless given).
        kp: K_p per angle in [N·m/rad], shape (3,).
        kd: K_d per angle in [N·m·s/rad], shape (3,).
    """

    def __init__(self, params: Parameters, kp=None, kd=None):
        self.params = params
        self.kp = _gains(params.control.kp if kp is None else kp, "kp")
        self.kd = _gains(params.control.kd if kd is None else kd, "kd")
        self._kernel_params = reduced_kernel.kernel_parameters(params)

    def __call__(self, t: float, state: Sample, desired: Sample) -> np.ndarray:
        # Called once per servo period on one state: the compiled law of
        # hipsim.reduced_kernel, J in closed form, no NumPy overhead.
        q, qd = floats(state.q, (3,), "state.q"), floats(state.qd, (3,), "state.qd")
        q_desired, qd_desired = floats(desired.q, (3,), "desired.q"), floats(desired.qd, (3,), "desired.qd")
        return reduced_kernel.workspace_pd(self._kernel_params, q, qd, q_desired, qd_desired, self.kp, self.kd)


def _gains(value, name: str) -> np.ndarray:
    """Gains per angle, (3,); one number applies to all three."""
    gains = floats(value, np.shape(value), name)
    return np.full(3, float(gains)) if gains.ndim == 0 else floats(gains, (3,), name)


def feedforward_torques(params: Parameters, desired: Trajectory) -> np.ndarray:
    """Inverse-dynamics motor torques along a desired trajectory, friction included, in [N·m], (N, 3)."""
    return inverse_dynamics(params, kinematics(params, desired), desired.Fe).total


class AugmentedPD(WorkspacePD):
    """Workspace PD plus inverse-dynamics feed-forward along the desired trajectory.

    Args:
        params: the controller's model of the machine (its masses and friction
            may differ from the plant's).
        desired_at: the desired trajectory as a function of time (e.g.
            :func:`hipsim.motion.trajectories.iso14242_at`).
        servo_rate: servo rate in [Hz].
        duration: length of the run in [s].
        kp, kd: gains as in :class:`WorkspacePD`.
    """

    def __init__(
        self,
        params: Parameters,
        desired_at: Callable[[np.ndarray], Trajectory],
        servo_rate: float,
        duration: float,
        kp=None,
        kd=None,
    ):
        super().__init__(params, kp, kd)
        self.servo_rate = servo_rate
        n = int(round(duration * servo_rate))
        self.feedforward = feedforward_torques(params, desired_at((np.arange(n) + 0.5) / servo_rate))

    def __call__(self, t: float, state: Sample, desired: Sample) -> np.ndarray:
        return self.feedforward[int(self.feedforward_rows(t))] + super().__call__(t, state, desired)

    def feedforward_rows(self, t):
        """The row of :attr:`feedforward` that applies at time(s) t in [s]: the servo period's, the last one after the end."""
        return np.minimum(np.rint(np.asarray(t) * self.servo_rate).astype(np.int64), len(self.feedforward) - 1)

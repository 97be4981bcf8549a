"""An exact plant of a per-chain machine from the analytic dynamics, the intermediate chain's stack-up included.

The Pinocchio and MuJoCo plants are built from the per-chain URDF tree, which
does not carry the stack-up yet (``[geometry] spline_seat_mm`` is refused
there); the reduced plant has one state for both platforms. This plant is the
analytic model run forwards: its state is the carriages x = [L, L̇] (3 + 3), and
L̈ = M⁻¹·(τ − b) with M and b from the per-chain inverse dynamics
(:func:`hipsim.analytic.chain_dynamics.chain_forward_dynamics`), both platforms
following the carriages through their own chains (m_1 lifted by the seat).
Exact and slow (tens of milliseconds a step, NumPy throughout): a plant for
checks and studies of a stacked machine in :func:`hipsim.control.machine_loop.run_machine`,
not for long runs.
"""

from __future__ import annotations

import numpy as np

from ..analytic.chain_dynamics import carriage_motion, chain_forward_dynamics
from ..analytic.stations import platform_motion
from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory

__all__ = ["ChainPlant"]


class ChainPlant:
    """The analytic per-chain machine as a plant: state [L (3) in [m], L̇ (3) in [m/s]].

    Args:
        params: the machine as built (with ``[geometry]``; its ``control`` is the platform the first state puts at
            the desired motion).
        lever_spin: give the levers the spin their universal joints impose (as the reduced plant, default True).
    """

    name = "analytic per-chain"

    def __init__(self, params: Parameters, lever_spin: bool = True):
        if params.geometry is None:
            raise ArgumentError(
                "params", "the drawing", "a per-chain machine ([geometry]); the drawing's is ReducedPlant"
            )
        self.params, self.lever_spin = params, bool(lever_spin)
        self._guess = np.zeros(3)  # both platforms' attitude near the state's, for Newton

    def initial_state(self, desired: Trajectory) -> np.ndarray:
        """The carriages that put the controlled platform at the first sample of ``desired``, and their rates."""
        assert self.params.geometry is not None
        first = desired.slice(slice(0, 1))
        L, Ld, _ = platform_motion(self.params, first.q, first.qd, first.qdd, self.params.geometry.control)
        self._guess = np.array(first.q[0], dtype=float)
        return np.concatenate([L[0], Ld[0]])

    def derivative(self, t: float, x: np.ndarray, tau: np.ndarray, Fe: float) -> np.ndarray:
        """[L̇, L̈] under motor torques tau [N·m], (3,), and load Fe [N]."""
        Ldd = chain_forward_dynamics(self.params, x[:3], x[3:], tau, Fe, self._guess, self.lever_spin)
        return np.concatenate([x[3:], Ldd])

    def readings(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Carriage readings [m] and rates [m/s], (3,); both platforms' gait angles [rad] and rates [rad/s], (2, 3)."""
        motion = carriage_motion(self.params, np.zeros(1), x[None, :3], x[None, 3:], np.zeros((1, 3)), self._guess)
        signs = self.params.angle_signs
        q = np.array([kin.q[0] * signs for kin in motion.platforms])
        qd = np.array([kin.qd[0] * signs for kin in motion.platforms])
        self._guess = q[0]
        return x[:3].copy(), x[3:].copy(), q, qd

    def angles(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The controlled platform's gait angles [rad] and rates [rad/s] in state x."""
        assert self.params.geometry is not None
        _, _, q, qd = self.readings(x)
        c = self.params.geometry.control - 1
        return q[c], qd[c]

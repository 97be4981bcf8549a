"""Closed-chain kinematics and inverse dynamics of the MuJoCo model along a trajectory, in one pass.

Everything here reads MuJoCo: joint anchors from ``mj_kinematics``, the
closure from :mod:`~hipsim.mujoco_engine.closure`, the singularity measure
from K⁻¹ and the platform's angular Jacobian (``mj_jacBody``), the dynamics
from :mod:`~hipsim.mujoco_engine.dynamics`. Nothing comes from the Pinocchio
model or the analytic formulas, so that the three engines check each other
(the central chain's friction moment reported beside the torques is the law of
:mod:`hipsim.physics.friction` at the platforms' motion).
"""

from __future__ import annotations

import numpy as np

from ..exceptions import ClosureError, PoseError
from ..motion.trajectories import trajectory_arrays
from ..physics.friction import central_chain_friction
from ..physics.orientation import angular_velocity_map, rotation_matrix
from ._dependency import mujoco
from .closure import MujocoKinematics, _Closer, _initial_guess, _inverse
from .dynamics import _InverseDynamics
from .machine import MujocoMachine

__all__ = ["kinematics", "trajectory_dynamics"]


def kinematics(machine: MujocoMachine, traj, *, tol: float = 1e-13, max_iter: int = 30) -> MujocoKinematics:
    """Close the MuJoCo model's chain along a platform trajectory.

    Args:
        machine: the model from :func:`load_model`.
        traj: a Trajectory-like object: t (N,) in [s]; q, qd, qdd (N, 3) [α, β, γ]
            in [rad], [rad/s], [rad/s²] (the parameter set's angle_signs applied here).
        tol: closure gap accepted in [m] (largest component of p₁ − p₂).
        max_iter: Gauss–Newton iterations allowed per sample.

    Returns:
        The closed configurations, velocities and accelerations, slider motion and singularity measure.

    Raises:
        PoseError: at the first sample whose pose is out of reach or singular.
    """
    return _close(machine, traj, tol, max_iter, Fe=None)[0]


def _close(machine: MujocoMachine, traj, tol: float, max_iter: int, Fe):
    t, q_in, qd_in, qdd_in = trajectory_arrays(traj)
    signs = machine.params.angle_signs
    angles, rates, accels = q_in * signs, qd_in * signs, qdd_in * signs
    model, data = machine.model, machine.data
    n, nv = len(t), model.nv
    Q, V, A = np.empty((n, nv)), np.empty((n, nv)), np.empty((n, nv))
    L = np.empty((n, 2, 3))
    cond_inv, residual = np.empty(n), np.empty(n)
    closer = _Closer(machine, tol, max_iter)
    dynamics = _InverseDynamics(machine, n, Fe) if Fe is not None else None
    jacr = np.zeros((3, nv))
    q = _initial_guess(machine)
    if closer.per_chain:  # the follower starts at the controlled platform's attitude, a fraction of a degree off
        q[closer.follower] = angles[0]
    # Per chain: the carriage readings, L_2i = L_1i − (h_1 − h_2) (hipsim.analytic.chain_dynamics); else b_ji's heights.
    dh = np.array([0.0, machine.params.heights[0] - machine.params.heights[1]])[:, None]
    c = closer.controlled
    for k in range(n):
        if k > 1:
            h = t[k] - t[k - 1]
            q = Q[k - 1] + h * (
                V[k - 1] + h * (0.5 * A[k - 1] + h / 6.0 * (A[k - 1] - A[k - 2]) / (t[k - 1] - t[k - 2]))
            )
        elif k == 1:
            h = t[1] - t[0]
            q = Q[0] + h * (V[0] + 0.5 * h * A[0])
        try:
            q, e, J = closer.close(q, angles[k])
            if np.min(data.xmat[machine.lever_body.ravel(), 8]) <= 1e-6:
                raise ClosureError("a lever is horizontal or points down (singular pose, spec §3)")
            v, a = closer.rates(J, rates[k], accels[k])
        except (ClosureError, np.linalg.LinAlgError) as error:
            raise PoseError(str(error), float(t[k]), k, source=getattr(traj, "name", None)) from None
        Q[k], V[k], A[k] = q, v, a
        residual[k] = np.linalg.norm(e.reshape(-1, 3), axis=1).max()
        L[k] = q[machine.slider_dof] - dh if closer.per_chain else data.xanchor[machine.ujoint_anchor][:, :, 2]
        # J = ∂L̇/∂ω = (∂L̇/∂q̇)·T⁻¹, both from MuJoCo: K⁻¹ gives the first, the held platform's angular Jacobian T.
        mujoco.mj_jacBody(model, data, None, jacr, machine.platform_body[c])
        T = jacr[:, machine.platform_dof[c]]
        assert closer.K_inv is not None  # closer.rates() above has set it
        G = closer.K_inv[machine.slider_dof, :3]
        singular = np.linalg.svd(G @ _inverse(T), compute_uv=False)
        cond_inv[k] = singular[-1] / singular[0]
        if dynamics is not None:
            dynamics.add(k, q, v, a, J)
    sliders = machine.slider_dof
    kin = MujocoKinematics(
        t=t,
        q=Q,
        v=V,
        a=A,
        L=L,
        Ld=np.repeat(V[:, None, sliders], 2, axis=1),
        Ldd=np.repeat(A[:, None, sliders], 2, axis=1),
        cond_inv=cond_inv,
        residual=residual,
    )
    if dynamics is None:
        return kin, None
    # The central chain's friction moment, for the summary: the law of spec §4.3 at the platforms' motion.
    omega = np.einsum("nab,nb->na", angular_velocity_map(angles), rates)
    moment = central_chain_friction(
        machine.params.friction,
        machine.params.platform_mass * machine.params.gravity,
        omega,
        dynamics.Fe,
        rotation_matrix(angles),
    )
    dynamics.friction_moment = np.linalg.norm(moment, axis=-1)
    return kin, dynamics.result(kin)


def trajectory_dynamics(machine: MujocoMachine, traj, *, tol: float = 1e-13, max_iter: int = 30):
    """:func:`kinematics` and :func:`inverse_dynamics` in one pass, with the trajectory's own load."""
    return _close(machine, traj, tol, max_iter, Fe=traj.Fe)

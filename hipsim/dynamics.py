"""Analytic inverse dynamics with joint friction (spec §4), vectorised over samples.

The motor torques follow from the principle of virtual power: the power of the
motors plus that of every applied and inertial (D'Alembert) wrench is zero for
any platform angular velocity ω. All body velocities are linear in ω, so each
wrench maps to a generalised moment in ω-space, and the motor torques are

    τ = τ_L + τ_f − (p/2π)·Σ_j [ J⁻ᵀ·Q_j + F_L,j − F_Lf,j ]      (spec §4.2)

with Q_j the generalised moment of platform j, its three levers and the
friction moments. Instead of forming the lever Jacobians J_v, J_ω of spec
§4.2, a lever wrench (force F at its centre, moment M) is mapped through
their transposes in closed form:

    J_vᵀF + J_ωᵀM = r × f_a + Jᵀ·f_b,z,   f_a = F/2 + (M × e)/l,  f_b = F/2 − (M × e)/l,

that is, the lever wrench is replaced by two forces at its ends: f_a acts on
the platform at a (moment r × f_a about the fixed centre) and the vertical part
of f_b acts on the slider. ``tests/test_dynamics.py`` checks this against the
explicit Jacobians of :func:`hipsim.kinematics.lever_jacobians`.

Both platforms have the same orientation and their legs the same lever
directions, so every platform, lever and slider term is the same for j = 1
and j = 2 and is computed once and counted twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .kinematics import Kinematics, _cross, _dot, lever_frames, lever_rotation, spin_transpose
from .parameters import Parameters

__all__ = [
    "Torques",
    "central_friction_moment",
    "inverse_dynamics",
    "mechanical_energy",
    "smooth_sign",
]

_Z = np.array([0.0, 0.0, 1.0])


def smooth_sign(w: np.ndarray, epsilon: float, vector: bool = False) -> np.ndarray:
    """ŝ(w) = w/√(|w|² + ε²) (spec §7.3).

    Args:
        w: speeds in [rad/s], any shape; with ``vector`` the last axis is a 3-vector.
        epsilon: ε in [rad/s]; below it the Coulomb friction fades linearly to zero.
        vector: True to take |w| over the last axis.
    """
    norm2 = np.sum(w**2, axis=-1, keepdims=True) if vector else w**2
    return w / np.sqrt(norm2 + epsilon**2)


def central_friction_moment(params: Parameters, omega: np.ndarray, Fe: np.ndarray) -> np.ndarray:
    """Friction moment τ_mf of one platform's central chain (hip joint + thrust bearing), spec §4.3.

    Args:
        params: the machine.
        omega: platform angular velocity in [rad/s], (N, 3).
        Fe: load magnitude in [N], (N,), pushing down like the platform's weight.

    Returns:
        τ_mf in [N·m], (N, 3), along ŝ(ω) (it resists the platform's rotation).
    """
    f = params.friction
    magnitude = f.hip_radius * f.hip_mu * np.abs(Fe) + f.thrust_radius * f.thrust_mu * np.abs(
        Fe + params.platform_mass * params.gravity
    )
    return smooth_sign(omega, f.epsilon, vector=True) * magnitude[:, None]


@dataclass(frozen=True, eq=False)
class Torques:
    """Motor torques and their parts along a trajectory (spec §4.4), all (N, 3) per motor.

    Attributes:
        tau: total motor torque in [N·m]; the sum of the five parts below.
        tau_m: moving platforms' inertia (both platforms) in [N·m].
        tau_l: levers' gravity and inertia in [N·m].
        tau_s: sliders' gravity and inertia in [N·m].
        tau_L: lead screws' inertia in [N·m].
        tau_f: all friction in [N·m].
        motor_speed: θ̇_i = 2π·L̇_i/p in [rad/s].
        friction_moment: magnitude of each platform's central-chain friction moment in [N·m], (N,).
        friction_power: power lost in all friction in [W], (N,), ≥ 0.
    """

    tau: np.ndarray
    tau_m: np.ndarray
    tau_l: np.ndarray
    tau_s: np.ndarray
    tau_L: np.ndarray
    tau_f: np.ndarray
    motor_speed: np.ndarray
    friction_moment: np.ndarray
    friction_power: np.ndarray

    #: Names of the five parts, in the order of spec §4.4.
    PARTS = ("tau_m", "tau_l", "tau_s", "tau_L", "tau_f")


def _to_body(frames: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Rᵀ·w for body frames R of shape (..., 3, 3) and vectors w of shape (..., 3)."""
    return np.einsum("...ba,...b->...a", frames, w)


def _euler_moment(frames: np.ndarray, inertia: np.ndarray, w: np.ndarray, w_dot: np.ndarray) -> np.ndarray:
    """The D'Alembert moment −I_w·ω̇ − ω × I_w·ω in world axes, I_w = R·I·Rᵀ.

    Evaluated in body axes, where the inertia is constant: R·(−I·Rᵀω̇ − Rᵀω × I·Rᵀω).
    """
    w_body = _to_body(frames, w)
    moment_body = -(_to_body(frames, w_dot) @ inertia.T) - _cross(w_body, w_body @ inertia.T)
    return np.einsum("...ab,...b->...a", frames, moment_body)


def _rotational_energy(frames: np.ndarray, inertia: np.ndarray, w: np.ndarray) -> np.ndarray:
    """½·ωᵀ·I_w·ω."""
    w_body = _to_body(frames, w)
    return 0.5 * _dot(w_body, w_body @ inertia.T)


def inverse_dynamics(params: Parameters, kin: Kinematics, Fe: np.ndarray, lever_spin: bool = False) -> Torques:
    """Motor torques of the three linear modules and their parts (spec §4).

    Args:
        params: the machine.
        kin: kinematics along the trajectory (:func:`hipsim.kinematics.kinematics`).
        Fe: hydraulic load magnitude in [N], (N,).
        lever_spin: False for the spec's lever model (no spin about its axis);
            True to give the levers the spin a universal joint imposes, which
            is what the Pinocchio model does.

    Returns:
        The torques; their parts add up to the total.
    """
    Fe = np.asarray(Fe, dtype=float)
    n_platforms = params.heights.size
    f = params.friction
    l, p = params.lever_length, params.lead
    gravity = np.array([0.0, 0.0, -params.gravity])
    Ldd = kin.Ldd[:, 0]
    Ld = kin.Ld[:, 0]
    motor_speed = 2.0 * math.pi * Ld / p

    # Platforms: the D'Alembert moment about the fixed centre.
    tau_m_j = _euler_moment(kin.R, params.platform_inertia, kin.omega, kin.omega_dot)

    # Levers: gravity and inertia at the centre, mapped to the ends.
    omega_l, omega_l_dot = lever_rotation(params, kin, lever_spin)
    F_l = params.lever_mass * (gravity - kin.a_l[:, 0])
    M_l = _euler_moment(lever_frames(params, kin), params.lever_inertia, omega_l, omega_l_dot)

    # Friction moments: U joint (lever relative to the non-rotating slider) and
    # S joint (lever relative to the platform); the S moment acts back on the platform.
    w_rel_s = omega_l - kin.omega[:, None]
    tau_bf = f.ujoint_coulomb * smooth_sign(omega_l, f.epsilon, True) + f.ujoint_viscous * omega_l
    tau_af = f.sjoint_coulomb * smooth_sign(w_rel_s, f.epsilon, True) + f.sjoint_viscous * w_rel_s
    tau_mf = central_friction_moment(params, kin.omega, Fe)
    M_f = -tau_af - tau_bf

    # Sliders: gravity and inertia along the screw; guide friction.
    F_L = params.slider_mass * (-params.gravity - Ldd)
    F_Lf = f.guide_coulomb * smooth_sign(motor_speed, f.epsilon) + f.guide_viscous * Ld

    def lever_ends(force, moment):
        """Generalised moment of the end forces on the platform, and the slider-axis force."""
        if lever_spin:
            moment = spin_transpose(params, kin, moment)
        m_cross_e = _cross(moment, kin.e) / l
        f_a = 0.5 * force + m_cross_e
        f_b_z = 0.5 * force[..., 2] - m_cross_e[..., 2]
        return np.sum(_cross(kin.r, f_a), axis=1), f_b_z

    Q_l, Fz_l = lever_ends(F_l, M_l)
    Q_lf, Fz_lf = lever_ends(np.zeros_like(M_f), M_f)
    Q_f = Q_lf - tau_mf + np.sum(tau_af, axis=1)

    # One solve of Jᵀ·y = Q for the platform, lever and friction moments together.
    Q = np.stack([tau_m_j, Q_l, Q_f], axis=-1)
    y = np.linalg.solve(np.swapaxes(kin.J, -1, -2), Q)
    scale = -n_platforms * p / (2.0 * math.pi)
    tau_m = scale * y[..., 0]
    tau_l = scale * (y[..., 1] + Fz_l)
    tau_s = scale * F_L
    tau_L = 2.0 * math.pi * params.screw_inertia / p * Ldd
    tau_screw_f = f.screw_coulomb * smooth_sign(motor_speed, f.epsilon) + f.screw_viscous * motor_speed
    tau_f = tau_screw_f + scale * (y[..., 2] + Fz_lf - F_Lf)

    friction_power = (
        np.sum(tau_screw_f * motor_speed, axis=1)
        + n_platforms
        * (
            np.sum(F_Lf * Ld, axis=1)
            + _dot(tau_mf, kin.omega)
            + np.sum(_dot(tau_bf, omega_l) + _dot(tau_af, w_rel_s), axis=1)
        )
    )
    tau = tau_m + tau_l + tau_s + tau_L + tau_f
    return Torques(
        tau=tau, tau_m=tau_m, tau_l=tau_l, tau_s=tau_s, tau_L=tau_L, tau_f=tau_f,
        motor_speed=motor_speed, friction_moment=np.linalg.norm(tau_mf, axis=-1),
        friction_power=friction_power,
    )


def mechanical_energy(params: Parameters, kin: Kinematics, lever_spin: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Kinetic and potential energy of the whole machine, computed from body motions alone.

    Independent of :func:`inverse_dynamics` (no wrenches, no Jacobian
    transposes), so the power balance motor power = dE/dt + friction power
    checks the torques.

    Args:
        params: the machine.
        kin: kinematics along the trajectory.
        lever_spin: as in :func:`inverse_dynamics`.

    Returns:
        Kinetic and potential energy in [J], each (N,). Potential energy is
        m·g·z of the levers and sliders (the platform centres do not move).
    """
    n_platforms = params.heights.size
    kinetic_m = _rotational_energy(kin.R, params.platform_inertia, kin.omega)
    omega_l, _ = lever_rotation(params, kin, lever_spin)
    v_l = kin.v_l[:, 0]
    kinetic_l = 0.5 * params.lever_mass * _dot(v_l, v_l) + _rotational_energy(lever_frames(params, kin), params.lever_inertia, omega_l)
    Ld = kin.Ld[:, 0]
    kinetic_s = 0.5 * params.slider_mass * Ld**2
    kinetic_L = 0.5 * params.screw_inertia * (2.0 * math.pi * Ld / params.lead) ** 2
    kinetic = n_platforms * (kinetic_m + kinetic_l.sum(1) + kinetic_s.sum(1)) + kinetic_L.sum(1)
    lever_height = 0.5 * (kin.a[..., 2] + kin.b[..., 2])
    potential = params.gravity * (params.lever_mass * lever_height.sum((1, 2)) + params.slider_mass * kin.L.sum((1, 2)))
    return kinetic, potential

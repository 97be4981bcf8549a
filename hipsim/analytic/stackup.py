"""The intermediate chain's stack-up in the analytic dynamics: m_1's centre rides Δz(R_2) up and down with m_2.

:func:`hipsim.machine.chains.stackup_lift` gives the lift Δz = ẑᵀ(R_2 − I)·e of m_1's
rotation centre, e the spline shaft's seat in m_2's axes. Its rates follow from
the seat point s = R_2·e turning with m_2:

    ż = ẑ·(ω_2 × s) = g·ω_2,   g = s × ẑ,
    z̈ = ẑ·(ω̇_2 × s + ω_2 × (ω_2 × s)).

m_1's subsystem (its platform and three levers) then moves as on a machine
without the stack-up (its carriages lowered by Δz: the "seen" carriages
L − Δz, L̇ − ż, L̈ − z̈) plus a vertical translation Δz(t) of the whole
subsystem. In virtual work, with G_1 the generalised force of m_1's subsystem
conjugate to its seen carriages (the per-chain model's J_1⁻ᵀ·Q_1 + F_z,1, with
the bodies' real accelerations) and F_1z the subsystem's vertical resultant
(levers' m_l·(g⃗ − a_l)_z, the platform's −m_m·(g + z̈) and the load −F_e, which
now does work), a virtual δL moves m_1's seen carriages by δL − 1·δz and lifts
it by δz = g·J_2⁻¹·δL, so the carriages see

    G = G_1 + J_2⁻ᵀ·g·(F_1z − 1ᵀ·G_1)

(the moment g·(F_1z − 1ᵀG_1) = s × (vertical force) on m_2: the stack's force at
the seat). The friction of the spline's axial slide is not modelled.

With m_1 controlled (``[geometry] control = 1``) its motion is given and m_2's follows from the carriages,
which m_1's lift itself depends on: L − Δz(q_2)·1 = L_1'(q_1) (m_1's seen carriages), L = L_2(q_2). Differentiated
(:func:`follower_rates`), with A = J_2 − 1·gᵀ:

    A·ω_2 = L̇_1' = J_1·ω_1,    A·ω̇_2 = L̈_1' − Φ_2(ω_2) + 1·ẑ·(ω_2 × (ω_2 × s)),

and L̇ = J_2·ω_2, L̈ = J_2·ω̇_2 + Φ_2. A is singular where the stacked machine is (m_2's and the lift's
Jacobians together); its determinant is J_2's times 1 − gᵀJ_2⁻¹1, ~1 − |e|/(50 mm).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..machine.chains import stackup_lift
from ..physics.orientation import rotation_matrix
from .chain_kinematics import chain_accelerations, chain_jacobian
from .inverse_kinematics import Kinematics

__all__ = ["follower_rates", "lift_motion", "lifted_kinematics"]


def lift_motion(
    spline_seat: np.ndarray, p2: np.ndarray, omega2: np.ndarray, omega2_dot: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """m_1's centre lift and its rates from m_2's motion.

    Args:
        spline_seat: the seat e in m_2's axes in [m], (3,).
        p2: m_2's platform angles in [rad], (N, 3).
        omega2: m_2's angular velocity in [rad/s], world frame, (N, 3).
        omega2_dot: its angular acceleration in [rad/s²], (N, 3).

    Returns:
        Δz [m], ż [m/s], z̈ [m/s²] (each (N,)), and g = (R_2·e) × ẑ [m] with ż = g·ω_2, (N, 3).
    """
    s = np.einsum("nij,j->ni", rotation_matrix(p2), np.asarray(spline_seat, dtype=float))
    g = np.cross(s, np.array([0.0, 0.0, 1.0]))
    zd = np.einsum("ni,ni->n", g, omega2)
    zdd = np.cross(omega2_dot, s)[:, 2] + np.cross(omega2, np.cross(omega2, s))[:, 2]
    return stackup_lift(spline_seat, p2), zd, zdd, g


def lifted_kinematics(kin: Kinematics, z: np.ndarray, zd: np.ndarray, zdd: np.ndarray) -> Kinematics:
    """m_1's kinematics computed on its seen carriages, translated up by Δz (N,) [m] with its rates [m/s], [m/s²].

    Points (platform joints, U-joints, slider heights) rise by Δz, the lever centres' velocities and accelerations
    gain ż·ẑ and z̈·ẑ, the carriage rates ż and z̈; angles, angular rates and the Jacobian are unchanged.
    """
    up = np.zeros((len(z), 1, 1, 3))
    up[..., 2] = 1.0
    return dataclasses.replace(
        kin,
        a=kin.a + z[:, None, None, None] * up,
        b=kin.b + z[:, None, None, None] * up,
        L=kin.L + z[:, None, None],
        Ld=kin.Ld + zd[:, None, None],
        Ldd=kin.Ldd + zdd[:, None, None],
        v_l=kin.v_l + zd[:, None, None, None] * up,
        a_l=kin.a_l + zdd[:, None, None, None] * up,
    )


def follower_rates(
    spline_seat: np.ndarray, p2: np.ndarray, r2: np.ndarray, d2: np.ndarray, seen_d: np.ndarray, seen_dd: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """m_2's angular velocity and acceleration when m_1 is controlled and its centre rides on m_2 (module docstring).

    Args:
        spline_seat: the seat e in m_2's axes in [m], (3,).
        p2: m_2's platform angles in [rad], (N, 3).
        r2, d2: m_2's joint and lever vectors at p2 (:func:`hipsim.analytic.chain_kinematics.chain_positions`) in [m].
        seen_d, seen_dd: m_1's seen carriage rates J_1·ω_1 [m/s] and accelerations J_1·ω̇_1 + Φ_1 [m/s²], (N, 3).

    Returns:
        ω_2 [rad/s] and ω̇_2 [rad/s²], world frame, each (N, 3).

    Raises:
        numpy.linalg.LinAlgError: where A = J_2 − 1·gᵀ is singular.
    """
    s = np.einsum("nij,j->ni", rotation_matrix(p2), np.asarray(spline_seat, dtype=float))
    g = np.cross(s, np.array([0.0, 0.0, 1.0]))
    A = chain_jacobian(r2, d2) - g[:, None, :]  # every row minus gᵀ: 1·gᵀ
    omega2 = np.linalg.solve(A, np.asarray(seen_d, dtype=float)[..., None])[..., 0]
    phi2 = chain_accelerations(r2, d2, omega2, np.zeros_like(omega2))
    psi = np.cross(omega2, np.cross(omega2, s))[:, 2]
    omega2_dot = np.linalg.solve(A, (np.asarray(seen_dd, dtype=float) - phi2 + psi[:, None])[..., None])[..., 0]
    return omega2, omega2_dot

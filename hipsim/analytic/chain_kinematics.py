"""Kinematics of one platform of a per-chain machine (:mod:`hipsim.machine.chains`), vectorised over samples.

On a per-chain machine the two platforms hang on the same three carriages but
their chains differ, so each platform has its own inverse kinematics, its own
Jacobian and its own attitude for given carriages. Chain ji of platform j
(:class:`hipsim.machine.chains.Chains`, index j = 0, 1) closes

    |a_ji − b_ji| = l_ji,   a_ji = o_j + R_j·r⁰_ji,   b_ji = c_ji + L_i·ẑ,

with L_i the carriage reading of module i. With g_i = a_ji − c_ji the
carriage reading is L_i = g_i,z − √(l_ji² − g_i,x² − g_i,y²) (the lever below
its platform joint, as in spec §3) and the lever vector d_i = a_ji − b_ji =
(g_i,x, g_i,y, √(…)). Differentiating |d_i|² = l_ji² twice:

    L̇_i = (r_i × d_i)·ω / d_i,z,       L̈_i = (d_i·ä_i + |ḋ_i|²) / d_i,z,

with r_i = R_j·r⁰_ji, ȧ_i = ω × r_i, ä_i = ω̇ × r_i + ω × ȧ_i and ḋ_i = ȧ_i − L̇_i·ẑ:
the formulas of spec §3 with the lever length folded into d.

Here angles are *platform* angles p (after the parameter file's angle signs),
arrays sample-first ((N, 3) per sample, (N, 3, 3) = (sample, leg, xyz) per leg).
:mod:`hipsim.analytic.stations` is the public face in gait angles.
"""

from __future__ import annotations

import numpy as np

from ..machine.chains import Chains
from ..physics.orientation import rotation_matrix_components
from ..physics.vectors import cross_array

__all__ = ["chain_accelerations", "chain_jacobian", "chain_positions", "chain_positions_per_sample"]


def chain_positions(chains: Chains, p: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Carriage readings and lever vectors of platform ``j`` (0 or 1) at platform angles ``p``.

    Args:
        chains: the machine's chains.
        p: platform angles [α, β, γ] in [rad] (after angle signs), (N, 3).
        j: platform index, 0 for m_1, 1 for m_2.

    Returns:
        L: carriage readings in [m], (N, 3), NaN where a lever cannot reach;
        r: platform joint vectors R·r⁰_ji in [m], (N, 3, 3);
        d: lever vectors a_ji − b_ji in [m], (N, 3, 3) (NaN z where out of reach).
    """
    return _positions(chains.platform_points[j], chains.centres[j] - chains.screw_points[j], chains.lever_lengths[j], p)


def chain_positions_per_sample(
    platform_points: np.ndarray, offsets: np.ndarray, lever_lengths: np.ndarray, p: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`chain_positions` with each sample on its own chains (many machines at once, e.g. tolerance draws).

    Args:
        platform_points: each sample's platform joints in platform axes in [m], (N, leg, xyz).
        offsets: each sample's o_j − c_ji (rotation centre minus the U-joint centre at reading 0) in [m], (N, leg, xyz).
        lever_lengths: each sample's lever lengths in [m], (N, leg).
        p: platform angles in [rad] (after angle signs), (N, 3).

    Returns:
        L, r, d as :func:`chain_positions`.
    """
    return _positions(platform_points.T.swapaxes(0, 1), offsets.T.swapaxes(0, 1), lever_lengths.T, p)


def _positions(
    P: np.ndarray, g0: np.ndarray, lever: np.ndarray, p: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`chain_positions` from r⁰ (leg, xyz[, N]), o − c (leg, xyz[, N]) and l (leg[, N]), one machine or one a sample."""
    # Components first inside, (xyz, leg, N), as hipsim.analytic.inverse_kinematics computes: each
    # operation then runs over one contiguous block; the results are the .T views, sample first.
    p = np.asarray(p, dtype=float).T
    R = rotation_matrix_components(np.cos(p), np.sin(p))
    if P.ndim == 2:
        r = np.einsum("im,kmn->kin", P, R)  # not BLAS: see inverse_kinematics._platform_vectors
        d = r + g0.T[:, :, None]  # g = a − c, then d in place
        radicand = lever[:, None] ** 2 - (d[0] ** 2 + d[1] ** 2)
    else:
        r = np.einsum("imn,kmn->kin", P, R)
        d = r + g0.swapaxes(0, 1)
        radicand = lever**2 - (d[0] ** 2 + d[1] ** 2)
    reach = radicand > 0
    with np.errstate(invalid="ignore"):
        dz = np.sqrt(np.where(reach, radicand, np.nan))  # NaN where the lever cannot reach
    L = d[2] - dz
    d[2] = dz
    return L.T, r.T, d.T


def chain_jacobian(r: np.ndarray, d: np.ndarray) -> np.ndarray:
    """J with L̇ = J·ω, rows (r_i × d_i)/d_i,z, (N, 3, 3), from :func:`chain_positions`' r and d."""
    r, d = r.T, d.T  # components first: the arrays chain_positions computed
    with np.errstate(invalid="ignore", divide="ignore"):
        J = cross_array(r, d)
        J /= d[2]
    return J.T


def chain_accelerations(r: np.ndarray, d: np.ndarray, omega: np.ndarray, omega_dot: np.ndarray) -> np.ndarray:
    """L̈ in [m/s²], (N, 3), for angular velocity ω in [rad/s] and acceleration ω̇ in [rad/s²], each (N, 3).

    The velocity terms Φ = L̈ − J·ω̇ are the result with ``omega_dot`` zero.
    """
    r_c, d_c = r.T, d.T  # components first, (xyz, leg, N)
    w, w_dot = np.asarray(omega, dtype=float).T[:, None], np.asarray(omega_dot, dtype=float).T[:, None]
    a_dot = cross_array(w, r_c)
    a_ddot = cross_array(w_dot, r_c)
    a_ddot += cross_array(w, a_dot)
    with np.errstate(invalid="ignore", divide="ignore"):
        J = cross_array(r_c, d_c)
        J /= d_c[2]
        d_dot = a_dot  # ḋ = ȧ − L̇·ẑ, in place
        d_dot[2] -= J[0] * w[0] + J[1] * w[1] + J[2] * w[2]
        Ldd = np.sum(d_c * a_ddot, axis=0) + np.sum(d_dot * d_dot, axis=0)
        Ldd /= d_c[2]
    return Ldd.T

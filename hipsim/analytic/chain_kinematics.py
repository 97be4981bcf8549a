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
from ..physics.orientation import rotation_matrix

__all__ = ["chain_accelerations", "chain_jacobian", "chain_positions"]


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
    R = rotation_matrix(np.asarray(p, dtype=float))
    r = np.einsum("nab,ib->nia", R, chains.platform_points[j])
    g = r + (chains.centres[j] - chains.screw_points[j])
    radicand = chains.lever_lengths[j] ** 2 - (g[..., 0] ** 2 + g[..., 1] ** 2)
    with np.errstate(invalid="ignore"):
        dz = np.where(radicand > 0, np.sqrt(np.where(radicand > 0, radicand, np.nan)), np.nan)
    d = g.copy()
    d[..., 2] = dz
    return g[..., 2] - dz, r, d


def chain_jacobian(r: np.ndarray, d: np.ndarray) -> np.ndarray:
    """J with L̇ = J·ω, rows (r_i × d_i)/d_i,z, (N, 3, 3), from :func:`chain_positions`' r and d."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.cross(r, d) / d[..., 2:3]


def chain_accelerations(r: np.ndarray, d: np.ndarray, omega: np.ndarray, omega_dot: np.ndarray) -> np.ndarray:
    """L̈ in [m/s²], (N, 3), for angular velocity ω in [rad/s] and acceleration ω̇ in [rad/s²], each (N, 3).

    The velocity terms Φ = L̈ − J·ω̇ are the result with ``omega_dot`` zero.
    """
    w = omega[:, None, :]
    a_dot = np.cross(w, r)
    a_ddot = np.cross(omega_dot[:, None, :], r) + np.cross(w, a_dot)
    J = chain_jacobian(r, d)
    d_dot = a_dot
    d_dot[..., 2] -= np.einsum("nik,nk->ni", J, omega)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (np.sum(d * a_ddot, axis=-1) + np.sum(d_dot * d_dot, axis=-1)) / d[..., 2]

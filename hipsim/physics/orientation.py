"""The platforms' orientation (spec §3, §7.1): R = Rz(γ)·Ry(β)·Rx(α), the map ω = T(q)·q̇, and how far a Jacobian is from singular.

Array versions over samples of the laws in :mod:`hipsim.physics.laws`, for
every engine: sample first, xyz last ((N, 3) angles, (N, 3, 3) matrices).
"""

from __future__ import annotations

import numpy as np

from . import laws
from .vectors import stack

__all__ = [
    "angular_velocity_map",
    "angular_velocity_map_rate",
    "inverse_condition_number",
    "inverse_condition_number_components",
    "rotation_matrix",
    "rotation_matrix_components",
]


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R = Rz(γ)·Ry(β)·Rx(α).

    Args:
        q: orientations [α, β, γ] in [rad], shape (N, 3).

    Returns:
        Rotation matrices, shape (N, 3, 3).
    """
    return np.moveaxis(rotation_matrix_components(np.cos(q.T), np.sin(q.T)), -1, 0)


def rotation_matrix_components(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """R of :func:`rotation_matrix`, components-first (3, 3, N), from the cosines and sines of q, each (3, N)."""
    return np.array(laws.rotation(c, s))


#: The unit vectors, whose images under a linear map are its columns.
_UNITS = np.eye(3)


def angular_velocity_map(q: np.ndarray) -> np.ndarray:
    """T(q) with ω = T(q)·q̇ (world frame), shape (N, 3, 3); q in [rad], shape (N, 3)."""
    c, s = np.cos(q.T), np.sin(q.T)
    columns = [stack(laws.t_times(c, s, unit)) for unit in _UNITS]
    return np.moveaxis(np.array(columns), (0, 1), (-1, -2))


def angular_velocity_map_rate(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Ṫ(q, q̇), so that ω̇ = T·q̈ + Ṫ·q̇; q in [rad], qd in [rad/s], shapes (N, 3)."""
    c, s = np.cos(q.T), np.sin(q.T)
    columns = [stack(laws.t_dot_times(c, s, qd.T, unit)) for unit in _UNITS]
    return np.moveaxis(np.array(columns), (0, 1), (-1, -2))


def inverse_condition_number(J: np.ndarray) -> np.ndarray:
    """σ_min/σ_max of 3x3 matrices, shape (..., 3, 3) → (...); NaN where J is NaN.

    The eigenvalues of the symmetric JᵀJ in closed form (the trigonometric
    solution of its characteristic cubic): LAPACK's batched SVD costs a
    hundred times more on 3x3 matrices.
    """
    return inverse_condition_number_components(np.moveaxis(J, (-1, -2), (0, 1)))


def inverse_condition_number_components(J: np.ndarray) -> np.ndarray:
    """:func:`inverse_condition_number` of J given by its rows, components-first (xyz, row, ...)."""

    def gram(k, m):
        """(JᵀJ)_km = Σ_i J_ik·J_im, a sum over the rows."""
        return np.sum(J[k] * J[m], axis=0)

    a00, a11, a22, a01, a02, a12 = gram(0, 0), gram(1, 1), gram(2, 2), gram(0, 1), gram(0, 2), gram(1, 2)
    trace = a00 + a11 + a22
    mean = trace / 3.0
    off = a01**2 + a02**2 + a12**2
    spread = np.sqrt(((a00 - mean) ** 2 + (a11 - mean) ** 2 + (a22 - mean) ** 2 + 2.0 * off) / 6.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        # B = (JᵀJ − mean·I)/spread has the eigenvalues 2·cos(φ + 2πk/3), cos 3φ = det(B)/2.
        b00, b11, b22 = (a00 - mean) / spread, (a11 - mean) / spread, (a22 - mean) / spread
        b01, b02, b12 = a01 / spread, a02 / spread, a12 / spread
        det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02)
        phi = np.arccos(np.clip(det / 2.0, -1.0, 1.0)) / 3.0
        largest = mean + 2.0 * spread * np.cos(phi)
        smallest = mean + 2.0 * spread * np.cos(phi + 2.0 * np.pi / 3.0)
        ratio = np.sqrt(np.maximum(smallest, 0.0) / largest)
    # An isotropic J (spread 0) has all singular values equal.
    return np.where(spread > 1e-300, ratio, np.where(np.isnan(trace), np.nan, 1.0))

"""The friction laws over arrays of samples (spec §4.3, §7.3), for every engine's vectorised code.

The laws themselves, one state or whole arrays component by component, are in
:mod:`hipsim.physics.laws`; these functions give them the array layout the
engines use (sample first, xyz last) and the checks of their arguments.
"""

from __future__ import annotations

import numpy as np

from ..exceptions import ArgumentError
from . import laws
from .vectors import stack

__all__ = ["central_chain_friction", "central_chain_friction_components", "smooth_sign"]


def smooth_sign(w: np.ndarray, epsilon: float, vector: bool = False) -> np.ndarray:
    """ŝ(w) = w/√(|w|² + ε²) (spec §7.3; :func:`hipsim.physics.laws.smooth_sign`).

    Args:
        w: speeds in [rad/s], any shape; with ``vector`` the last axis is a 3-vector.
        epsilon: ε in [rad/s]; below it the Coulomb friction fades linearly to zero.
        vector: True to take |w| over the last axis.
    """
    w = np.asarray(w, dtype=float)
    if not vector:
        return laws.smooth_sign(w, epsilon)
    return np.moveaxis(stack(laws.smooth_sign_vector(np.moveaxis(w, -1, 0), epsilon)), 0, -1)


def central_chain_friction(
    friction, weight: float, omega: np.ndarray, Fe: np.ndarray, R: np.ndarray | None = None
) -> np.ndarray:
    """Friction moment τ_mf of one platform's central chain (hip joint + thrust bearing), spec §4.3.

    Args:
        friction: the friction coefficients (:class:`hipsim.machine.parameters.Friction`).
        weight: the platform's weight m_m·g in [N], which the thrust bearing carries with the load.
        omega: platform angular velocity in [rad/s], (N, 3).
        Fe: load magnitude in [N], (N,), pushing down like the platform's weight.
        R: platform rotations, (N, 3, 3); needed when the thrust bearing
            resists only rotation about its own axis (``friction.thrust_bearing_axial_only``).

    Returns:
        τ_mf in [N·m], (N, 3); it resists the platform's rotation.

    Raises:
        ArgumentError: the axial-only thrust bearing without R.
    """
    if friction.thrust_bearing_axial_only and R is None:
        raise ArgumentError(
            "R", None, "the platform rotations (N, 3, 3): the axial-only thrust bearing's friction needs them"
        )
    z = None if R is None else np.asarray(R, dtype=float)[..., 2].T
    return central_chain_friction_components(
        friction, weight, np.asarray(omega, dtype=float).T, np.asarray(Fe, dtype=float), z
    ).T


def central_chain_friction_components(friction, weight: float, omega: np.ndarray, Fe: np.ndarray, z) -> np.ndarray:
    """:func:`central_chain_friction` with ω and the platform's z axis components-first (3, N); z may be None."""
    return stack(laws.central_friction_moment(friction, omega, z, Fe, weight))

"""The hip's joint angles (ISB Z–X–Y chain) and the machine's platform angles (R = Rz(γ)·Ry(β)·Rx(α)).

Gait data give the hip as a joint chain in the pelvis's axes (ISB, Wu et al.
2002; OpenSim's ``hip_flexion``, ``hip_adduction``, ``hip_rotation``): flexion
about the pelvis's mediolateral axis first, then adduction about the rotated
anterior axis, internal rotation about the femur's long axis last,

    R_h = Rz(flexion)·Rx(adduction)·Ry(rotation)   (intrinsic Z–X–Y),

with the pelvis axes x anterior, y superior, z to the subject's right. The
machine turns its platforms by R = Rz(γ)·Ry(β)·Rx(α) in its own axes, which
map onto the body as X → the subject's right, Y → anterior, Z → superior
(:data:`PELVIS_AXES`), so that α is flexion, β adduction and γ internal
rotation, each positive as the ISB has it for a right hip. The same rotation
in both frames is R = C·R_h·Cᵀ, C = :data:`PELVIS_AXES`.

One angle at a time the two sets agree (flexion = α, adduction = β, rotation
= γ); combined they differ, because the chain flexes first and turns about
the femur last while the machine turns about the vertical first and flexes
last. Along the built-in ISO cycle the difference reaches several degrees.

A left hip: OpenSim's left-side axes are mirrored (adduction about −x,
rotation about −y), so that positive values are adduction and internal
rotation on both sides. Mirroring the left femur's motion through the
sagittal plane, M·R_h,left·M with M = diag(1, 1, −1), gives exactly
Rz(flexion)·Rx(adduction)·Ry(rotation): the same composition, so a left hip's
coordinates drive the machine as the mirror-image right hip would.

Compositions and decompositions are SciPy's :class:`~scipy.spatial.transform.Rotation`
(``"ZXY"`` and ``"ZYX"``, upper case: intrinsic). Both decompositions are
regular within ±90° of the middle angle (adduction, β), far beyond any gait.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from ..exceptions import ArgumentError

__all__ = ["PELVIS_AXES", "hip_to_machine", "machine_to_hip", "hip_angles_of", "hip_rotation", "machine_rotation"]

#: The pelvis axes (ISB: x anterior, y superior, z right) in machine axes, as columns:
#: x_p → +Y, y_p → +Z, z_p → +X.
PELVIS_AXES = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
PELVIS_AXES.setflags(write=False)
_C = Rotation.from_matrix(PELVIS_AXES)


def _rows(angles) -> tuple[np.ndarray, tuple[int, ...]]:
    angles = np.asarray(angles, dtype=float)
    if angles.shape[-1:] != (3,):
        raise ArgumentError("angles", angles, "shape (3,) or (N, 3)")
    return angles.reshape(-1, 3), angles.shape


def hip_rotation(hip) -> np.ndarray:
    """The femur's rotation in the pelvis's axes, R_h = Rz(flexion)·Rx(adduction)·Ry(rotation).

    Args:
        hip: [flexion, adduction, internal rotation] in [rad], shape (3,) or (N, 3).

    Returns:
        R_h, shape (3, 3) or (N, 3, 3).
    """
    rows, shape = _rows(hip)
    return Rotation.from_euler("ZXY", rows).as_matrix().reshape(shape[:-1] + (3, 3))


def machine_rotation(q) -> np.ndarray:
    """The platform rotation R = Rz(γ)·Ry(β)·Rx(α) in machine axes.

    Args:
        q: [α, β, γ] in [rad], shape (3,) or (N, 3).

    Returns:
        R, shape (3, 3) or (N, 3, 3).
    """
    rows, shape = _rows(q)
    return Rotation.from_euler("ZYX", rows[:, ::-1]).as_matrix().reshape(shape[:-1] + (3, 3))


def hip_to_machine(hip) -> np.ndarray:
    """Platform angles [α, β, γ] that turn the platforms as the hip's joint chain turns the femur.

    Args:
        hip: [flexion, adduction, internal rotation] in [rad] of the ISB Z–X–Y
            chain, shape (3,) or (N, 3).

    Returns:
        [α, β, γ] in [rad], same shape; α and γ in (−π, π], β in [−π/2, π/2].
    """
    rows, shape = _rows(hip)
    R = _C * Rotation.from_euler("ZXY", rows) * _C.inv()
    return R.as_euler("ZYX")[:, ::-1].reshape(shape)


def hip_angles_of(R) -> np.ndarray:
    """The ISB hip chain's angles of a platform rotation R (machine axes).

    Args:
        R: rotation matrices, shape (3, 3) or (N, 3, 3).

    Returns:
        [flexion, adduction, internal rotation] in [rad], shape (3,) or (N, 3).
    """
    R = np.asarray(R, dtype=float)
    Rh = _C.inv() * Rotation.from_matrix(R.reshape(-1, 3, 3)) * _C
    return Rh.as_euler("ZXY").reshape(R.shape[:-2] + (3,))


def machine_to_hip(q) -> np.ndarray:
    """The ISB hip chain's angles [flexion, adduction, internal rotation] of platform angles [α, β, γ].

    The inverse of :func:`hip_to_machine`.

    Args:
        q: [α, β, γ] in [rad], shape (3,) or (N, 3).

    Returns:
        [flexion, adduction, internal rotation] in [rad], same shape.
    """
    return hip_angles_of(machine_rotation(q))

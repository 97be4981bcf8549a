"""How the platforms' attitudes move with the per-chain values, and which combinations of them any log can see.

Platform j's carriage readings are a closed-form function L = f_j(q, θ) of its
attitude q and the per-chain values θ (:mod:`hipsim.stations.deviations`). At a
fixed reading, 0 = (∂f_j/∂q)·dq + (∂f_j/∂θ)·dθ, so the attitude the sensor
sees moves by

    ∂q_j/∂θ = −(∂f_j/∂q)⁻¹·∂f_j/∂θ,

∂f_j/∂q being :func:`reading_rate` (from :func:`hipsim.analytic.stations.platform_jacobian`) and ∂f_j/∂θ
:func:`hipsim.analytic.stations.carriage_sensitivities` in closed form (the kinematics live once, there).
Here θ is the deviation vector δ of :mod:`hipsim.stations.deviations`.

:func:`structure` finds the combinations of θ that no log can see, from the
structure alone (as ``identify --base`` does for the dynamic parameters): the
prediction Jacobian over random poses in the workspace, with each sensor
angle's mean removed when a constant offset per sensor and log is estimated
too, and a QR decomposition of its columns in a fixed order of preference (a value
the earlier ones explain leaves a zero on R's diagonal). Its rank r and those r
columns are the values estimated; each other value is kept at its prior (the
drawing) and folded into them by fixed coefficients C, the least-squares
solution of Y₁·C = Y₂ (exact here): θ_b = θ₁ + C·θ₂. Translating a whole platform with its
U-joints, or lifting it with its three sliders, changes no reading: those are
the directions it finds on the published machine.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..analytic.stations import carriage_sensitivities, platform_jacobian
from ..machine.parameters import Parameters
from ..physics import laws
from ..physics.orientation import angular_velocity_map
from . import deviations as dv

__all__ = [
    "Structure",
    "attitude_jacobian",
    "inverse3",
    "platform_attitude_jacobian",
    "random_poses",
    "reading_jacobian",
    "reading_rate",
    "structure",
]

#: A pivot of R this far below the largest (in units of the prior) is a direction no log can see.
RANK_TOL = 1e-7
#: Random poses for the structure, and their range in [rad] per angle.
POSES = 240
POSE_RANGE = np.radians(20.0)


def reading_rate(params: Parameters, q: np.ndarray, j: int) -> np.ndarray:
    """∂f_j/∂q: how platform j's carriage readings move with its gait angles q (N, 3) [rad], (N, 3, 3) [m/rad].

    L̇ = J_j·ω and ω = T(p)·ṗ with p the platform angles (gait angles times the file's angle signs).
    """
    signs = params.angle_signs
    return np.matmul(platform_jacobian(params, q, j), angular_velocity_map(q * signs)) * signs


def reading_jacobian(params: Parameters, j: int, q: np.ndarray, q_other: np.ndarray | None = None) -> np.ndarray:
    """∂f_j/∂δ: how platform j's carriage readings at gait angles q (N, 3) move with its values, (N, 3, 27 or 24) [m/m].

    The columns follow :func:`hipsim.stations.deviations.platform_columns` (platform 1's include the stack-up's
    seat, which needs m_2's attitude ``q_other``; None for q)
    (:func:`hipsim.analytic.stations.carriage_sensitivities`, closed form).
    """
    return carriage_sensitivities(params, q, j, q_other)[..., dv.platform_columns(j)]


def inverse3(P: np.ndarray) -> np.ndarray:
    """P⁻¹ of 3x3 matrices (N, 3, 3) in closed form (:func:`hipsim.physics.laws.inverse_transpose`); inf where singular."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rows = laws.inverse_transpose([P[:, i, :].T for i in range(3)])  # row i of P⁻ᵀ = column i of P⁻¹
    return np.array(rows).transpose(2, 1, 0)


def platform_attitude_jacobian(
    params: Parameters, q: np.ndarray, j: int, q_other: np.ndarray | None = None
) -> np.ndarray:
    """∂q_j/∂δ of platform j at its gait angles q (N, 3) [rad], for its own values, (N, 3, 27 or 24) [rad/m].

    The columns follow :func:`hipsim.stations.deviations.platform_columns`; the other platform's values do not move it
    (under a stack-up, only by a product of two deviations). ``q_other``: m_2's attitude for m_1's stack-up column.
    ∂q_j/∂δ = −(∂f_j/∂q)⁻¹·∂f_j/∂δ, from :func:`reading_rate` and :func:`reading_jacobian`.
    """
    return -np.matmul(inverse3(reading_rate(params, q, j)), reading_jacobian(params, j, q, q_other))


def attitude_jacobian(params: Parameters, q: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """∂q_j/∂δ at both platforms' gait angles q (N, 2, 3) [rad], (N, 2, 3, 48) [rad/m]; zero across platforms.

    Args:
        params: the machine.
        q: both platforms' attitudes in [rad], (N, 2, 3).
        columns: only these entries of δ (the last axis then follows them); None for all 48.
    """
    out = np.zeros((len(q), 2, 3, dv.COUNT))
    for j in (1, 2):  # m_2's attitude: m_1's seat column needs it (m_2's own columns do not)
        out[:, j - 1][..., dv.platform_columns(j)] = platform_attitude_jacobian(params, q[:, j - 1], j, q[:, 1])
    return out if columns is None else out[..., columns]


def random_poses(samples: int = POSES, seed: int = 0) -> np.ndarray:
    """Random attitudes in [rad], (samples, 3), uniform within ±20° per angle."""
    return np.random.default_rng(seed).uniform(-POSE_RANGE, POSE_RANGE, (samples, 3))


@dataclass(frozen=True, eq=False)
class Structure:
    """The combinations of the per-chain values the sensors can see.

    Attributes:
        rank: how many combinations are seen.
        independent: the entries of θ estimated, sorted.
        dependent: the entries kept at their prior, sorted.
        coefficients: (rank, dependent) fixed coefficients in θ_b = θ₁ + coefficients·θ₂, in the order of
            ``independent`` and ``dependent``.
        offsets: whether a constant offset per sensor and log was taken out.
    """

    rank: int
    independent: np.ndarray
    dependent: np.ndarray
    coefficients: np.ndarray
    offsets: bool

    def definitions(self, tol: float = 1e-6) -> list[str]:
        """Each estimated value that absorbs others, as ``name + c·other + …`` (coefficients rounded to 1e-6)."""
        labels = dv.names()
        out = []
        for row, k in enumerate(self.independent):
            terms = [
                f"{'+' if c > 0 else '−'} {abs(c):.6g}·{labels[d]}"
                for c, d in zip(self.coefficients[row], self.dependent)
                if abs(c) > tol
            ]
            if terms:
                out.append(f"{labels[k]} {' '.join(terms)}")
        return out


def _preference() -> np.ndarray:
    """The entries of θ in the order they are preferred as estimated values: the chains' own, then the centres.

    Among values that trade against each other the later one is kept at its prior, so the centres (which a
    translation of the whole platform moves with its U-joints) are the first kept; a fixed order, not the
    pivoting's choice among columns of equal norm, so that every machine of one drawing reports the same set.
    """
    labels = dv.names()
    order = (
        "lever",
        "slider",
        "ujoint_x",
        "ujoint_y",
        "joint_x",
        "joint_y",
        "joint_z",
        "centre_x",
        "centre_y",
        "centre_z",
        "spline_x",
        "spline_y",
        "spline_z",
    )
    return np.array(sorted(range(dv.COUNT), key=lambda k: (order.index(labels[k].rsplit("_", 1)[0]), k)))


def structure(params: Parameters, offsets: bool, seed: int = 0) -> Structure:
    """The combinations of θ the two attitude sensors can see on this machine, by QR over random poses.

    Args:
        params: the machine (its drawing or a calibration's start).
        offsets: a constant offset per sensor angle is estimated too (each angle's mean is then no evidence).
        seed: the random poses' seed (a second seed gives the same result to ~1e-9).
    """
    q_single = random_poses(POSES, seed)
    q = np.stack([q_single, q_single], axis=1)
    Y = attitude_jacobian(params, q)  # (N, 2, 3, 51) [rad/m]; all values share one prior scale
    if offsets:
        Y = Y - Y.mean(axis=0)
    Y = Y.reshape(-1, dv.COUNT)
    order = _preference()
    # Without pivoting, in the preferred order: a value that the earlier ones explain leaves a zero on R's diagonal.
    R = scipy.linalg.qr(Y[:, order], mode="r")[0]
    diagonal = np.abs(np.diag(R))
    seen = diagonal > RANK_TOL * diagonal.max()
    independent, dependent = np.sort(order[seen]), np.sort(order[~seen])
    Y1 = Y[:, independent]
    coefficients = np.linalg.solve(Y1.T @ Y1, Y1.T @ Y[:, dependent])
    coefficients = np.where(np.abs(coefficients) < 1e-9, 0.0, coefficients)
    return Structure(independent.size, independent, dependent, coefficients, offsets)

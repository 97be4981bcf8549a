"""Uncertainty forward: the identified base parameters' covariance, read back, and 95 % bands on motor torques.

An identified parameter file carries the ``[identification]`` table
(:meth:`hipsim.rig.identification.fit.Identification.table`): the base
parameters by name (``base``), their definitions, posterior ``value`` and
``std``, ``prior`` and ``prior_std``, and ``covariance`` (r × r, file units).
:func:`read_covariance` reads and checks it; torque is linear in the base
parameters, τ = Y_b·θ_b, so the standard deviation of a predicted torque sample
is exactly √(y_kᵀ Σ y_k) (:func:`torque_std`), and its 95 % band ±1.96 of that.
A nonlinear quantity of the torques (a sizing margin) takes draws of θ_b
(:func:`torque_draws`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import ParameterError
from ...machine.parameters import Parameters
from ...motion.trajectories import Trajectory
from .base import base_parameters
from .identified_file import identification_table
from .regressor import regressor

__all__ = [
    "Z95",
    "Covariance",
    "band_columns",
    "band_summary",
    "log_torque_std",
    "read_covariance",
    "sigma_machines",
    "torque_draws",
    "torque_std",
]

#: The two-sided 95 % quantile of the normal distribution.
Z95 = 1.959963984540054


@dataclass(frozen=True, eq=False)
class Covariance:
    """The base parameters' posterior covariance of an identified file.

    Attributes:
        names: the base parameters, by name.
        matrix: their covariance in SI, (r, r).
        determined: per base parameter, whether the logs determined it.
        lever_spin: the model they were identified with.
        source: the file.
        residual: the fit's residual RMS per motor in [N·m], (3,) (noise and model error of the training logs, filtered), or None.
    """

    names: tuple[str, ...]
    matrix: np.ndarray
    determined: tuple[bool, ...]
    lever_spin: bool
    source: str
    residual: np.ndarray | None = None


def _table_error(key: str, path: str | Path, message: str) -> ParameterError:
    """An entry of the file's ``[identification]`` table that cannot be read, named by file and key."""
    return ParameterError(message, key=f"identification.{key}", source=str(path))


def read_covariance(path: str | Path | None, params: Parameters) -> Covariance | None:
    """The ``[identification]`` covariance of a parameter file, checked; None when it has none.

    Raises:
        ParameterError: naming the file and key: a table of the wrong shape, not symmetric positive
            semi-definite, or of base parameters other than this machine's.
    """
    if path is None:
        return None
    table = identification_table(path)
    if "covariance" not in table:
        return None
    names = table.get("base")
    lever_spin = bool(table.get("lever_spin", True))
    try:
        matrix = np.array(table["covariance"], dtype=float)
    except (TypeError, ValueError):
        raise _table_error("covariance", path, "expected a square table of numbers") from None
    if not isinstance(names, list) or matrix.shape != (len(names), len(names)):
        raise _table_error(
            "covariance",
            path,
            f"expected {len(names) if isinstance(names, list) else 'one row per base parameter'} rows "
            f"and columns (one per name in base), got shape {matrix.shape}",
        )
    if not np.all(np.isfinite(matrix)):
        raise _table_error("covariance", path, "not finite")
    size = max(np.abs(matrix).max(), 1e-300)
    if np.abs(matrix - matrix.T).max() > 1e-9 * size:
        raise _table_error("covariance", path, "not symmetric")
    scale = np.sqrt(np.maximum(np.diag(matrix), 1e-300))
    eigen = np.linalg.eigvalsh(matrix / np.outer(scale, scale)) if len(names) else np.zeros(1)
    if eigen.min() < -1e-8 * max(eigen.max(), 1.0):
        raise _table_error(
            "covariance",
            path,
            f"not positive semi-definite (smallest eigenvalue {eigen.min():.3g} of the correlation matrix)",
        )
    base = base_parameters(params, lever_spin)
    if list(names) != base.names:
        raise _table_error(
            "base",
            path,
            f"{', '.join(map(str, names))} are not this machine's base parameters ({', '.join(base.names)})",
        )
    determined = table.get("determined", [True] * len(names))
    si = matrix * np.outer(base.scale, base.scale)
    residual = table.get("residual_rms_Nmm")
    try:
        residual = None if residual is None else np.array(residual, dtype=float).reshape(3) * 1e-3
    except (TypeError, ValueError):
        raise _table_error(
            "residual_rms_Nmm", path, f"expected three numbers (N·mm per motor), got {table.get('residual_rms_Nmm')!r}"
        ) from None
    if residual is not None and not np.all(np.isfinite(residual) & (residual >= 0)):
        raise _table_error(
            "residual_rms_Nmm", path, f"expected three non-negative numbers, got {table.get('residual_rms_Nmm')!r}"
        )
    return Covariance(tuple(names), si, tuple(bool(d) for d in determined), lever_spin, str(path), residual)


def _base_rows(params: Parameters, trajectory: Trajectory, covariance: Covariance) -> np.ndarray:
    base = base_parameters(params, covariance.lever_spin)
    return regressor(params, trajectory, covariance.lever_spin)[:, :, base.index]


def torque_std(params: Parameters, trajectory: Trajectory, covariance: Covariance) -> np.ndarray:
    """The standard deviation of each predicted motor torque sample in [N·m], (N, 3): √(y_kᵀ Σ y_k)."""
    Yb = _base_rows(params, trajectory, covariance)
    return np.sqrt(np.maximum(np.einsum("nip,pq,niq->ni", Yb, covariance.matrix, Yb), 0.0))


def torque_draws(
    params: Parameters, trajectory: Trajectory, covariance: Covariance, draws: int = 200, seed: int = 0
) -> np.ndarray:
    """Draws of the motor torques' deviation from the prediction in [N·m], (draws, N, 3), θ_b ~ N(θ̂_b, Σ)."""
    Yb = _base_rows(params, trajectory, covariance)
    values, vectors = np.linalg.eigh(covariance.matrix)
    root = vectors * np.sqrt(np.maximum(values, 0.0))
    deltas = np.random.default_rng(seed).standard_normal((draws, len(values))) @ root.T
    return np.einsum("nip,dp->dni", Yb, deltas)


def band_columns(
    params: Parameters, trajectory: Trajectory, covariance: Covariance, tau_Nmm: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """The 95 % band columns ``tau_i_lo95_Nmm``, ``tau_i_hi95_Nmm`` of a piece of a torque CSV, from its ``tau_i_Nmm`` columns.

    A sample whose pose the regressor cannot take (flagged) gets NaN.
    """
    from ...exceptions import PoseError

    try:
        half = Z95 * torque_std(params, trajectory, covariance) * 1e3
    except PoseError:
        half = np.full((len(trajectory), 3), np.nan)
    out = {}
    for i in range(3):
        tau = np.asarray(tau_Nmm[f"tau_{i + 1}_Nmm"], dtype=float)
        out[f"tau_{i + 1}_lo95_Nmm"] = tau - half[:, i]
        out[f"tau_{i + 1}_hi95_Nmm"] = tau + half[:, i]
    return out


def log_torque_std(params: Parameters, log, times: np.ndarray, covariance: Covariance) -> np.ndarray:
    """:func:`torque_std` along a rig log (:class:`hipsim.rig.logs.log.Log`, window by window) at the samples of ``times`` in [s], (N, 3) [N·m].

    ``times`` are samples of the log (a comparison's kept samples); one that is not gets NaN.
    """
    from ...exceptions import PoseError

    times = np.asarray(times, dtype=float)
    out = np.full((times.size, 3), np.nan)
    for window, core, _ in log.windows():
        trajectory = window.trajectory
        chosen = np.flatnonzero(np.isin(trajectory.t[core], times)) + (core.start or 0)
        if chosen.size == 0:
            continue
        part = Trajectory(
            trajectory.t[chosen],
            trajectory.q[chosen],
            trajectory.qd[chosen],
            trajectory.qdd[chosen],
            trajectory.Fe[chosen],
            name=trajectory.name,
        )
        try:
            std = torque_std(params, part, covariance)
        except PoseError:
            continue
        out[np.searchsorted(times, part.t)] = std
    return out


def band_summary(half_Nm: np.ndarray, error_Nm: np.ndarray, residual: np.ndarray | None = None) -> dict:
    """Per motor ("1", "2", "3"): the model's 95 % band (its parameters' uncertainty) in [N·mm], RMS and largest half-width, and the share of
    samples whose model − measured error lies within it; with the fit's ``residual`` RMS in [N·m], (3,), also the prediction band
    ±1.96·√(σ_model² + residual²) (what a measurement adds: its noise and the model error of the training logs) and the share within that."""
    out = {}
    for i in range(3):
        half, error = half_Nm[:, i], error_Nm[:, i]
        ok = np.isfinite(half)
        entry = {
            "rms_half_width_Nmm": float(np.sqrt(np.mean(half[ok] ** 2)) * 1e3) if ok.any() else None,
            "max_half_width_Nmm": float(half[ok].max() * 1e3) if ok.any() else None,
            "measured_within_band": float(np.mean(np.abs(error[ok]) <= half[ok])) if ok.any() else None,
        }
        if residual is not None:
            wide = np.sqrt(half**2 + (Z95 * residual[i]) ** 2)
            entry["prediction_rms_half_width_Nmm"] = float(np.sqrt(np.mean(wide[ok] ** 2)) * 1e3) if ok.any() else None
            entry["measured_within_prediction_band"] = (
                float(np.mean(np.abs(error[ok]) <= wide[ok])) if ok.any() else None
            )
        out[str(i + 1)] = entry
    return out


def sigma_machines(params: Parameters, covariance: Covariance) -> list[Parameters]:
    """Machines one standard deviation away along each principal direction of the covariance: θ_b + √λ_k·v_k.

    For any quantity g of a model run (a sizing margin), Σ_k (g(machine_k) − g(params))² is
    ∇gᵀ Σ ∇g to first order (the columns √λ_k·v_k factor Σ), the variance of g: one model run per
    base parameter instead of hundreds of draws. Directions of zero variance are left out.
    """
    from .quantities import standard_values, with_values

    base = base_parameters(params, covariance.lever_spin)
    theta = standard_values(params)
    theta_b = base.transform @ theta
    values, vectors = np.linalg.eigh(covariance.matrix)
    out = []
    for k in np.flatnonzero(values > 1e-12 * max(values.max(), 1e-300)):
        out.append(with_values(params, base.standard(theta_b + math.sqrt(values[k]) * vectors[:, k], theta)))
    return out

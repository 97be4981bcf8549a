"""The specimen's friction from the motor torques of one snapshot: the monitor's estimate.

The reference machine (an identified parameter file) is held fixed: inertias,
masses, the transmission, the guides' and lever joints' friction. What a
snapshot re-estimates are the friction terms it determines (spec §4.3; the
regressor's friction columns, :mod:`hipsim.rig.identification.regressor`):

- ``load_friction_mm``: a = r_h·μ_h + r_t·μ_t, the central chain's friction
  moment per newton of axial load. The hip joint's column is ŝ(ω)·r_h·|F_e| and
  the thrust bearing's ŝ(ω)·r_t·|F_e + m_m·g|: under the one shared load both
  multiply ŝ(ω)·|F_e| alike, so only their sum a is seen;
- ``weight_friction_Nmm``: b = r_t·μ_t·m_m·g, the thrust bearing's moment
  from the platform's own weight (with m_m from the file, itself an estimate);
- the screw's Coulomb and viscous friction (the guide's Coulomb and viscous
  terms have the same columns; they are held at the file's values, so a change
  of either shows in the screw's).

Least squares over the snapshot's filtered, decimated rows (reversals left
out, as identification does). The standard errors hold for correlated
residuals: a sandwich (Newey–West) covariance whose correlation window is the
rows per independent row identification floors its information by
(:func:`~hipsim.rig.identification.regressor.rows_per_independent_row`: the
low-pass's and the model error's bandwidth), so a residual correlated over that
window widens the errors as much as it is correlated, and a white one (noise
only) does not: repeated noise-only snapshots give z-scores of spread 1. A
slower model error that moves between snapshots shows in the chart's
between-snapshot spread σ₀ instead. With per-station loads logged (``Fe_1_N``,
``Fe_2_N``) the load term is split per station (a_1, a_2) when the two loads
vary differently enough to tell apart; when they are proportional they cannot
be, and the row says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...analytic.inverse_kinematics import kinematics
from ...analytic.virtual_work import inverse_dynamics
from ...exceptions import HipsimError, IdentificationError, ParameterError
from ...fingerprint import part_fingerprints
from ...fit_checks import NOISE_FLOOR, FitCheck, column_pattern, residual_gate
from ...machine.parameters import Parameters
from ..identification.quantities import friction_unit
from ..identification.regressor import CHUNK, decimation, rows_per_independent_row
from ..identification.self_check import TORQUE_COLUMNS
from ..logs.log import DEFAULT_TOLERANCE_DEG, MeasuredLog
from ..logs.reversals import reversal_mask
from ..logs.smoothing import DEFAULT_CUTOFF, lowpass, minimum_samples
from ..plausibility import check_log
from .reference import identified_file, reference
from .snapshot_log import read_snapshot
from .snapshots import Skipped, Snapshot, skipped

__all__ = [
    "ESTIMATE_COLUMNS",
    "ESTIMATOR",
    "MonitorSetup",
    "estimate",
    "estimate_batch",
    "identified_file",  # from .reference, where it lives; kept here for the callers that import it from the fit
    "reference",
]

#: The estimator's version: part of the set-up's fingerprint, so a changed estimator never extends an older table.
ESTIMATOR = "monitor-2"
#: The per-snapshot columns :func:`estimate` fills.
ESTIMATE_COLUMNS = (
    "cycle",
    "last_cycle",
    "file",
    "samples",
    "load_friction_mm",
    "load_friction_mm_std",
    "weight_friction_Nmm",
    "weight_friction_Nmm_std",
    "screw_coulomb_Nmm",
    "screw_coulomb_Nmm_std",
    "screw_viscous_Nmm_s_rad",
    "screw_viscous_Nmm_s_rad_std",
    "load_friction_1_mm",
    "load_friction_1_mm_std",
    "load_friction_2_mm",
    "load_friction_2_mm_std",
    "stations",
    "load_gain",
    "residual_rms_Nmm",
    "note",
    "bytes",
    "sha256",
)
#: A per-station split is reported when each station's standard deviation is below this fraction of the whole term
#: (and the stations' load columns are not proportional: smallest to largest singular value of the unit-norm columns above 1e-6).
STATION_SEPARABLE = 0.2
_FITTED = ("hip_mu", "thrust_mu", "screw_coulomb", "screw_viscous")


@dataclass(frozen=True, eq=False)
class MonitorSetup:
    """What every snapshot shares.

    Attributes:
        params: the identified reference machine.
        lever_spin: the model's lever spin (as identification used; its file header says).
        cutoff: the low-pass cutoff in [Hz] (None: signals already clean).
        torque_constant: the motors' torque constant in [N·m/A], for logs of currents.
        tolerance_deg: the attitude sensor's allowed disagreement with the encoders in [deg].
        window: cycles per window of a long log, or None (one snapshot a file).
        rate: the sample rate in [Hz] the times are read from (the sample index), or None for the logs' time stamps.
        columns: a TDMS or HDF5 snapshot's column map (``NAME=GROUP/CHANNEL,…``, :mod:`hipsim.channels`), or None.
    """

    params: Parameters
    lever_spin: bool = True
    cutoff: float | None = DEFAULT_CUTOFF
    torque_constant: float | None = None
    tolerance_deg: float = DEFAULT_TOLERANCE_DEG
    window: int | None = None
    rate: float | None = None
    columns: str | None = None

    def __post_init__(self):
        f = self.params.friction
        if f.thrust_bearing_axial_only:
            raise ParameterError(
                "the monitor's load term r_h·μ_h + r_t·μ_t needs the thrust bearing's moment along ω "
                "(friction.thrust_bearing_axial_only = false)",
                "friction.thrust_bearing_axial_only",
                True,
                self.params.source,
            )
        if not (f.hip_radius > 0):
            raise ParameterError(
                "the hip joint's friction radius must be positive to read its friction",
                "friction.hip_radius_mm",
                f.hip_radius,
                self.params.source,
            )

    def fingerprints(self) -> dict[str, str]:
        """The fingerprint of everything that determines an estimate, per part and whole (``"setup"``)."""
        return part_fingerprints(
            {
                "parameters": self.params,
                "model": {
                    "lever_spin": self.lever_spin,
                    "cutoff": self.cutoff,
                    "torque_constant": self.torque_constant,
                    "tolerance_deg": self.tolerance_deg,
                    "rate": self.rate,
                    # Only when given: a table of CSV snapshots keeps the fingerprint it had.
                    **({"columns": self.columns} if self.columns is not None else {}),
                },
                "window": self.window,
                "estimator": ESTIMATOR,
            }
        )


def _rows(setup: MonitorSetup, log: MeasuredLog, loads: np.ndarray | None):
    """The fit's rows, chunk by chunk: the fixed machine's torque, the fitted terms' columns, the measured torque, the rows to use.

    The regressor's columns (:func:`hipsim.rig.identification.regressor.log_rows`) of only what is fitted: by the
    model's linearity in θ, the torque of every held parameter is the inverse dynamics of the machine with the fitted
    coefficients at zero, and each fitted coefficient's column that of the machine whose only friction is that
    coefficient at one (:func:`~hipsim.rig.identification.quantities.friction_unit`, as the regressor builds it): five
    runs of the model instead of the regressor's ten, filtered and decimated as the regressor's rows are. With
    per-station loads, two more runs give each station's load column.

    Yields:
        fixed (m, 3), columns (m, 3, 4) of μ_h, μ_t, the screw's Coulomb and viscous coefficients, τ (m, 3),
        use (m, 3) bool, stations (m, 3, 2) or None.
    """
    params = setup.params
    held = params.replace(**{name: 0.0 for name in _FITTED})
    units = [friction_unit(params, name) for name in _FITTED]
    n, step = len(log), decimation(log)
    first, stop = log.usable.start, log.usable.stop
    margin = 0 if log.cutoff is None else minimum_samples(log.rate, log.cutoff)
    use_all = ~reversal_mask(params, log)
    if loads is not None and log.cutoff is not None:
        loads = np.maximum(lowpass(loads, log.rate, log.cutoff, log.name), 0.0)  # as the log's own load
    chunk = max(step, CHUNK - CHUNK % step)  # whole decimation steps, as the regressor's rows
    for a in range(first, stop, chunk):
        b = min(a + chunk, stop)
        lo, hi = max(0, a - margin), min(n, b + margin)
        trajectory = log.trajectory.slice(slice(lo, hi))
        kin = kinematics(params, trajectory)
        parts = [inverse_dynamics(held, kin, trajectory.Fe, setup.lever_spin).total]
        parts += [inverse_dynamics(unit, kin, trajectory.Fe, setup.lever_spin).friction for unit in units]
        if loads is not None:
            for p in range(2):
                column = inverse_dynamics(units[0], kin, loads[lo:hi, p], setup.lever_spin).friction
                parts.append(column / params.heights.size)
        Y = np.stack(parts, axis=-1)
        if log.cutoff is not None:
            Y = lowpass(Y, log.rate, log.cutoff, log.name)
        keep = np.arange(a, b, step)
        Y = Y[keep - lo]
        yield Y[:, :, 0], Y[:, :, 1:5], log.tau[keep], use_all[keep], (Y[:, :, 5:7] if loads is not None else None)


def _solve(A: np.ndarray, y: np.ndarray, time: np.ndarray, window: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least squares with a standard error that holds for correlated residuals: (estimate, standard deviations, residual).

    The covariance is the sandwich (AᵀA)⁻¹·S·(AᵀA)⁻¹ with S the rows' scores g_t = Σ_motors A_t·r_t summed with their
    neighbours up to ``window`` rows apart, Bartlett-weighted (Newey & West 1987): a white residual gets the plain
    σ²(AᵀA)⁻¹, a residual correlated over the window (the low-pass, the model error) its wider spread, as the data
    show it. Columns are scaled to unit norm first; dependent columns give NaN estimates and infinite deviations.

    Args:
        A: (rows, k) columns, rows of every motor.
        y: (rows,) targets.
        time: (rows,) each row's sample (its decimated row index), non-decreasing.
        window: rows a residual may be correlated over (≥ 0).
    """
    norm = np.linalg.norm(A, axis=0)
    norm = np.where(norm > 0, norm, 1.0)
    An = A / norm
    singular = np.linalg.svd(An, compute_uv=False)
    if singular[-1] <= 1e-6 * singular[0]:
        return np.full(A.shape[1], math.nan), np.full(A.shape[1], math.inf), np.full(A.shape[0], math.nan)
    x, *_ = np.linalg.lstsq(An, y, rcond=None)
    residual = y - An @ x
    samples = int(time[-1]) + 1 if time.size else 0
    scores = np.zeros((samples, A.shape[1]))
    np.add.at(scores, time, An * residual[:, None])
    S = scores.T @ scores
    for lag in range(1, window + 1):
        C = scores[:-lag].T @ scores[lag:]
        S += (1.0 - lag / (window + 1.0)) * (C + C.T)
    bread = np.linalg.pinv(An.T @ An)
    dof = A.shape[0] / max(A.shape[0] - A.shape[1], 1)  # the residual is short of k degrees of freedom
    covariance = bread @ S @ bread * dof
    return x / norm, np.sqrt(np.maximum(np.diag(covariance), 0.0)) / norm, residual


def estimate(setup: MonitorSetup, snapshot: Snapshot) -> dict[str, Any]:
    """One snapshot's row (:data:`ESTIMATE_COLUMNS`): the friction terms with standard deviations, in file units.

    Raises:
        TrajectoryError: the snapshot cannot be read (naming the file, line, column).
        IdentificationError: too few samples to estimate from (naming the file).
    """
    params = setup.params
    f = params.friction
    weight = params.platform_mass * params.gravity
    read = read_snapshot(
        snapshot, params, setup.torque_constant, setup.cutoff, setup.tolerance_deg, setup.rate, setup.columns
    )
    log = read.log
    check_log(params, log, setup.lever_spin, setup.torque_constant)  # a unit slip skips the snapshot (issue 38)
    loads = read.loads if params.heights.size == 2 else None
    blocks = list(_rows(setup, log, loads))
    fixed = np.concatenate([b[0] for b in blocks])
    Y = np.concatenate([b[1] for b in blocks])
    tau = np.concatenate([b[2] for b in blocks])
    use = np.concatenate([b[3] for b in blocks])
    stations = np.concatenate([b[4] for b in blocks]) if loads is not None else None
    load_column = Y[:, :, 0] / f.hip_radius
    columns = [load_column]
    if weight > 0 and f.thrust_radius > 0:
        columns.append((Y[:, :, 1] / f.thrust_radius - load_column) / weight)
    columns += [Y[:, :, 2], Y[:, :, 3]]
    target = tau - fixed
    if int(use.sum()) <= len(columns) + 2:
        raise IdentificationError(
            f"{int(use.sum())} samples left after the filter's edges and the reversals: too few to estimate from",
            (str(snapshot.path),),
        )
    time = np.nonzero(use)[0]
    window = math.ceil(rows_per_independent_row(log))
    A = np.stack(columns, axis=-1)[use]
    x, std, residual = _solve(A, target[use], time, window)
    check = snapshot_check(snapshot.name, tau[use], fixed[use] + A @ x)
    if not check.plausible:  # the snapshot is skipped, naming why (a model that does not explain it is no trend point)
        raise IdentificationError(check.message(), (str(snapshot.path),))
    has_weight = len(columns) == 4
    values = dict(zip(("a", "b", "sc", "sv") if has_weight else ("a", "sc", "sv"), zip(x.tolist(), std.tolist())))
    values.setdefault("b", (math.nan, math.nan))
    row: dict[str, Any] = {
        "cycle": int(read.cycles[0]),
        "last_cycle": int(read.cycles[-1]),
        "file": snapshot.name,
        "samples": len(log),
        "load_friction_mm": values["a"][0] * 1e3,
        "load_friction_mm_std": values["a"][1] * 1e3,
        "weight_friction_Nmm": values["b"][0] * 1e3,
        "weight_friction_Nmm_std": values["b"][1] * 1e3,
        "screw_coulomb_Nmm": values["sc"][0] * 1e3,
        "screw_coulomb_Nmm_std": values["sc"][1] * 1e3,
        "screw_viscous_Nmm_s_rad": values["sv"][0] * 1e3,
        "screw_viscous_Nmm_s_rad_std": values["sv"][1] * 1e3,
        "residual_rms_Nmm": math.sqrt(float(residual @ residual) / residual.size) * 1e3,
        "load_gain": read.load_gain,
        "note": "" if snapshot.ends_with_newline else "no line end after its last line: the file may be cut",
        "bytes": snapshot.size,
        "sha256": snapshot.sha256,
    }
    row |= _stations(setup, stations, use, time, window, columns, target, values["a"][0])
    return row


def snapshot_check(name: str, measured: np.ndarray, model: np.ndarray) -> FitCheck:
    """A snapshot's fit against the gates: residual beyond 3 times the noise (5 % of each motor's RMS torque).

    Args:
        name: the snapshot's name, for the message.
        measured: the measured motor torques of the rows fitted in [N·m], (n, 3).
        model: the fitted model's torques for them in [N·m], (n, 3).

    Returns:
        The check; a failed gate names a swapped, sign-flipped or offset torque column when one explains it.
    """
    residual = np.sqrt(np.mean((measured - model) ** 2, axis=0))
    scale = np.sqrt(np.mean(measured**2, axis=0))
    found = residual_gate(residual * 1e3, NOISE_FLOOR * scale * 1e3, TORQUE_COLUMNS, "N·mm")
    if found is None:
        return FitCheck(name)
    pattern = column_pattern(measured * 1e3, model * 1e3, TORQUE_COLUMNS, "N·mm")
    return FitCheck(
        name, (found + (f" (likely cause: {pattern})" if pattern else " (is the filter off, --no-filter?)"),)
    )


def _stations(setup, stations, use, time, window, columns, target, whole) -> dict[str, Any]:
    """The per-station split of the load term, or why there is none."""
    out: dict[str, Any] = {f"load_friction_{p}_mm{s}": math.nan for p in (1, 2) for s in ("", "_std")}
    if stations is None:
        out["stations"] = "not logged" if setup.params.heights.size == 2 else "one station"
        return out
    A = np.concatenate([stations / setup.params.friction.hip_radius, np.stack(columns[1:], axis=-1)], axis=-1)[use]
    x, std, _ = _solve(A, target[use], time, window)
    if not np.all(std[:2] < STATION_SEPARABLE * abs(whole)):
        out["stations"] = (
            "not separable: the two stations' loads are proportional"
            if np.isinf(std[0])
            else "not separable: the two stations' loads vary too much alike (standard deviation over "
            f"{STATION_SEPARABLE:.0%} of the term)"
        )
        return out
    for p in range(2):
        out[f"load_friction_{p + 1}_mm"], out[f"load_friction_{p + 1}_mm_std"] = float(x[p]) * 1e3, float(std[p]) * 1e3
    out["stations"] = "separated"
    return out


def estimate_batch(batch: list[Snapshot], setup: MonitorSetup) -> list[dict[str, Any] | Skipped]:
    """The rows of a batch of snapshots; a snapshot that cannot be read or estimated is a :class:`Skipped`, its reason
    the error's message (file, line, column), so one bad file never stops a test. The task each worker runs."""
    out: list[dict[str, Any] | Skipped] = []
    for snapshot in batch:
        try:
            out.append(estimate(setup, snapshot))
        except HipsimError as error:
            out.append(skipped(snapshot, error))
    return out

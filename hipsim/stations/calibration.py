"""Kinematic calibration of the two stations from the carriage encoders and the two attitude sensors.

A calibration log holds, per sample, the carriage readings L (the encoders) and
each platform's attitude as its sensor reads it, y_j. The model is

    y_j = q_j(L; θ) + o_j + noise,

q_j the forward kinematics of platform j on the machine with per-chain values
θ (:mod:`hipsim.stations.deviations`), o_j a constant offset per sensor angle
and log when asked (``offsets=True``: the paper's sensor drifts at its zero
between runs) and zero otherwise.

What is estimated (:func:`hipsim.stations.sensitivity.structure`): the
combinations of θ the sensors can see; the others are kept at their prior and
reported. With sensor offsets, the combinations a sensor's zero imitates (a tilt
or turn of a platform's joint pattern: the whole attitude moves by a near
constant) are estimated all the same, with their prior: the logs cannot tell
them from the offsets, and the posterior carries that trade instead of hiding
it (fixing them at the prior made the offsets take the pattern's tilt and the
stated uncertainty miss it). :attr:`Calibration.confounded` names each offset
and the values it trades with; a log with rows where a platform is held at a
known attitude (a fixture: ``known``) pins the offsets and separates them. The fit is Bayesian least squares by Gauss–Newton: every estimated
value has a prior N(drawing, s₀²) (s₀ = 0.5 mm by default), each offset a wide
one (10°), each sensor angle's residual is weighted by the inverse of its
standard deviation, estimated from the residuals as the fit goes (the noise),
and

    Δ = (JᵀWJ + Σ₀⁻¹)⁻¹ (JᵀW r − Σ₀⁻¹(x − x₀)),   Σ_post = (JᵀWJ + Σ₀⁻¹)⁻¹

with J = ∂q/∂θ (:func:`hipsim.stations.sensitivity.attitude_jacobian`). It
stops when no step exceeds 1e-4 of its posterior standard deviation or an
absolute floor, whichever is larger: 1e-10 m (0.1 nm, an atom's size: no
machine moves by it, no encoder sees it) for a per-chain value, 1e-10 rad
(6e-9°, ~1e-5 of the finest attitude sensor's resolution) for an offset.
The floor is for noise-free logs (simulated ones): their residuals, and with
them the posterior spread, fall to round-off, where a relative step is never
met; Gauss–Newton takes such a fit from 0.3 mm to the truth in a few
iterations (five on a 4 s log, its last step ~1e-14 m). A fit
that has not stopped after :data:`MAX_ITERATIONS`, or whose machine leaves the
workspace at a logged reading, is refused (:class:`~hipsim.exceptions.CalibrationError`).
The samples are taken as independent (sensor noise white at the log's rate):
filtered or oversampled sensors make Σ_post optimistic by the ratio of the
rate to twice the bandwidth.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..arrays import readonly
from ..exceptions import ArgumentError, CalibrationError, PoseError
from ..machine.parameters import Parameters
from ..records import Record
from . import deviations as dv
from .commands import attitudes
from .sensitivity import Structure, attitude_jacobian, platform_attitude_jacobian, structure

__all__ = [
    "CONFOUNDED",
    "DEFAULT_PRIOR",
    "NAMED",
    "SEPARATION",
    "Confounding",
    "confounded_pairs",
    "DETERMINED",
    "MAX_ITERATIONS",
    "OFFSET_STEP_FLOOR",
    "STEP_FLOOR",
    "STEP_TOL",
    "Calibration",
    "CalibrationLog",
    "calibrate",
    "prediction_errors",
]

#: The prior standard deviation of every per-chain value in [m] (0.5 mm).
DEFAULT_PRIOR = 0.5e-3
#: The prior standard deviation of a sensor's offset in [rad].
OFFSET_PRIOR = math.radians(10.0)
#: A value is determined by the logs when its posterior standard deviation is at most this of its prior's.
DETERMINED = 0.5
#: The fit has converged when no step exceeds this fraction of its posterior standard deviation ...
STEP_TOL = 1e-4
#: ... or this absolute floor, whichever is larger: a per-chain value's in [m] (0.1 nm), an offset's in [rad].
STEP_FLOOR = 1e-10
OFFSET_STEP_FLOOR = 1e-10
#: Gauss–Newton iterations at most.
MAX_ITERATIONS = 25
#: Largest disagreement in [rad] between a sensor and the drawing's forward kinematics before the fit: beyond, the
#: sensor does not read this machine (a wrong column, a unit slip), 5°.
MAX_DISAGREEMENT = math.radians(5.0)
#: The noise assumed before the residuals say, in [rad] (0.05°).
START_NOISE = math.radians(0.05)


@dataclass(frozen=True, eq=False)
class CalibrationLog:
    """One calibration log, SI.

    Attributes:
        name: where it came from (its file).
        t: sample times in [s], (N,).
        carriages: the carriage readings L_1, L_2, L_3 in [m], (N, 3).
        sensors: each platform's attitude [α, β, γ] as its sensor reads it, in [rad], (N, 2, 3).
        known: where a fixture holds a platform at a known attitude, that attitude in [rad], NaN elsewhere, (N, 2, 3);
            None for none. Its rows pin the log's sensor offsets: offset = sensor − known.
    """

    name: str
    t: np.ndarray
    carriages: np.ndarray
    sensors: np.ndarray
    known: np.ndarray | None = None

    def __post_init__(self):
        n = np.shape(self.t)[0]
        for attr, shape in (("t", (n,)), ("carriages", (n, 3)), ("sensors", (n, 2, 3)), ("known", (n, 2, 3))):
            if getattr(self, attr) is None:
                continue
            value = np.asarray(getattr(self, attr), dtype=float)
            if value.shape != shape:
                raise ArgumentError(attr, value, f"shape {shape}")
            object.__setattr__(self, attr, readonly(value))


#: An offset is confounded when the per-chain values explain at least this fraction of its posterior variance.
CONFOUNDED = 0.9
#: A value is named in a confounding when its standardised weight is at least this fraction of the largest.
NAMED = 0.25
#: At most this many values are named per confounded offset (the largest weights).
MAX_NAMED = 6
#: What separates a sensor's zero from the joint pattern's tilt and turn.
SEPARATION = (
    "a log with rows where a fixture holds the platform at a known attitude (known_alpha_j_deg, known_beta_j_deg, "
    "known_gamma_j_deg), in the same run as the motion, so that the offset is the sensor minus the known attitude"
)
_ANGLES = ("alpha", "beta", "gamma")


@dataclass(frozen=True)
class Confounding(Record):
    """A sensor offset that the logs cannot tell apart from a combination of per-chain values.

    Attributes:
        sensor: the sensor angle, e.g. ``alpha_1`` (platform 1's α).
        explained: the fraction of the offset's posterior variance the per-chain values explain (R², 0 to 1): how
            much of what the offset may be is what the values may be.
        values: the values of that combination (standardised weight at least :data:`NAMED` of the largest, at most
            :data:`MAX_NAMED`), most first.
        weights: their standardised weights in the offset's regression on the values (signed, largest 1).
        separated_by: the extra log that tells them apart.
    """

    sensor: str
    explained: float
    values: tuple[str, ...]
    weights: tuple[float, ...]
    separated_by: str = SEPARATION


def confounded_pairs(covariance: np.ndarray, independent: np.ndarray, p: int) -> tuple[Confounding, ...]:
    """The first log's sensor offsets that trade with per-chain values, from the joint posterior covariance.

    For offset o and the values θ: R² = 1 − var(o | θ)/var(o), var(o | θ) = Σ_oo − Σ_oθ·Σ_θθ⁻¹·Σ_θo; the
    combination is the regression o ≈ Σ_oθ·Σ_θθ⁻¹·θ, each value's weight scaled by its posterior std.

    Args:
        covariance: the posterior covariance of [estimated values (p), offsets (6 per log)], SI.
        independent: the estimated values' entries of δ, (p,).
        p: how many values are estimated.

    Returns:
        The confounded offsets (R² ≥ :data:`CONFOUNDED`), platform 1 then 2, α β γ.
    """
    S_tt = covariance[:p, :p]
    labels = dv.names()
    out = []
    for j in range(2):
        for k in range(3):
            o = p + 3 * j + k
            S_ot = covariance[o, :p]
            beta = np.linalg.solve(S_tt, S_ot)
            explained = float(S_ot @ beta / covariance[o, o])
            if explained < CONFOUNDED:
                continue
            weight = beta * np.sqrt(np.diag(S_tt))
            weight = weight / np.abs(weight).max()
            named = np.flatnonzero(np.abs(weight) >= NAMED)
            named = named[np.argsort(-np.abs(weight[named]))][:MAX_NAMED]
            out.append(
                Confounding(
                    f"{_ANGLES[k]}_{j + 1}",
                    round(explained, 6),
                    tuple(labels[independent[c]] for c in named),
                    tuple(round(float(weight[c]), 4) for c in named),
                )
            )
    return tuple(out)


@dataclass(frozen=True, eq=False)
class Calibration:
    """A calibrated machine and what the logs said of it.

    Attributes:
        machine: the calibrated machine (the start with the calibrated chains).
        start: the machine the prior was centred on (the drawing, or the starting file's chains).
        theta, theta_std: each per-chain deviation δ and its posterior standard deviation in [m], (51,); a value
            kept at its prior has its prior's.
        covariance: the posterior covariance of the estimated values in [m²], in the order of ``structure.independent``.
        structure: which combinations the logs can see.
        determined: per value, whether the logs determined it (posterior std ≤ DETERMINED × prior's), (51,).
        prior: the prior standard deviation in [m].
        offsets: each log's sensor offsets in [rad], (K, 2, 3) (zero when not estimated).
        noise: each sensor angle's residual standard deviation in [rad], (2, 3).
        residual_rms: per log, the RMS residual per sensor angle in [rad] with the calibrated machine, (K, 2, 3).
        start_rms: the same with the starting machine (offsets fitted alike when estimated), (K, 2, 3).
        logs: the logs' names.
        samples: samples fitted.
        iterations: Gauss–Newton iterations made.
        confounded: with sensor offsets, each offset and the values it trades with (:class:`Confounding`); empty
            without offsets, or when fixture rows pinned them.
    """

    machine: Parameters
    start: Parameters
    theta: np.ndarray
    theta_std: np.ndarray
    covariance: np.ndarray
    structure: Structure
    determined: np.ndarray
    prior: float
    offsets: np.ndarray
    noise: np.ndarray
    residual_rms: np.ndarray
    start_rms: np.ndarray
    logs: tuple[str, ...]
    samples: int
    iterations: int
    confounded: tuple[Confounding, ...] = ()

    @property
    def unseen(self) -> list[str]:
        """The values no log of this kind can see (kept at their prior), by name."""
        return [dv.names()[k] for k in self.structure.dependent]

    @property
    def weak(self) -> list[str]:
        """The estimated values these logs barely saw (posterior std above DETERMINED of the prior's), by name."""
        labels = dv.names()
        return [labels[k] for k in self.structure.independent if not self.determined[k]]

    def prediction_std(self, q: np.ndarray, up_to_constant: bool = False) -> np.ndarray:
        """The standard deviation in [rad] of the predicted attitudes q (N, 2, 3) [rad] from θ's uncertainty, (N, 2, 3).

        The estimated values θ₁ (posterior covariance, offsets' trade included) and the values kept at their prior
        θ₂: the estimate is of θ₁ + C·θ₂, so a prediction moves by (J₂ − J₁·C)·θ₂ with θ₂ ~ N(start, prior²). Without
        sensor offsets that is zero (C folds θ₂ exactly); with them it is the constant part of θ₂'s effect, which the
        fitted offsets took: the attitude's error that the logs cannot tell from a sensor's zero.

        Args:
            q: both platforms' attitudes in [rad], (N, 2, 3) (a motion: its samples together).
            up_to_constant: the spread of the prediction about its mean over the samples (what a log whose sensors
                have their own unknown offset can check), instead of the attitude's own.
        """
        q = np.asarray(q, dtype=float)
        J = attitude_jacobian(self.machine, q)
        J1 = J[..., self.structure.independent]
        K = J[..., self.structure.dependent] - np.einsum("njkp,pd->njkd", J1, self.structure.coefficients)
        if up_to_constant:
            J1, K = J1 - J1.mean(axis=0), K - K.mean(axis=0)
        variance = np.einsum("njkp,pr,njkr->njk", J1, self.covariance, J1) + self.prior**2 * (K**2).sum(axis=-1)
        return np.sqrt(variance)


def _checked_attitudes(machine: Parameters, log: CalibrationLog, guess: np.ndarray, what: str) -> np.ndarray:
    try:
        return attitudes(machine, log.carriages, guess, log.t, log.name)
    except PoseError as error:
        raise CalibrationError(f"{log.name}, t = {error.time:.6g} s: {what} ({error.reason})") from None


def _fit_offsets(residual: np.ndarray) -> np.ndarray:
    return residual.mean(axis=0)


def prediction_errors(
    machine: Parameters, log: CalibrationLog, offsets: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sensors' residuals against a machine's predictions from the log's carriages.

    Args:
        machine: the machine.
        log: the log.
        offsets: fit (and take out) a constant offset per sensor angle first.

    Returns:
        residuals (N, 2, 3) in [rad], the offsets taken out (2, 3) in [rad], the predictions (N, 2, 3) in [rad].
    """
    q = _checked_attitudes(machine, log, log.sensors, "the machine does not reach the logged carriages")
    r = log.sensors - q
    o = _fit_offsets(r) if offsets else np.zeros((2, 3))
    return r - o, o, q


def _check_agreement(machine: Parameters, log: CalibrationLog, offsets: bool) -> tuple[np.ndarray, np.ndarray]:
    """The starting machine's predictions and RMS residual, refusing a sensor that disagrees with the encoders beyond reach."""
    r, _, q = prediction_errors(machine, log, offsets)
    worst = np.abs(r).max(axis=0)
    if np.any(worst > MAX_DISAGREEMENT):
        j, k = np.unravel_index(int(np.argmax(worst)), worst.shape)
        n = int(np.argmax(np.abs(r[:, j, k])))
        column = f"{('alpha', 'beta', 'gamma')[k]}_{j + 1}_deg"
        raise CalibrationError(
            f"{log.name}, t = {log.t[n]:.6g} s, column '{column}': the sensor reads {math.degrees(log.sensors[n, j, k]):.4g}°, "
            f"the encoders put the platform at {math.degrees(q[n, j, k]):.4g}° (more than {math.degrees(MAX_DISAGREEMENT):g}° "
            "apart: a wrong column, unit or sensor; no per-chain deviation explains it)"
        )
    return q, np.sqrt((r**2).mean(axis=0))


def calibrate(
    logs: Sequence[CalibrationLog],
    start: Parameters,
    prior: float = DEFAULT_PRIOR,
    offsets: bool = False,
    structure_of: Structure | None = None,
) -> Calibration:
    """Calibrate the per-chain values from logs of the encoders and both attitude sensors.

    Args:
        logs: the logs fitted together.
        start: the machine the prior is centred on (the drawing, or a file's chains).
        prior: prior standard deviation of every per-chain value in [m].
        offsets: estimate a constant offset per sensor angle and log (``--sensor-offset per-log``); a log's
            ``known`` rows (a fixture) pin its offsets.
        structure_of: the combinations to estimate (default: :func:`~hipsim.stations.sensitivity.structure` of
            ``start`` without offsets: what the offsets imitate is estimated with its prior, the trade in the posterior).

    Raises:
        CalibrationError: a sensor far from the encoders, a machine leaving the workspace, no convergence.
    """
    if not logs:
        raise ArgumentError("logs", logs, "at least one calibration log")
    if not (math.isfinite(prior) and prior > 0):
        raise ArgumentError("prior", prior, "a positive standard deviation in m")
    # With offsets: the values the sensors see up to the offsets' trade are estimated all the same (module docstring).
    seen = structure_of or structure(start, False)
    ind = seen.independent
    theta0 = dv.deviation(start)
    K = len(logs)
    p = ind.size
    n_off = 6 * K if offsets else 0
    x0 = np.concatenate([theta0[ind], np.zeros(n_off)])
    # Per platform: the positions in x of its estimated values (own) and their columns among its 24 (local).
    own, local = [], []
    for j in (1, 2):
        platform = list(dv.platform_columns(j))
        mine = [c for c, k in enumerate(ind) if k in platform]
        own.append(np.array(mine, dtype=int))
        local.append(np.array([platform.index(ind[c]) for c in mine], dtype=int))
    prior_info = np.concatenate([np.full(p, prior**-2), np.full(n_off, OFFSET_PRIOR**-2)])
    floor = np.concatenate([np.full(p, STEP_FLOOR), np.full(n_off, OFFSET_STEP_FLOOR)])
    checked = [_check_agreement(start, log, offsets) for log in logs]
    starts = [q for q, _ in checked]
    start_rms = np.array([rms for _, rms in checked])
    x = x0.copy()
    noise = np.full((2, 3), START_NOISE)
    theta = theta0.copy()
    converged = False
    iterations = 0
    for iterations in range(1, MAX_ITERATIONS + 1):
        theta[ind] = x[:p]
        machine = dv.machine(start, theta)
        A = np.diag(prior_info)
        b = -prior_info * (x - x0)
        rows = []
        for k, log in enumerate(logs):
            q = _checked_attitudes(machine, log, starts[k], "the calibrated machine leaves the workspace")
            starts[k] = q
            o = x[p + 6 * k : p + 6 * k + 6].reshape(2, 3) if offsets else np.zeros((2, 3))
            # Each platform's rows see only its own values: ∂q_j/∂δ_b per platform, (N, 3, its estimated values).
            blocks = [platform_attitude_jacobian(machine, q[:, j], j + 1, q[:, 1])[..., local[j]] for j in (0, 1)]
            rows.append((log.sensors - o - q, blocks))
        residual_rms = np.array(
            [np.sqrt((r**2).mean(axis=0)) for r, _ in rows]
        )  # the last iteration's: the step is tiny
        if iterations > 1:  # the noise from this iteration's residuals (the first's are the start's, too large)
            squares = sum((r**2).sum(axis=0) for r, _ in rows)
            noise = np.sqrt(np.maximum(squares / sum(len(r) for r, _ in rows), 1e-24))
        w = 1.0 / noise**2  # (2, 3)
        for k, (r, blocks) in enumerate(rows):
            for j, Jj in enumerate(blocks):
                Jw = Jj * w[j][None, :, None]
                # einsum, not a matrix product: threaded BLAS on these thin matrices stalls on a busy machine.
                A[np.ix_(own[j], own[j])] += np.einsum("nkp,nkr->pr", Jw, Jj)
                b[own[j]] += np.einsum("nkp,nk->p", Jw, r[:, j])
                if offsets:
                    rows_j = p + 6 * k + 3 * j + np.arange(3)
                    cross = Jw.sum(axis=0)  # (3, p_j): ∂r/∂o = −I per sensor angle
                    A[np.ix_(own[j], rows_j)] += cross.T
                    A[np.ix_(rows_j, own[j])] += cross
                    A[rows_j, rows_j] += len(r) * w[j]
                    b[rows_j] += (r[:, j] * w[j]).sum(axis=0)
                    known = logs[k].known
                    if known is not None:  # the fixture's rows: sensor − o − known, no per-chain value
                        held = np.isfinite(known[:, j])  # (N, 3)
                        o = x[rows_j]
                        r_known = np.where(held, logs[k].sensors[:, j] - o - np.nan_to_num(known[:, j]), 0.0)
                        A[rows_j, rows_j] += held.sum(axis=0) * w[j]
                        b[rows_j] += (r_known * w[j]).sum(axis=0)
        del rows
        try:
            step = np.linalg.solve(A, b)
            covariance = np.linalg.inv(A)
        except np.linalg.LinAlgError:
            raise CalibrationError("the calibration's normal equations are singular") from None
        x = x + step
        if not np.all(np.isfinite(x)):
            raise CalibrationError(f"the calibration diverged at iteration {iterations}")
        if iterations > 1 and np.all(np.abs(step) <= np.maximum(STEP_TOL * np.sqrt(np.diag(covariance)), floor)):
            converged = True
            break
    if not converged:
        raise CalibrationError(
            f"the calibration did not converge in {MAX_ITERATIONS} iterations (the logs may not excite the machine, or the "
            "start is too far from it: try --prior or a richer motion, hipsim excite --for calibration)"
        )
    theta[ind] = x[:p]
    machine = dv.machine(start, theta)
    theta_std = np.full(dv.COUNT, prior)
    theta_std[ind] = np.sqrt(np.diag(covariance)[:p])
    determined = np.zeros(dv.COUNT, dtype=bool)
    determined[ind] = theta_std[ind] <= DETERMINED * prior
    offsets_out = x[p:].reshape(K, 2, 3) if offsets else np.zeros((K, 2, 3))
    confounded = confounded_pairs(covariance, ind, p) if offsets else ()
    return Calibration(
        machine=machine,
        start=start,
        theta=readonly(theta),
        theta_std=readonly(theta_std),
        covariance=readonly(covariance[:p, :p]),
        structure=seen,
        determined=readonly(determined),
        prior=prior,
        offsets=readonly(offsets_out),
        noise=readonly(noise),
        residual_rms=readonly(residual_rms),
        start_rms=readonly(start_rms),
        logs=tuple(log.name for log in logs),
        samples=sum(len(log.t) for log in logs),
        iterations=iterations,
        confounded=confounded,
    )

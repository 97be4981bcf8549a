"""Identification of the machine's dynamic parameters from measured motor torques: the fit.

What is estimated are the base parameters (:mod:`hipsim.rig.identification.base`): the fixed
combinations of the :data:`~hipsim.rig.identification.quantities.QUANTITIES` that motor torques
can ever determine, defined by the machine's geometry alone, so every
identification of one machine reports the same quantities with the same
definitions, whatever the logs.

The fit (:func:`identify`). Each log's regressor rows and torques go
through the log's own low-pass (the torques already have), so model and
measurement share one bandwidth, and are kept every D-th sample (decimation
to four times the cutoff); the samples around each motor's reversals are left
out of that motor's rows (:func:`hipsim.rig.identification.regressor.log_rows`). Rows are
accumulated log by log and chunk by chunk into the triangular factor of a QR
decomposition of [Y | τ] per motor, so memory does not grow with the log.

Bayesian least squares. Every base parameter has a prior N(θ_b0, s_b²) from
the starting machine (:mod:`hipsim.rig.identification.prior`); each motor's rows are weighted
by the inverse of its residual's standard deviation (from a first,
unweighted fit), the information divided by the rows per independent row:
those the low-pass leaves (rate/(2·cutoff) after decimation), or those of the
model error the residual carries besides the noise, whichever is more
(rate/(2·:data:`~hipsim.rig.identification.regressor.MODEL_ERROR_BANDWIDTH`): 4.2 at 1 kHz and 20 Hz;
:func:`~hipsim.rig.identification.regressor.rows_per_independent_row`), so that a 95 % band covers the truth on held-out runs, and

    θ̂_b = (YᵀWY + Σ₀⁻¹)⁻¹ (YᵀWτ + Σ₀⁻¹θ_b0),   Σ_post = (YᵀWY + Σ₀⁻¹)⁻¹.

A base parameter the logs do not see stays at its prior with its prior
standard deviation (exactly, for one the logs cannot see at all) and, its
prior being its own, never biases the others; rich logs make the prior
irrelevant. A base parameter counts as *determined* by the logs when its
posterior standard deviation is at most :data:`DETERMINED` of its prior's;
logs that determine none are refused, and so are logs of no more rows than base parameters
(the unweighted fit would match every row: no residual level to weigh the motors by). Per base parameter the result says how
far the data moved it from its prior, in prior standard deviations.

The identified machine: the parameters folded into others keep their
starting values, each base parameter's own takes the rest. If that machine is
not physically consistent, the fit (data and prior) is solved again under the
constraints of :mod:`hipsim.rig.identification.consistency`; and it is refused if a value is
outside the plausible ranges of this class of machine (:func:`hipsim.machine.parameters.implausible`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg

from ...exceptions import IdentificationError
from ...machine.parameters import Parameters, implausible, implausible_message
from ..compare import Comparison, compare_log
from ..logs.log import Log
from .base import BaseParameters, base_parameters
from .consistency import consistent, violations
from .identified_file import IDENTIFIED_MARK, FileProvenance, identified_toml, write_identified_file
from .prior import HELD
from .prior import prior as make_prior
from .quantities import QUANTITIES, standard_values, with_values
from .regressor import column_condition, log_rows, rows_per_independent_row
from .summary import EstimateRow, HeldOutLog, HeldRow, IdentificationSummary, IdentifiedRow
from .validation import ValidationNote, training_envelope, validation_note

__all__ = [
    "DETERMINED",
    "BaseEstimate",
    "Identification",
    "IdentifiedQuantity",
    "identify",
]

#: A base parameter is determined by the logs when its posterior standard deviation is at most this of its prior's.
DETERMINED = 0.5


@dataclass(frozen=True)
class IdentifiedQuantity:
    """One determined base parameter, as the file's comment header lists it.

    Attributes:
        label: the parameter that names it (``m_L``).
        key: its parameter-file key.
        unit: its unit (file units).
        value: the identified value in file units.
        relative_std: its relative standard deviation (0.01 = 1 %; large for a value near zero).
        std: its standard deviation in file units.
        terms: the other parameters it combines, (label, coefficient in file units, coefficient's unit).
    """

    label: str
    key: str
    unit: str
    value: float
    relative_std: float
    std: float
    terms: tuple[tuple[str, float, str], ...] = ()

    def expression(self, terms: int | None = 4) -> str:
        """ "m_L + 0.5·m_l": the combination, its first ``terms`` terms (None: all) and how many more there are."""
        text = self.label
        shown = self.terms if terms is None else self.terms[:terms]
        for label, coefficient, unit in shown:
            sign = "−" if coefficient < 0 else "+"
            text += f" {sign} {abs(coefficient):.10g}{' ' + unit if unit else ''}·{label}"
        if len(shown) < len(self.terms):
            text += f" + … ({len(self.terms) - len(shown)} more)"
        return text


@dataclass(frozen=True)
class BaseEstimate:
    """One base parameter's estimate, with its prior (file units).

    Attributes:
        name: the standard parameter that names it (``m_L``).
        definition: the combination it stands for (``m_L + 0.5·m_l``).
        key, unit: its standard parameter's file key and unit.
        value, std: posterior mean and standard deviation.
        prior, prior_std: prior mean (the starting machine's) and standard deviation.
    """

    name: str
    definition: str
    key: str
    unit: str
    value: float
    std: float
    prior: float
    prior_std: float

    @property
    def determined(self) -> bool:
        """The logs determine it: posterior standard deviation at most :data:`DETERMINED` of the prior's."""
        return self.std <= DETERMINED * self.prior_std

    @property
    def shift(self) -> float:
        """How far the data moved it from its prior, in prior standard deviations."""
        return (self.value - self.prior) / self.prior_std if self.prior_std > 0 else 0.0

    def row(self) -> EstimateRow:
        """The estimate as the summary's row (with :attr:`determined` and :attr:`shift`)."""
        return EstimateRow(
            self.name,
            self.definition,
            self.key,
            self.unit,
            self.value,
            self.std,
            self.prior,
            self.prior_std,
            self.determined,
            self.shift,
        )


@dataclass(frozen=True, eq=False)
class Identification:
    """What :func:`identify` found.

    Attributes:
        params: the identified, physically consistent machine (what :meth:`write_toml` writes).
        start: the starting machine.
        base: the machine's base parameters (their definitions).
        estimates: each base parameter's estimate and prior, in the order of ``base``.
        covariance: the base parameters' posterior covariance in file units, (r, r).
        condition_number: of the weighted regressor of the determined base parameters (unit-norm columns).
        residual_rms: RMS residual torque per motor in [N·m], (3,), of the fit (filtered, decimated rows).
        rows: samples used, all motors.
        logs: the logs fitted, by name.
        lever_spin: the model's lever spin.
        active_constraints: the physical-consistency constraints the solution sits on.
        validation: per held-out log, (the identified machine's comparison, the starting machine's).
        notes: per held-out log, what :mod:`hipsim.rig.identification.validation` says of it (per-phase errors, envelope warnings).
        torque_rms: RMS measured torque per motor in [N·m], (3,), over the rows fitted (the scale of the residual gate).
    """

    params: Parameters
    start: Parameters
    base: BaseParameters
    estimates: tuple[BaseEstimate, ...]
    covariance: np.ndarray
    condition_number: float
    residual_rms: np.ndarray
    rows: int
    logs: tuple[str, ...]
    lever_spin: bool
    active_constraints: tuple[str, ...] = ()
    validation: tuple[tuple[Comparison, Comparison], ...] = field(default=())
    notes: tuple[ValidationNote, ...] = field(default=())
    torque_rms: np.ndarray | None = None

    @property
    def quantities(self) -> tuple[IdentifiedQuantity, ...]:
        """The base parameters the logs determine (the rest stay near their priors)."""
        out = []
        for estimate, parameter in zip(self.estimates, self.base.parameters):
            if estimate.determined:
                relative = estimate.std / abs(estimate.value) if estimate.value else math.inf
                out.append(
                    IdentifiedQuantity(
                        estimate.name,
                        estimate.key,
                        estimate.unit,
                        estimate.value,
                        relative,
                        estimate.std,
                        parameter.terms,
                    )
                )
        return tuple(out)

    @property
    def held(self) -> tuple[tuple[str, str, float, str], ...]:
        """What the logs did not determine: (label, reason, value, unit), file units."""
        theta = standard_values(self.params)
        out = [
            (
                e.name,
                f"not determined by these logs: near its prior {e.prior:.6g} ± {e.prior_std:.2g} (posterior std {e.std:.2g})",
                e.value,
                e.unit,
            )
            for e in self.estimates
            if not e.determined
        ]
        for j in self.base.dependent:
            into = [p.label for p in self.base.parameters if self.base.beta[p.index, j]]
            reason = (
                f"folded into {', '.join(into)} (starting value kept)"
                if into
                else "no effect on the motor torques (starting value kept)"
            )
            out.append((QUANTITIES[j].label, reason, float(theta[j] / QUANTITIES[j].scale), QUANTITIES[j].unit))
        return tuple(out)

    def combinations(self, params: Parameters) -> np.ndarray:
        """The base parameters' values (file units) for another machine, e.g. the true one of a synthetic test."""
        return self.base.values(params) / self.base.scale

    def table(self) -> dict[str, Any]:
        """The ``[identification]`` table of the parameter file: base parameters, prior, covariance, logs, validation."""
        e = self.estimates
        table: dict[str, Any] = {
            "logs": list(self.logs),
            "start": self.start.source,
            "lever_spin": self.lever_spin,
            "base": [x.name for x in e],
            "definitions": [x.definition for x in e],
            "keys": [x.key for x in e],
            "units": [x.unit for x in e],
            "value": [x.value for x in e],
            "std": [x.std for x in e],
            "prior": [x.prior for x in e],
            "prior_std": [x.prior_std for x in e],
            "determined": [x.determined for x in e],
            "covariance": [list(map(float, row)) for row in self.covariance],
            "residual_rms_Nmm": [float(r * 1e3) for r in self.residual_rms],
        }
        if self.validation:
            table["validation_logs"] = [identified.log.name for identified, _ in self.validation]
            table["validation_rms_error_Nmm"] = [
                [identified.motor_errors()[i]["rms_error_Nmm"] for i in "123"] for identified, _ in self.validation
            ]
            table["validation_start_rms_error_Nmm"] = [
                [start.motor_errors()[i]["rms_error_Nmm"] for i in "123"] for _, start in self.validation
            ]
        return table

    def summary(self) -> IdentificationSummary:
        """Everything a script needs, in file units, torques in [N·mm] (:mod:`hipsim.rig.identification.summary`)."""
        validation = None
        if self.validation:
            notes = self.notes or (None,) * len(self.validation)
            validation = tuple(
                HeldOutLog(
                    identified.log.name,
                    identified.summary().motors,
                    start.summary().motors,
                    None if note is None else note.summary(),
                )
                for (identified, start), note in zip(self.validation, notes)
            )
        return IdentificationSummary(
            logs=tuple(self.logs),
            starting_parameters=self.start.source,
            lever_spin=self.lever_spin,
            rows=self.rows,
            condition_number=float(self.condition_number),
            residual_rms_Nmm={str(i + 1): float(self.residual_rms[i] * 1e3) for i in range(3)},
            base_parameters=tuple(e.row() for e in self.estimates),
            identified=tuple(
                IdentifiedRow(q.expression(None), q.key, q.value, q.std, q.unit, q.relative_std)
                for q in self.quantities
            ),
            held=tuple(HeldRow(label, reason, value, unit) for label, reason, value, unit in self.held),
            active_constraints=tuple(self.active_constraints),
            validation=validation,
        )

    def comments(self) -> list[str]:
        """The file's comment header, for people (programs read the tables): the logs, the model, each value."""
        header = [
            f"{IDENTIFIED_MARK}: a parameter file every hipsim command accepts (--params).",
            f"# From the logs: {', '.join(self.logs)} ({self.rows} samples per motor after filtering and decimation).",
            f"# Starting parameters: {self.start.source}.",
            f"# Model: analytic, lever spin {'on' if self.lever_spin else 'off'}; regressor condition number {self.condition_number:.4g}.",
            "# Residual RMS per motor: "
            + ", ".join(f"M{i + 1} {self.residual_rms[i] * 1e3:.3g} N·mm" for i in range(3))
            + ".",
            "#",
            "# Identified (value, relative standard deviation); each base parameter is a fixed combination (hipsim identify --base);",
            "# the parameters it folds in keep their starting values below and the first takes the rest:",
        ]
        for q in self.quantities:
            header.append(
                f"#   {q.expression(None)} = {q.value:.6g} ± {q.std:.2g} {q.unit} ({_percent(q.relative_std)})".replace(
                    "  ", " "
                )
            )
        if self.held:
            header.append("# Not identified from these logs:")
            for label, reason, value, unit in self.held:
                header.append(f"#   {label} = {value:.6g} {unit}: {reason}")
        if self.active_constraints:
            header.append("# Physical consistency constraints active: " + "; ".join(self.active_constraints) + ".")
        if self.validation:
            header.append("# Validation (RMS error of the motor torque, identified vs starting parameters):")
            for identified, start in self.validation:
                a, b = identified.motor_errors(), start.motor_errors()
                parts = [
                    f"M{i} {a[i]['rms_error_Nmm']:.3g} vs {b[i]['rms_error_Nmm']:.3g} N·mm" for i in ("1", "2", "3")
                ]
                header.append(f"#   {identified.log.name}: " + ", ".join(parts))
        header.append(
            "# The [identification] table at the end: base parameters, prior and posterior covariance (file units)."
        )
        return header

    def toml(self, provenance: FileProvenance | None = None) -> str:
        """The identified machine as a parameter file (:mod:`~hipsim.rig.identification.identified_file`).

        Args:
            provenance: what made it (the ``[identification.provenance]`` table); None for none.
        """
        return identified_toml(self.params, self.table(), provenance, self.comments())

    def write_toml(self, path: str | Path, provenance: FileProvenance | None = None) -> Path:
        """Write :meth:`toml` atomically. Returns the path."""
        return write_identified_file(path, self.params, self.table(), provenance, self.comments())


# --- The fit ----------------------------------------------------------------------------------


@dataclass
class _Accumulator:
    """The triangular factor of [Y_i | τ_i] per motor, and the row count."""

    size: int
    R: list[np.ndarray] = field(default_factory=list)
    rows: Any = 0  # per motor, (3,)
    inflation: float = 0.0  # Σ rows × (samples per independent sample)

    def add(self, Y: np.ndarray, tau: np.ndarray, use: np.ndarray, inflation: float) -> None:
        if not self.R:
            self.R = [np.zeros((0, self.size + 1)) for _ in range(3)]
            self.rows = np.zeros(3, dtype=int)
        for i in range(3):
            rows = use[:, i]
            stacked = np.vstack([self.R[i], np.column_stack([Y[rows, i, :], tau[rows, i]])])
            self.R[i] = scipy.linalg.qr(stacked, mode="r", check_finite=False)[0][: self.size + 1]
            if self.R[i].shape[0] < self.size + 1:
                self.R[i] = np.vstack([self.R[i], np.zeros((self.size + 1 - self.R[i].shape[0], self.size + 1))])
        self.rows = self.rows + use.sum(axis=0)
        self.inflation += use.sum() * inflation


def _condition(A: np.ndarray) -> float:
    if A.shape[1] == 0:
        return math.nan
    return column_condition(A[:, np.linalg.norm(A, axis=0) > 0])  # a column the logs never excite is left out


def _plausible(params: Parameters, theta: np.ndarray, logs: tuple[str, ...]) -> None:
    """Refuse an identified machine outside the plausible ranges of this class of machine (:func:`hipsim.machine.parameters.implausible`)."""
    found = implausible(with_values(params, theta))
    if found:
        key, value, plausible = found[0]
        raise IdentificationError(
            f"the identified machine is implausible: {implausible_message(key, value, plausible)}; "
            "the logs and the model disagree (check the log's units, torque constant and sign convention); nothing written",
            logs,
        )


def identify(
    logs: Sequence[Log],
    params: Parameters,
    validate: Sequence[Log] = (),
    lever_spin: bool = True,
    fixed: Sequence[str] = (),
    prior: Mapping[str, Any] | None = None,
    prior_source: str = "prior",
) -> Identification:
    """Identify the base parameters from logs of motion, load and motor torque (module docstring).

    Args:
        logs: the logs to fit (:func:`hipsim.rig.load_log`, or built from arrays), or logs
            of any length read in pieces (:class:`~hipsim.rig.logs.log.LogPieces`: memory then does
            not grow with the log, the fit is the same to round-off).
        params: the starting machine: its geometry and friction radii are used,
            and its values are the prior's means.
        validate: held-out logs (either kind) to predict with the identified and the starting machine.
        lever_spin: the model's levers spin as their universal joints impose (default) or not.
        fixed: parameters to hold at their starting values (a prior of zero uncertainty), by label, key or
            key prefix (``"lever"``, ``"friction.ujoint"``, ``"m_l"``).
        prior: prior standard deviations by parameter (:mod:`hipsim.rig.identification.prior`): a number in the file's
            unit or a text such as ``"10 %"``; None for the defaults.
        prior_source: what to call ``prior`` in messages (a file, ``--prior``).

    Returns:
        The identification.

    Raises:
        IdentificationError: no logs, too few samples, logs that determine nothing, or an implausible result.
        ParameterError: a bad prior.
        PoseError: a logged pose out of reach or singular, naming the log and time.
    """
    logs = list(logs)
    if not logs:
        raise IdentificationError("identification needs at least one log")
    names = tuple(log.name for log in logs)
    P = len(QUANTITIES)
    base = base_parameters(params, lever_spin)
    entries = dict(prior or {})
    for name in fixed:
        entries[name] = 0.0
    belief = make_prior(base, params, entries, prior_source)
    theta0 = standard_values(params)
    sizes = np.array([abs(theta0[k]) if theta0[k] != 0 else q.nominal for k, q in enumerate(QUANTITIES)])
    index = base.index
    r = len(index)

    accumulator = _Accumulator(P)
    for log in logs:
        inflation = rows_per_independent_row(log)
        for Y, tau, use in log_rows(params, log, lever_spin):
            accumulator.add(Y, tau, use, inflation)
    rows_per_motor = np.asarray(accumulator.rows)
    if rows_per_motor.sum() <= 3:
        raise IdentificationError(f"{int(rows_per_motor.sum())} samples are too few to identify anything", names)
    R = accumulator.R  # per motor, (P + 1, P + 1): columns θ then τ
    rows = int(rows_per_motor.sum())
    if rows <= r:
        # The unweighted fit would match every row, leaving no residual to weigh the motors by (its round-off would).
        raise IdentificationError(
            f"{rows} samples are too few to identify {r} base parameters and measure the noise (more than {r} needed)",
            names,
        )
    inflation = accumulator.inflation / rows

    # Scaled deviations from the prior: x = (θ_b − θ_b0)/s_b, prior N(0, 1).
    def scaled(Ri):
        return Ri[:, index] * belief.std, Ri[:, P] - Ri[:, index] @ belief.mean

    # Unweighted first, for each motor's residual level (minimum-norm: what the data leave free stays at the prior).
    parts = [scaled(Ri) for Ri in R]
    x = np.linalg.lstsq(np.vstack([A for A, _ in parts]), np.concatenate([z for _, z in parts]), rcond=1e-12)[0]
    sigma = np.array([np.linalg.norm(A @ x - z) / math.sqrt(max(n, 1)) for (A, z), n in zip(parts, rows_per_motor)])
    sigma = np.maximum(sigma, 1e-12 * max(sigma.max(), 1e-300))
    if sigma.max() == 0 or not np.all(np.isfinite(sigma)):
        sigma = np.ones(3)
    weights = 1.0 / sigma
    Rw = scipy.linalg.qr(np.vstack([w * Ri for w, Ri in zip(weights, R)]), mode="r", check_finite=False)[0][: P + 1]
    Rw = Rw / math.sqrt(inflation)  # information per independent sample
    A, z = scaled(Rw)
    information = A.T @ A
    factor = scipy.linalg.cho_factor(information + np.eye(r))
    x = scipy.linalg.cho_solve(factor, A.T @ z)
    covariance_x = scipy.linalg.cho_solve(factor, np.eye(r))
    theta_b = belief.mean + belief.std * x
    covariance = covariance_x * np.outer(belief.std, belief.std)
    std = np.sqrt(np.diag(covariance))
    if np.all(std > (1 - 1e-3) * belief.std):
        raise IdentificationError(
            "these logs determine none of the base parameters (is anything moving, and is the torque logged?)", names
        )

    theta = base.standard(theta_b, theta0)
    active: tuple[str, ...] = ()
    if violations(theta):
        # Data and prior rows over the standard parameters, solved under the constraints.
        T = base.transform
        rows_all = np.vstack([Rw[:, :P], T / belief.std[:, None]])
        rhs = np.concatenate([Rw[:, P], belief.mean / belief.std])
        free = [j for j in base.dependent if belief.standard[j] > 10 * HELD * sizes[j]]  # held ones stay exactly
        theta, active = consistent(rows_all, rhs, theta, index, free, theta0, sizes)
        theta_b = T @ theta
    _plausible(params, theta, names)
    # The residual of the solution (constrained or not) against the noise the weights assumed: never narrower than it says.
    chi2 = float(np.sum((Rw[:, :P] @ theta - Rw[:, P]) ** 2)) * inflation / max(rows - r, 1)
    if chi2 > 1.0:  # the data's information shrinks by χ²; what the data do not see keeps its prior exactly
        covariance = scipy.linalg.cho_solve(
            scipy.linalg.cho_factor(information / chi2 + np.eye(r)), np.eye(r)
        ) * np.outer(belief.std, belief.std)
        std = np.sqrt(np.diag(covariance))

    scale = base.scale
    determined = std <= DETERMINED * belief.std
    estimates = tuple(
        BaseEstimate(
            p.label,
            p.definition,
            p.key,
            p.unit,
            float(theta_b[k] / scale[k]),
            float(std[k] / scale[k]),
            float(belief.mean[k] / scale[k]),
            float(belief.std[k] / scale[k]),
        )
        for k, p in enumerate(base.parameters)
    )
    residual = np.array(
        [np.linalg.norm(Ri[:, :P] @ theta - Ri[:, P]) / math.sqrt(max(n, 1)) for Ri, n in zip(R, rows_per_motor)]
    )
    identified = with_values(params, theta, source=f"identified from {', '.join(names)}")
    validation = tuple(
        (compare_log(identified, log, lever_spin), compare_log(params, log, lever_spin)) for log in validate
    )
    notes: tuple[ValidationNote, ...] = ()
    if validate:
        training = training_envelope(logs)
        notes = tuple(validation_note(a, b, log, training) for (a, b), log in zip(validation, validate))
    return Identification(
        identified,
        params,
        base,
        estimates,
        covariance / np.outer(scale, scale),
        _condition(Rw[:, index][:, determined]),
        residual,
        rows,
        names,
        lever_spin,
        active,
        validation,
        notes,
        np.array([np.linalg.norm(Ri[:, P]) / math.sqrt(max(n, 1)) for Ri, n in zip(R, rows_per_motor)]),
    )


def _percent(fraction: float) -> str:
    return f"±{100 * fraction:.2g} %" if fraction < 10 else "near zero"

"""Identification of the machine's dynamic parameters from measured motor torques: the fit.

What is identified are the :data:`~hipsim.rig.quantities.QUANTITIES` (the
platform's inertia about its centre, the sliders' mass, the screws' rotor
inertia, the levers' inertia about their centre and mass, and the friction
coefficients), through the linear model τ = Y·θ of
:mod:`hipsim.rig.regressor`.

The fit (:func:`identify`). Each log's regressor rows and torques go
through the log's own low-pass (the torques already have), so model and
measurement share one bandwidth ("parallel filtering"), and are then kept
every D-th sample (decimation to four times the cutoff); the samples
around each motor's reversals, where the real motion sticks and no model on
the filtered motion can follow (:func:`hipsim.rig.reversals.reversal_mask`),
are left out of that motor's rows (:func:`hipsim.rig.regressor.log_rows`). Rows are
accumulated log by log and chunk by chunk into the triangular factor of a
QR decomposition of [Y | τ] per motor, so memory does not grow with the log.
Weighted least squares: each motor's rows weighted by the inverse of its
residual's standard deviation from a first, unweighted fit.

Base parameters. Parameters that the data cannot tell apart are found
numerically: the columns are scaled to unit norm and taken in the order of
:data:`QUANTITIES` (platform, sliders, screws, levers, friction), each kept
when its distance from the span of the columns already kept exceeds
:data:`RANK_TOLERANCE` (a QR decomposition in that fixed order; with
pivoting the order would follow the column norms, and the base parameters
would change names from log to log). Then, as in Gautier's essential
parameters, the kept parameter with the largest standard deviation (relative
to its size, see Statistics) is dropped while it exceeds
``max_relative_std``: what is left are the identified quantities, each reported as the combination it stands for,
θ_k + Σ_j β_kj θ_j over the dropped parameters (β from the regression of
their columns on the kept ones; exact for dependent columns, e.g. the lever
mass, which regroups into the sliders and the platform inertia, or the screw
and guide Coulomb friction, which have the same column), never as separate
numbers.

Physical consistency. The identified machine's dropped parameters keep
their starting values and the kept ones take what the combinations leave;
if that machine is not physically consistent, the fit is solved again under
the constraints of :mod:`hipsim.rig.consistency`.

Statistics. The standard deviations come from the covariance σ²(YᵀWY)⁻¹
of the weighted fit, the residual variance σ² inflated by the samples per
independent sample that the low-pass leaves (rate/(2·cutoff) after
decimation): an approximation that treats the filtered residual as white
within the filter's band. A quantity is dropped when its σ exceeds
``max_relative_std`` of its size, max(|θ_k|, its starting value or, where
that is zero, a nominal value), so that a quantity known to be near zero
counts as identified; the relative standard deviation reported is σ/|θ_k|.
The condition number is that of the weighted regressor with unit-norm
columns (unit-free): ``condition_number`` over every parameter the data can
separate, ``condition_number_base`` over the identified quantities alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import scipy.linalg

from ..exceptions import HipsimError
from ..files import write_atomic
from ..machine.parameters import Parameters
from ..machine.toml_writer import parameter_toml
from .compare import Comparison, compare_log
from .consistency import consistent, violations
from .logs import Log
from .quantities import QUANTITIES, Quantity, friction_unit, standard_values, with_values
from .regressor import inflation as _inflation, log_rows, regressor, regressor_from_kinematics

__all__ = [
    "QUANTITIES",
    "RANK_TOLERANCE",
    "Identification",
    "IdentifiedQuantity",
    "Quantity",
    "friction_unit",
    "identify",
    "parameter_toml",
    "regressor",
    "regressor_from_kinematics",
    "standard_values",
    "with_values",
]

#: A column closer than this to the span of the columns before it (all scaled to unit norm) depends on them.
RANK_TOLERANCE = 1e-6
#: Default largest relative standard deviation of an identified quantity.
DEFAULT_MAX_RELATIVE_STD = 0.01


@dataclass(frozen=True)
class IdentifiedQuantity:
    """One identified quantity: a parameter, or the combination of parameters the data determine.

    Attributes:
        label: the parameter that names it (``m_L``).
        key: its parameter-file key.
        unit: its unit (file units).
        value: the identified value in file units.
        relative_std: its relative standard deviation (0.01 = 1 %; large for a value near zero).
        std: its standard deviation in file units.
        terms: the other parameters it combines, (label, coefficient in file units, coefficient's unit), largest first.
    """

    label: str
    key: str
    unit: str
    value: float
    relative_std: float
    std: float
    terms: tuple[tuple[str, float, str], ...] = ()

    def expression(self, terms: int | None = 4) -> str:
        """"m_L + 0.5·m_l": the combination, its largest ``terms`` terms (None: all) and how many more there are."""
        text = self.label
        shown = self.terms if terms is None else self.terms[:terms]
        for label, coefficient, unit in shown:
            sign = "−" if coefficient < 0 else "+"
            text += f" {sign} {abs(coefficient):.4g}{' ' + unit if unit else ''}·{label}"
        if len(shown) < len(self.terms):
            text += f" + … ({len(self.terms) - len(shown)} more)"
        return text


@dataclass(frozen=True, eq=False)
class Identification:
    """What :func:`identify` found.

    Attributes:
        params: the identified, physically consistent machine (what :meth:`write_toml` writes).
        start: the starting machine.
        quantities: the identified quantities (parameters or combinations), with relative standard deviations.
        held: parameters not identified, with the reason and the value kept (file units): (label, reason, value, unit).
        beta: the combination coefficients in SI, (P, P): base k = θ_k + Σ_j beta[k, j]·θ_j.
        base: indices of the identified quantities' parameters in :data:`QUANTITIES`.
        condition_number: of the regressor of every parameter the data can separate (unit-norm columns).
        condition_number_base: of the identified quantities' regressor alone.
        residual_rms: RMS residual torque per motor in [N·m], (3,), of the fit (filtered, decimated rows).
        rows: samples used per motor.
        logs: the logs fitted, by name.
        lever_spin: the model's lever spin.
        active_constraints: the physical-consistency constraints the solution sits on.
        validation: per held-out log, (the identified machine's comparison, the starting machine's).
    """

    params: Parameters
    start: Parameters
    quantities: tuple[IdentifiedQuantity, ...]
    held: tuple[tuple[str, str, float, str], ...]
    beta: np.ndarray
    base: tuple[int, ...]
    condition_number: float
    condition_number_base: float
    residual_rms: np.ndarray
    rows: int
    logs: tuple[str, ...]
    lever_spin: bool
    active_constraints: tuple[str, ...] = ()
    validation: tuple[tuple[Comparison, Comparison], ...] = field(default=())

    def combinations(self, params: Parameters) -> np.ndarray:
        """The identified quantities' values (file units) for another machine, e.g. the true one of a synthetic test."""
        theta = standard_values(params)
        out = []
        for k in self.base:
            value = theta[k] + self.beta[k] @ theta
            out.append(value / QUANTITIES[k].scale)
        return np.array(out)

    def summary(self) -> dict[str, Any]:
        """Everything a script needs, JSON-ready, in file units (torques in N·mm)."""
        out: dict[str, Any] = {
            "logs": list(self.logs),
            "starting_parameters": self.start.source,
            "lever_spin": self.lever_spin,
            "rows": self.rows,
            "condition_number": self.condition_number,
            "condition_number_base": self.condition_number_base,
            "residual_rms_Nmm": {str(i + 1): float(self.residual_rms[i] * 1e3) for i in range(3)},
            "identified": [
                {"quantity": q.expression(None), "key": q.key, "value": q.value, "std": q.std, "unit": q.unit, "relative_std": q.relative_std}
                for q in self.quantities
            ],
            "held": [{"quantity": label, "reason": reason, "value": value, "unit": unit} for label, reason, value, unit in self.held],
            "active_constraints": list(self.active_constraints),
        }
        if self.validation:
            out["validation"] = [
                {
                    "log": identified.log.name,
                    "identified": identified.motor_errors(),
                    "starting": start.motor_errors(),
                }
                for identified, start in self.validation
            ]
        return out

    def toml(self) -> str:
        """The identified machine as a parameter file, with a comment header saying what was identified from what."""
        header = [
            "# Identified by hipsim identify: a parameter file every hipsim command accepts (--params).",
            f"# From the logs: {', '.join(self.logs)} ({self.rows} samples per motor after filtering and decimation).",
            f"# Starting parameters: {self.start.source}.",
            f"# Model: analytic, lever spin {'on' if self.lever_spin else 'off'}; regressor condition number {self.condition_number:.4g}.",
            "# Residual RMS per motor: " + ", ".join(f"M{i + 1} {self.residual_rms[i] * 1e3:.3g} N·mm" for i in range(3)) + ".",
            "#",
            "# Identified (value, relative standard deviation); each combination is what the data determine,",
            "# the parameters it combines keep their starting values below and the first takes the rest:",
        ]
        for q in self.quantities:
            header.append(f"#   {q.expression(None)} = {q.value:.6g} ± {q.std:.2g} {q.unit} ({_percent(q.relative_std)})".replace("  ", " "))
        if self.held:
            header.append("# Not identified from these logs (starting value kept):")
            for label, reason, value, unit in self.held:
                header.append(f"#   {label} = {value:.6g} {unit}: {reason}")
        if self.active_constraints:
            header.append("# Physical consistency constraints active: " + "; ".join(self.active_constraints) + ".")
        if self.validation:
            header.append("# Validation (RMS error of the motor torque, identified vs starting parameters):")
            for identified, start in self.validation:
                a, b = identified.motor_errors(), start.motor_errors()
                parts = [f"M{i} {a[i]['rms_error_Nmm']:.3g} vs {b[i]['rms_error_Nmm']:.3g} N·mm" for i in ("1", "2", "3")]
                header.append(f"#   {identified.log.name}: " + ", ".join(parts))
        return "\n".join(header) + "\n\n" + parameter_toml(self.params)

    def write_toml(self, path: str | Path) -> Path:
        """Write :meth:`toml` atomically. Returns the path."""
        return write_atomic(path, self.toml())


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


def _select(R: np.ndarray, candidates: list[int], tolerance: float) -> tuple[list[int], list[int]]:
    """Columns of R (in the order given) kept when their unit-norm distance from the kept ones' span exceeds the tolerance."""
    kept: list[int] = []
    dependent: list[int] = []
    basis = np.zeros((R.shape[0], 0))
    for k in candidates:
        column = R[:, k] / np.linalg.norm(R[:, k])
        rest = column - basis @ (basis.T @ column)
        rest -= basis @ (basis.T @ rest)  # twice is enough (Gram–Schmidt, reorthogonalised)
        distance = np.linalg.norm(rest)
        if distance > tolerance:
            kept.append(k)
            basis = np.column_stack([basis, rest / distance])
        else:
            dependent.append(k)
    return kept, dependent


def _condition(R: np.ndarray, columns: list[int]) -> float:
    if not columns:
        return math.nan
    A = R[:, columns] / np.linalg.norm(R[:, columns], axis=0)
    s = np.linalg.svd(A, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else math.inf


def identify(
    logs: Sequence[Log],
    params: Parameters,
    validate: Sequence[Log] = (),
    lever_spin: bool = True,
    fixed: Sequence[str] = (),
    max_relative_std: float = DEFAULT_MAX_RELATIVE_STD,
) -> Identification:
    """Identify the dynamic parameters from logs of motion, load and motor torque.

    Args:
        logs: the logs to fit (:func:`hipsim.rig.load_log`, or built from arrays), or logs
            of any length read in pieces (:class:`~hipsim.rig.log_file.LogPieces`: memory then does
            not grow with the log, the fit is the same to round-off).
        params: the starting machine: its geometry and friction radii are
            used, and it supplies the values of what the data do not determine.
        validate: held-out logs (either kind) to predict with the identified and the starting machine.
        lever_spin: the model's levers spin as their universal joints impose (default) or not.
        fixed: parameters to hold at their starting values, by label, key or
            key prefix (``"lever"``, ``"friction.ujoint"``, ``"m_l"``).
        max_relative_std: identified quantities must have a relative standard
            deviation at most this (0.01 = 1 %); the worst beyond it joins the
            others' combinations, one at a time.

    Returns:
        The identification.

    Raises:
        HipsimError: no logs, or nothing the logs can identify.
        PoseError: a logged pose out of reach or singular, naming the log and time.
    """
    logs = list(logs)
    if not logs:
        raise HipsimError("identification needs at least one log")
    if not (max_relative_std > 0):
        raise HipsimError(f"the largest relative standard deviation must be positive, got {max_relative_std!r}")
    P = len(QUANTITIES)
    prior = standard_values(params)
    nominal = np.array([abs(prior[k]) if prior[k] != 0 else q.nominal for k, q in enumerate(QUANTITIES)])

    held_fixed = set()
    for name in fixed:
        matches = [k for k, q in enumerate(QUANTITIES) if name in (q.label, q.key) or q.key.startswith(name)]
        if not matches:
            known = ", ".join(q.label for q in QUANTITIES)
            raise HipsimError(f"cannot hold '{name}' fixed: no such parameter (known: {known}, or a key prefix such as 'lever')")
        held_fixed.update(matches)

    accumulator = _Accumulator(P)
    for log in logs:
        inflation = _inflation(log)
        for Y, tau, use in log_rows(params, log, lever_spin):
            accumulator.add(Y, tau, use, inflation)
    rows_per_motor = np.asarray(accumulator.rows)
    if rows_per_motor.sum() <= P:
        raise HipsimError(f"{int(rows_per_motor.sum())} samples are too few to identify {P} parameters")
    R = accumulator.R  # per motor, (P + 1, P + 1): columns θ then τ
    rows = int(rows_per_motor.sum())
    inflation = accumulator.inflation / rows

    # Which parameters act at all: a parameter of typical size must move the torque by more than round-off.
    stacked = np.vstack(R)
    column_norm = np.linalg.norm(stacked[:, :P], axis=0)
    torque_norm = np.linalg.norm(stacked[:, P])
    reasons: dict[int, str] = {k: "held fixed as asked" for k in held_fixed}
    for k in range(P):
        if k not in reasons and column_norm[k] * nominal[k] <= 1e-9 * max(torque_norm, 1e-300):
            reasons[k] = "no effect on the motor torques of these logs"
    free = [k for k in range(P) if k not in reasons]
    fixed_idx = [k for k in range(P) if k in reasons]

    def right_hand_side(Ri):
        """τ minus the fixed parameters' torque, in the factor's rows."""
        return Ri[:, P] - Ri[:, fixed_idx] @ prior[fixed_idx]

    # Unweighted fit first, for each motor's residual level; then weighted.
    kept, dependent = _select(stacked[:, :P], free, RANK_TOLERANCE)
    if not kept:
        raise HipsimError("nothing in these logs identifies any parameter (is anything moving?)")
    A = stacked[:, kept]
    b = np.concatenate([right_hand_side(Ri) for Ri in R])
    theta_kept = np.linalg.lstsq(A, b, rcond=None)[0]
    sigma = np.empty(3)
    for i, Ri in enumerate(R):
        sigma[i] = np.linalg.norm(Ri[:, kept] @ theta_kept - right_hand_side(Ri)) / math.sqrt(max(rows_per_motor[i], 1))
    sigma = np.maximum(sigma, 1e-12 * max(sigma.max(), 1e-300))
    weights = 1.0 / np.where(sigma > 0, sigma, 1.0)
    Rw = scipy.linalg.qr(np.vstack([w * Ri for w, Ri in zip(weights, R)]), mode="r", check_finite=False)[0][: P + 1]
    zw = Rw[:, P] - Rw[:, fixed_idx] @ prior[fixed_idx]
    Aw = Rw[:, :P]

    kept, dependent = _select(Aw, free, RANK_TOLERANCE)
    condition_number = _condition(Aw, kept)
    for k in dependent:
        reasons[k] = "cannot be told apart from others in these logs"
    dropped: list[int] = []
    while True:
        Q, Rk = np.linalg.qr(Aw[:, kept])
        theta_kept = scipy.linalg.solve_triangular(Rk, Q.T @ zw)
        dof = max(rows - len(kept), 1)
        variance = np.sum((Aw[:, kept] @ theta_kept - zw) ** 2) / dof * inflation
        Rk_inv = scipy.linalg.solve_triangular(Rk, np.eye(len(kept)))
        std = np.sqrt(variance * np.sum(Rk_inv**2, axis=1))
        # Uncertainty against the size the quantity has or typically has: a value near zero, known to be
        # near zero, is identified; one whose uncertainty is as large as a typical value is not.
        spread = std / np.maximum(np.abs(theta_kept), nominal[kept])
        worst = int(np.argmax(spread))
        if spread[worst] <= max_relative_std or len(kept) == 1:
            break
        k = kept.pop(worst)
        dropped.append(k)
        reasons[k] = (f"too weakly excited: standard deviation {100 * spread[worst]:.3g} % of its size "
                      f"(at most {100 * max_relative_std:g} % asked)")
    if spread.max() > max_relative_std:
        k = kept[0]
        raise HipsimError(
            f"these logs identify nothing to within {100 * max_relative_std:g} %: the best determined quantity, "
            f"{QUANTITIES[k].label}, has a standard deviation of {100 * spread[0]:.3g} % of its size (excite the machine more, or log longer)"
        )
    with np.errstate(divide="ignore"):
        relative = std / np.abs(theta_kept)
    condition_number_base = _condition(Aw, kept)

    # Combinations: base k stands for θ_k + Σ_j β_kj θ_j over the parameters not kept (free ones only).
    others = dependent + dropped
    beta = np.zeros((P, P))
    if others:
        beta_kept = np.linalg.lstsq(Aw[:, kept], Aw[:, others], rcond=None)[0]
        beta[np.ix_(kept, others)] = beta_kept
    # The identified machine: others at their starting values, the kept ones take the rest.
    theta = prior.copy()
    theta[kept] = theta_kept - beta[np.ix_(kept, others)] @ prior[others]

    active: tuple[str, ...] = ()
    if violations(theta):
        theta, active = consistent(Aw / math.sqrt(inflation), zw / math.sqrt(inflation), theta, kept, dependent, prior, nominal)

    quantities = []
    for position, k in enumerate(kept):
        q = QUANTITIES[k]
        value = theta_kept[position]
        # Terms whose parameter, at its typical size, moves the combination by less than 1 % of the
        # combination's size are left out of the text (they stay in ``beta``).
        terms = sorted(
            (j for j in others if abs(beta[k, j]) * nominal[j] >= 1e-2 * max(abs(value), nominal[k])),
            key=lambda j: -abs(beta[k, j]) * nominal[j],
        )
        quantities.append(IdentifiedQuantity(
            q.label, q.key, q.unit, float(value / q.scale), float(relative[position]), float(std[position] / q.scale),
            tuple((QUANTITIES[j].label, float(beta[k, j] * QUANTITIES[j].scale / q.scale), _ratio_unit(q.unit, QUANTITIES[j].unit)) for j in terms),
        ))
    held = tuple(
        (QUANTITIES[k].label, reasons[k], float(theta[k] / QUANTITIES[k].scale), QUANTITIES[k].unit) for k in range(P) if k in reasons
    )

    residual = np.array([np.linalg.norm(Ri[:, :P] @ theta - Ri[:, P]) / math.sqrt(max(r, 1)) for Ri, r in zip(R, rows_per_motor)])
    names = tuple(log.name for log in logs)
    identified = with_values(params, theta, source=f"identified from {', '.join(names)}")
    validation = tuple((compare_log(identified, log, lever_spin), compare_log(params, log, lever_spin)) for log in validate)
    return Identification(
        identified, params, tuple(quantities), held, beta, tuple(kept), condition_number, condition_number_base,
        residual, rows, names, lever_spin, active, validation,
    )


def _percent(fraction: float) -> str:
    return f"±{100 * fraction:.2g} %" if fraction < 10 else "near zero"


def _ratio_unit(numerator: str, denominator: str) -> str:
    """The unit of a combination coefficient: the base's unit per the term's."""
    if numerator == denominator:
        return ""
    if not denominator:
        return numerator
    if numerator == "kg·mm²" and denominator == "kg":
        return "mm²"
    return f"{numerator or '1'}/{denominator}"

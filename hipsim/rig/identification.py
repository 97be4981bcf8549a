"""Identification of the machine's dynamic parameters from measured motor torques.

The regressor. The analytic inverse dynamics (spec §4) is linear in the
inertial parameters of each body group and in the friction coefficients:
τ(t) = Y(q, q̇, q̈, F_e)·θ, with θ the :data:`QUANTITIES` below (the
platform's inertia about its centre, the sliders' mass, the screws' rotor
inertia, the levers' inertia about their centre and mass, and the friction
coefficients). :func:`regressor` builds Y from that linearity: the inverse
dynamics of a machine whose parameters are all zero but one, set to one, is
that parameter's column. Each body group lands in its own torque part (spec
§4.4), so one call gives a column of every group at once, ten calls in all.
The levers' centre of mass stays at mid-length, as the model has it; the
hip-joint and thrust-bearing Coulomb terms scale with the load, the screw and
guide terms with the motor speed, the lever-joint terms with their relative
angular speeds, each through the same friction law the model uses (the
friction coefficient is what is identified; radii, the platform mass and the
smooth sign's ε are kept). The thrust bearing's column comes from one
function, :func:`friction_unit`, so a different bearing law (one that
resists only the rotation about the bearing's axis) changes it there and
nowhere else.

The fit (:func:`identify`). Each log's regressor rows and torques go
through the log's own low-pass (the torques already have), so model and
measurement share one bandwidth ("parallel filtering"), and are then kept
every D-th sample (decimation to four times the cutoff); the samples
around each motor's reversals, where the real motion sticks and no model on
the filtered motion can follow (:func:`hipsim.rig.compare.reversal_mask`),
are left out of that motor's rows. Rows are
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
their starting values and the kept ones take what the combinations leave.
If that machine is not physically consistent — a negative mass, friction
coefficient or rotor inertia, or an inertia no rigid body has (its
principal moments must satisfy the triangle inequalities, i.e.
Σ = ½·tr(I)·𝟙 − I ⪰ 0, which also makes I ⪰ 0) — the fit is solved again
under those constraints, the dependent parameters then free to move but held
by a prior of :data:`PRIOR_SPREAD` of their size: first as bounded least
squares (SciPy's ``lsq_linear``, BVLS, exact for the bounds), and if an
inertia is still impossible, as a small convex program with the two 3×3
semidefinite constraints added, solved by ADMM (alternating direction method
of multipliers: the bounds and the semidefinite cones projected onto
exactly, the least squares solved with one factorisation). The constraints
the solution sits on are reported.

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
import scipy.optimize

from ..exceptions import HipsimError
from ..files import write_atomic
from ..machine.parameters import SCHEMA, Parameters, file_values
from .logs import MeasuredLog, lowpass, minimum_samples
from ..motion.trajectories import Trajectory
from ..analytic.inverse_kinematics import kinematics
from ..analytic.virtual_work import inverse_dynamics
from .compare import Comparison, LogPieces, compare, compare_log, reversal_mask

__all__ = [
    "QUANTITIES",
    "RANK_TOLERANCE",
    "Identification",
    "IdentifiedQuantity",
    "Quantity",
    "friction_unit",
    "identify",
    "regressor",
    "regressor_from_kinematics",
    "standard_values",
    "with_values",
]

#: A column closer than this to the span of the columns before it (all scaled to unit norm) depends on them.
RANK_TOLERANCE = 1e-6
#: Default largest relative standard deviation of an identified quantity.
DEFAULT_MAX_RELATIVE_STD = 0.01
#: The starting values' spread, relative to their size, where the consistency constraints move a dependent parameter.
PRIOR_SPREAD = 0.1
#: Samples per chunk of the regressor (memory: ~2 kB per sample while a chunk is computed and filtered).
CHUNK = 50_000


@dataclass(frozen=True)
class Quantity:
    """One parameter of the regressor.

    Attributes:
        key: the parameter file's key (``lever.mass_kg``), with a component for inertias (``platform.inertia_kgmm2[xy]``).
        label: short name for tables (``m_l``).
        unit: the file's unit.
        scale: SI value of one file unit.
        part: the torque part (spec §4.4) its column lands in.
        nominal: a typical magnitude in SI, for scaling where the starting value is zero.
        nonnegative: True for masses, rotor inertias and friction coefficients.
    """

    key: str
    label: str
    unit: str
    scale: float
    part: str
    nominal: float
    nonnegative: bool = False


_AXES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def _inertia(body: str, label: str, part: str, nominal: float) -> list[Quantity]:
    return [
        Quantity(f"{body}.inertia_kgmm2[{axes}]", f"{label},{axes}", "kg·mm²", 1e-6, part, nominal, nonnegative=axes[0] == axes[1])
        for axes in _AXES
    ]


#: The regressor's parameters, in the order base parameters are chosen (the first of a dependent group names it).
QUANTITIES: tuple[Quantity, ...] = (
    *_inertia("platform", "I_m", "platforms", 0.3),
    Quantity("slider.mass_kg", "m_L", "kg", 1.0, "sliders", 3.0, True),
    Quantity("screw.inertia_kgmm2", "I_L", "kg·mm²", 1e-6, "screws", 5e-5, True),
    *_inertia("lever", "I_l", "levers", 0.03),
    Quantity("lever.mass_kg", "m_l", "kg", 1.0, "levers", 1.5, True),
    Quantity("friction.hip_mu", "μ_h", "", 1.0, "friction", 0.1, True),
    Quantity("friction.thrust_mu", "μ_t", "", 1.0, "friction", 0.03, True),
    Quantity("friction.screw_coulomb_Nmm", "τ_c,screw", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.screw_viscous_Nmm_s_rad", "b_screw", "N·mm·s/rad", 1e-3, "friction", 2e-4, True),
    Quantity("friction.guide_coulomb_N", "F_c,guide", "N", 1.0, "friction", 15.0, True),
    Quantity("friction.guide_viscous_N_s_mm", "b_guide", "N·s/mm", 1e3, "friction", 40.0, True),
    Quantity("friction.ujoint_coulomb_Nmm", "τ_c,U", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.ujoint_viscous_Nmm_s_rad", "b_U", "N·mm·s/rad", 1e-3, "friction", 0.005, True),
    Quantity("friction.sjoint_coulomb_Nmm", "τ_c,S", "N·mm", 1e-3, "friction", 0.05, True),
    Quantity("friction.sjoint_viscous_Nmm_s_rad", "b_S", "N·mm·s/rad", 1e-3, "friction", 0.005, True),
)

_INDEX = {quantity.key: k for k, quantity in enumerate(QUANTITIES)}
#: The friction coefficients by Friction field, in the order of QUANTITIES.
_FRICTION_FIELDS = ("hip_mu", "thrust_mu", "screw_coulomb", "screw_viscous", "guide_coulomb", "guide_viscous",
                    "ujoint_coulomb", "ujoint_viscous", "sjoint_coulomb", "sjoint_viscous")
#: The inertia blocks whose consistency is a semidefinite constraint: indices of xx … yz in QUANTITIES.
_BLOCKS = {body: [_INDEX[f"{body}.inertia_kgmm2[{axes}]"] for axes in _AXES] for body in ("platform", "lever")}


def _symmetric(values: Sequence[float]) -> np.ndarray:
    """The symmetric 3x3 matrix of (xx, yy, zz, xy, xz, yz)."""
    matrix = np.zeros((3, 3))
    for value, (a, b) in zip(values, _AXES.values()):
        matrix[a, b] = matrix[b, a] = value
    return matrix


def standard_values(params: Parameters) -> np.ndarray:
    """θ of a machine in SI, in the order of :data:`QUANTITIES`, (P,)."""
    f = params.friction
    values = [params.platform_inertia[a, b] for a, b in _AXES.values()]
    values += [params.slider_mass, params.screw_inertia]
    values += [params.lever_inertia[a, b] for a, b in _AXES.values()]
    values += [params.lever_mass]
    values += [getattr(f, name) for name in _FRICTION_FIELDS]
    return np.array(values, dtype=float)


def with_values(params: Parameters, theta: np.ndarray, source: str | None = None) -> Parameters:
    """The machine ``params`` with θ (SI, order of :data:`QUANTITIES`) in place of its dynamic parameters."""
    theta = np.asarray(theta, dtype=float)
    changes = dict(
        platform_inertia=_symmetric(theta[0:6]), slider_mass=float(theta[6]), screw_inertia=float(theta[7]),
        lever_inertia=_symmetric(theta[8:14]), lever_mass=float(theta[14]),
        **{name: float(value) for name, value in zip(_FRICTION_FIELDS, theta[15:])},
    )
    if source is not None:
        changes["source"] = source
    return params.replace(**changes)


def _zero_dynamics(params: Parameters) -> Parameters:
    """The machine with every identified parameter zero (geometry, radii, ε and platform mass kept)."""
    return with_values(params, np.zeros(len(QUANTITIES)))


def friction_unit(params: Parameters, name: str) -> Parameters:
    """The machine whose only friction is coefficient ``name`` (a :class:`~hipsim.machine.parameters.Friction` field) set to one.

    Everything else of the friction law — radii, the platform mass in the
    thrust bearing's load, the smooth sign's ε, and any option of the law —
    is kept from ``params``, so the column is the law's own, per unit coefficient.
    For ``hip_mu`` and ``thrust_mu`` the column is the friction moment per unit μ at the machine's radius.
    """
    return params.replace(**{field: 1.0 if field == name else 0.0 for field in _FRICTION_FIELDS})


def _unit_machines(params: Parameters) -> list[tuple[Parameters, dict[str, int]]]:
    """Ten machines, each with one parameter per body group set to one, and where each part's column goes."""
    zero = _zero_dynamics(params)
    basis = [_symmetric(np.eye(6)[k]) for k in range(6)]
    machines = []
    for s in range(10):
        changes: dict[str, Any] = {}
        columns: dict[str, int] = {}
        if s < 6:
            changes["platform_inertia"] = basis[s]
            columns["platforms"] = s
            changes["lever_inertia"] = basis[s]
            columns["levers"] = 8 + s
        elif s == 6:
            changes["lever_mass"] = 1.0
            columns["levers"] = 14
        if s == 0:
            changes["slider_mass"] = 1.0
            columns["sliders"] = 6
            changes["screw_inertia"] = 1.0
            columns["screws"] = 7
        machine = zero.replace(**changes)
        if s < len(_FRICTION_FIELDS):
            machine = friction_unit(machine, _FRICTION_FIELDS[s])
            columns["friction"] = 15 + s
        machines.append((machine, columns))
    return machines


def regressor(params: Parameters, trajectory: Trajectory, lever_spin: bool = True) -> np.ndarray:
    """Y with motor torque τ = Y·θ along a trajectory (θ: :func:`standard_values`).

    Args:
        params: the machine (its geometry, friction radii, ε and platform mass
            are used; its dynamic parameters are not).
        trajectory: the motion and load, N samples.
        lever_spin: as in :func:`hipsim.analytic.inverse_dynamics`.

    Returns:
        Y in [N·m per SI unit of each parameter], (N, 3, P).

    Raises:
        PoseError: naming the time of a pose out of reach or singular.
    """
    return regressor_from_kinematics(params, kinematics(params, trajectory), trajectory.Fe, lever_spin)


def regressor_from_kinematics(params: Parameters, kin, Fe: np.ndarray, lever_spin: bool = True) -> np.ndarray:
    """:func:`regressor` from kinematics already computed (:func:`hipsim.analytic.kinematics`) and the load in [N], (N,)."""
    Y = np.zeros((len(kin), 3, len(QUANTITIES)))
    for machine, columns in _unit_machines(params):
        torques = inverse_dynamics(machine, kin, Fe, lever_spin)
        for part, k in columns.items():
            Y[:, :, k] = getattr(torques, part)
    return Y


# --- Rows of a log, filtered and decimated ----------------------------------------------------


def _decimation(log: MeasuredLog) -> int:
    """Keep every D-th sample after the low-pass: four samples per period of the cutoff."""
    return 1 if log.cutoff is None else max(1, int(log.rate // (4.0 * log.cutoff)))


def _rows(params: Parameters, log: MeasuredLog, lever_spin: bool, chunk: int = CHUNK, span: tuple[int, int, int] | None = None):
    """The log's regressor rows and torques, low-passed like the log and decimated, chunk by chunk.

    Args:
        span: (first, stop, origin): the rows of samples ``first`` … ``stop``−1
            a whole number of decimation steps after sample ``origin`` (a piece
            of a log: origin is where the whole log's usable samples start);
            None for the log's usable samples.

    Yields:
        Y (m, 3, P), τ (m, 3) and the rows to use per motor (m, 3) bool (False near that motor's reversals).
    """
    n = len(log)
    first, stop, origin = span if span is not None else (log.usable.start, log.usable.stop, log.usable.start)
    step = _decimation(log)
    first += (origin - first) % step  # the first kept sample
    margin = 0 if log.cutoff is None else minimum_samples(log.rate, log.cutoff)
    trajectory = log.trajectory
    use = ~reversal_mask(params, log)
    chunk = max(step, chunk - chunk % step)  # whole decimation steps, so the kept samples line up across chunks
    for a in range(first, stop, chunk):
        b = min(a + chunk, stop)
        lo, hi = max(0, a - margin), min(n, b + margin)
        Y = regressor(params, trajectory.slice(slice(lo, hi)), lever_spin)
        if log.cutoff is not None:
            # The filter's transient from the chunk's own ends dies out within the margin.
            Y = lowpass(Y, log.rate, log.cutoff, log.name)
        keep = np.arange(a, b, step)
        yield Y[keep - lo], log.tau[keep], use[keep]


def _log_rows(params: Parameters, log: MeasuredLog | LogPieces, lever_spin: bool):
    """:func:`_rows` of a log in memory, or of a log in pieces piece by piece (the same rows, to round-off)."""
    if isinstance(log, MeasuredLog):
        yield from _rows(params, log, lever_spin)
        return
    usable = log.usable
    for window, core, start in log.windows():
        first, stop = max(start, usable.start), min(start + core.stop - core.start, usable.stop)
        if first < stop:
            shift = core.start - start  # window index of a log index
            yield from _rows(params, window, lever_spin, span=(first + shift, stop + shift, usable.start + shift))


# --- Results ----------------------------------------------------------------------------------


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


def _toml_value(value) -> str:
    if isinstance(value, bool):  # before numbers: a bool is an int to Python
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(float(f"{value:.15g}"))
    return repr(value)


def parameter_toml(params: Parameters) -> str:
    """A machine as the text of a parameter file (every section, file units, 15 significant digits)."""
    values = file_values(params)
    lines = []
    for section, keys in SCHEMA.items():
        present = [key for key in keys if f"{section}.{key}" in values]
        if not present:
            continue
        lines.append(f"[{section}]")
        for key in present:
            value = values[f"{section}.{key}"]
            meaning = SCHEMA[section][key].meaning
            lines.append(f"{key} = {_toml_value(value)}" + (f"  # {meaning}" if meaning else ""))
        lines.append("")
    return "\n".join(lines)


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


def _inflation(log: MeasuredLog) -> float:
    """Samples per independent sample after the low-pass and decimation (1 without a filter)."""
    if log.cutoff is None:
        return 1.0
    return max(1.0, log.rate / _decimation(log) / (2.0 * log.cutoff))


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
    logs: Sequence[MeasuredLog],
    params: Parameters,
    validate: Sequence[MeasuredLog] = (),
    lever_spin: bool = True,
    fixed: Sequence[str] = (),
    max_relative_std: float = DEFAULT_MAX_RELATIVE_STD,
) -> Identification:
    """Identify the dynamic parameters from logs of motion, load and motor torque.

    Args:
        logs: the logs to fit (:func:`hipsim.rig.load_log`, or built from arrays), or logs
            of any length in pieces (:class:`~hipsim.rig.compare.LogPieces`: memory then does
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
        for Y, tau, use in _log_rows(params, log, lever_spin):
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
    if _violations(theta):
        theta, active = _consistent(Aw / math.sqrt(inflation), zw / math.sqrt(inflation), theta, kept, dependent, prior, nominal)

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
    validation = tuple((_compare(identified, log, lever_spin), _compare(params, log, lever_spin)) for log in validate)
    return Identification(
        identified, params, tuple(quantities), held, beta, tuple(kept), condition_number, condition_number_base,
        residual, rows, names, lever_spin, active, validation,
    )


def _compare(params: Parameters, log: MeasuredLog | LogPieces, lever_spin: bool) -> Comparison:
    return compare(params, log, lever_spin) if isinstance(log, MeasuredLog) else compare_log(params, log, lever_spin)


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


# --- Physical consistency ---------------------------------------------------------------------

#: Σ = ½·tr(I)·𝟙 − I as a linear map of (Ixx, Iyy, Izz, Ixy, Ixz, Iyz), to (Σxx, Σyy, Σzz, √2Σxy, √2Σxz, √2Σyz)
#: (the √2 makes the Euclidean norm of the vector the Frobenius norm of the matrix).
_SIGMA = np.array([
    [-0.5, 0.5, 0.5, 0, 0, 0],
    [0.5, -0.5, 0.5, 0, 0, 0],
    [0.5, 0.5, -0.5, 0, 0, 0],
    [0, 0, 0, -math.sqrt(2), 0, 0],
    [0, 0, 0, 0, -math.sqrt(2), 0],
    [0, 0, 0, 0, 0, -math.sqrt(2)],
])
_BOUNDED = [k for k, q in enumerate(QUANTITIES) if q.nonnegative and not any(k in block for block in _BLOCKS.values())]


def _matrix(sigma: np.ndarray) -> np.ndarray:
    """The symmetric matrix of a Σ vector (xx, yy, zz, √2xy, √2xz, √2yz)."""
    r = 1.0 / math.sqrt(2)
    return _symmetric([sigma[0], sigma[1], sigma[2], sigma[3] * r, sigma[4] * r, sigma[5] * r])


def _vector(matrix: np.ndarray) -> np.ndarray:
    r = math.sqrt(2)
    return np.array([matrix[0, 0], matrix[1, 1], matrix[2, 2], r * matrix[0, 1], r * matrix[0, 2], r * matrix[1, 2]])


def _project_psd(sigma: np.ndarray) -> np.ndarray:
    values, vectors = np.linalg.eigh(_matrix(sigma))
    return _vector((vectors * np.maximum(values, 0.0)) @ vectors.T)


def _violations(theta: np.ndarray, tolerance: float = 1e-12) -> list[str]:
    """The physical-consistency constraints θ breaks, as text."""
    out = [f"{QUANTITIES[k].label} ≥ 0" for k in _BOUNDED if theta[k] < 0]
    for body, block in _BLOCKS.items():
        sigma = np.linalg.eigvalsh(_matrix(_SIGMA @ theta[block]))
        if sigma[0] < -tolerance * max(abs(sigma).max(), 1e-300):
            out.append(f"{body} inertia of a rigid body (principal moments within the triangle inequalities)")
    return out


def _consistent(Aw, zw, theta0, kept, dependent, prior, nominal, max_iter: int = 20_000):
    """Weighted least squares under the consistency constraints (module docstring).

    Variables: the kept and dependent parameters, scaled by their nominal sizes
    (``Aw``, ``zw``: the weighted rows, scaled to a χ²); the others stay at θ0. First bounded least squares (SciPy's ``lsq_linear``,
    BVLS: exact for the bounds); if an inertia then breaks the rigid-body
    condition, the semidefinite constraints join in a small convex program
    solved by ADMM. Returns θ and the active constraints as text.
    """
    variables = list(kept) + list(dependent)
    scale = nominal[variables]
    constant = np.array(theta0, dtype=float)
    constant[variables] = 0.0
    A = Aw[:, variables] * scale
    b = zw - Aw @ constant
    # The dependent parameters move only where the bounds need them to: a prior of 10 % of their size
    # (the data term is a χ², its rows weighted by the inverse noise), which holds them wherever the
    # data leave them free and gives way where the data pull.
    dep = np.zeros(len(variables))
    dep[len(kept):] = 1.0
    target = prior[variables] / scale
    pull = 1.0 / PRIOR_SPREAD
    A_reg = np.vstack([A, pull * np.diag(dep)[dep > 0]])
    b_reg = np.concatenate([b, pull * target[dep > 0]])
    position = {k: n for n, k in enumerate(variables)}
    lower = np.full(len(variables), -np.inf)
    for k in _BOUNDED:
        if k in position:
            lower[position[k]] = 0.0
    x = scipy.optimize.lsq_linear(A_reg, b_reg, bounds=(lower, np.inf), method="bvls", tol=1e-14).x
    theta = constant.copy()
    theta[variables] = x * scale
    if any("inertia" in violation for violation in _violations(theta)):
        theta = _semidefinite(A_reg, b_reg, x, scale, constant, variables, max_iter)
    return theta, _active(theta, [k for k in variables if k in kept or prior[k] > 0], nominal)


def _active(theta, movable, nominal) -> tuple[str, ...]:
    """The constraints θ sits on: bounds of the parameters that moved to them, and inertias on the rigid-body limit."""
    active = [f"{QUANTITIES[k].label} ≥ 0" for k in _BOUNDED if k in movable and theta[k] <= 1e-9 * nominal[k]]
    for body, block in _BLOCKS.items():
        eigen = np.linalg.eigvalsh(_matrix(_SIGMA @ theta[block]))
        if eigen[0] <= 1e-9 * eigen[-1]:
            active.append(f"{body} inertia on the rigid-body limit (one principal moment equals the sum of the other two)")
    return tuple(active)


def _semidefinite(A, b, x0, scale, constant, variables, max_iter):
    """Least squares ‖A·x − b‖² under the bounds and the two semidefinite constraints, by ADMM (x scaled by ``scale``)."""
    H = A.T @ A
    q = A.T @ b
    # Constraint rows y = M·x + c, blocks: bounds (y ≥ 0), then each inertia's Σ vector (PSD).
    position = {k: n for n, k in enumerate(variables)}
    rows, offsets, kinds = [], [], []
    for k in _BOUNDED:
        if k in position:
            row = np.zeros(len(variables))
            row[position[k]] = 1.0
            rows.append(row)
            offsets.append(0.0)
            kinds.append(("bound", k))
    for body, block in _BLOCKS.items():
        G = np.zeros((6, len(variables)))
        c = _SIGMA @ constant[block]
        for column, k in enumerate(block):
            if k in position:
                G[:, position[k]] = _SIGMA[:, column] * scale[position[k]]
        size = max(np.abs(G).max(), np.abs(c).max(), 1e-300)
        rows.extend(G / size)
        offsets.extend(c / size)
        kinds.append(("block", body))
    M = np.array(rows)
    c = np.array(offsets)

    def project(v):
        out = v.copy()
        n_bounds = sum(1 for kind in kinds if kind[0] == "bound")
        out[:n_bounds] = np.maximum(out[:n_bounds], 0.0)
        for b_index in range(len(_BLOCKS)):
            start = n_bounds + 6 * b_index
            out[start : start + 6] = _project_psd(out[start : start + 6])
        return out

    rho = np.trace(H) / len(variables)
    x = x0
    y = project(M @ x + c)
    u = np.zeros_like(y)
    factor = scipy.linalg.cho_factor(H + rho * M.T @ M)
    for iteration in range(max_iter):
        x = scipy.linalg.cho_solve(factor, q + rho * M.T @ (y - c - u))
        Mx = M @ x + c
        y_new = project(Mx + u)
        u += Mx - y_new
        primal = np.linalg.norm(Mx - y_new)
        dual = rho * np.linalg.norm(M.T @ (y_new - y))
        y = y_new
        if primal <= 1e-10 * max(np.linalg.norm(Mx), 1.0) and dual <= 1e-10 * max(np.linalg.norm(q), 1e-300):
            break
        if iteration % 50 == 49 and (primal > 10 * dual or dual > 10 * primal):
            factor_change = 2.0 if primal > dual else 0.5
            rho *= factor_change
            u /= factor_change
            factor = scipy.linalg.cho_factor(H + rho * M.T @ M)
    theta = constant.copy()
    theta[variables] = x * scale
    # Exactly feasible: clip the bounds, and put each inertia on its cone.
    for k in _BOUNDED:
        theta[k] = max(theta[k], 0.0)
    for block in _BLOCKS.values():
        sigma = _SIGMA @ theta[block]
        projected = _project_psd(sigma)
        if np.linalg.norm(projected - sigma) > 0:
            inertia = np.trace(_matrix(projected)) * np.eye(3) - _matrix(projected)
            theta[block] = [inertia[a, b] for a, b in _AXES.values()]
    return theta

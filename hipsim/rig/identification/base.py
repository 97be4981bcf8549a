"""The base parameters: the fixed combinations of the dynamic parameters that motor torques can ever determine.

Motor torque is linear in the standard parameters θ (the
:data:`~hipsim.rig.identification.quantities.QUANTITIES`): τ = Y(q, q̇, q̈, F_e)·θ. Some columns
of Y are linear combinations of others for *every* motion the machine can make
(the levers' mass regroups into the sliders and the platform; the guide's
friction acts exactly as the screw's), whatever the log. Those structural
dependencies are found once per machine geometry (Gautier, "Numerical
calculation of the base inertial parameters of robots", J. Robotic Systems 1991):

1. the regressor is stacked over random samples (q, q̇, q̈, F_e) inside the
   workspace (random, not a trajectory: no accidental collinearity), its columns
   scaled by each parameter's typical size;
2. its rank r comes from a QR decomposition with column pivoting;
3. the independent columns are chosen in the fixed order of ``QUANTITIES``
   (the first of a dependent group names it, so the names never follow the
   column norms of one draw), and each dependent column's coefficients on them,
   R₁⁻¹R₂, are rounded to :data:`DIGITS` significant digits (they are geometric
   constants: a second draw agrees to ~1e-10) and set to zero below 1e-9 of
   their typical effect.

The base parameter k is then θ_b,k = θ_k + Σ_j β_kj·θ_j over the dependent
parameters j, and τ = Y[:, base]·θ_b exactly. :func:`base_parameters` caches the
result per geometry (everything of the machine but its dynamic parameters).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...machine.parameters import Parameters, file_values
from ...motion.trajectories import Trajectory
from .quantities import QUANTITIES, standard_values
from .regressor import regressor

__all__ = ["DIGITS", "BaseParameter", "BaseParameters", "base_parameters", "random_regressor"]

#: Significant digits the combination coefficients keep.
DIGITS = 10
#: A scaled column whose distance from the span of the columns before it is below this depends on them.
RANK_TOLERANCE = 1e-8
#: Random samples per draw: angles within ±20°, speeds within ±3 rad/s, accelerations within ±40 rad/s², loads 0–3000 N.
SAMPLES = 300


@dataclass(frozen=True)
class BaseParameter:
    """One base parameter: a standard parameter and the dependent ones folded into it.

    Attributes:
        index: its standard parameter's index in :data:`QUANTITIES`.
        label: the standard parameter that names it (``m_L``).
        key: that parameter's file key (``slider.mass_kg``).
        unit: its unit (file units).
        terms: the dependent parameters folded in, (label, coefficient in file units, the coefficient's unit).
    """

    index: int
    label: str
    key: str
    unit: str
    terms: tuple[tuple[str, float, str], ...] = ()

    @property
    def definition(self) -> str:
        """``"m_L + 0.5·m_l"``: the combination, every term."""
        text = self.label
        for label, coefficient, unit in self.terms:
            sign = "−" if coefficient < 0 else "+"
            text += f" {sign} {abs(coefficient):.{DIGITS}g}{' ' + unit if unit else ''}·{label}"
        return text


@dataclass(frozen=True, eq=False)
class BaseParameters:
    """The base parameters of one machine geometry.

    Attributes:
        parameters: each base parameter, in the order of :data:`QUANTITIES`.
        dependent: indices in :data:`QUANTITIES` of the parameters folded into others.
        beta: (P, P) in SI: θ_b,k = θ_k + Σ_j beta[k, j]·θ_j (rows of dependent parameters and columns of base ones zero).
        lever_spin: the model they are of.
    """

    parameters: tuple[BaseParameter, ...]
    dependent: tuple[int, ...]
    beta: np.ndarray
    lever_spin: bool

    @property
    def index(self) -> list[int]:
        """Indices in :data:`QUANTITIES` of the base parameters' standard parameters."""
        return [p.index for p in self.parameters]

    @property
    def scale(self) -> np.ndarray:
        """SI value of one file unit of each base parameter."""
        return np.array([QUANTITIES[k].scale for k in self.index])

    @property
    def names(self) -> list[str]:
        return [p.label for p in self.parameters]

    @property
    def transform(self) -> np.ndarray:
        """T, (r, P), SI: θ_b = T·θ."""
        T = self.beta[self.index].copy()
        T[np.arange(len(self.index)), self.index] += 1.0
        return T

    def values(self, params: Parameters) -> np.ndarray:
        """The base parameters of a machine in SI, (r,)."""
        return self.transform @ standard_values(params)

    def standard(self, theta_b: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Standard parameters (SI) with the base values ``theta_b``: the dependent ones kept from ``theta``, the base ones take the rest."""
        out = np.array(theta, dtype=float)
        dependent = list(self.dependent)
        out[self.index] = theta_b - self.beta[np.ix_(self.index, dependent)] @ out[dependent]
        return out


def _geometry(params: Parameters) -> str:
    """Everything of the machine but its dynamic parameters, as text: the cache key."""
    dynamic = {q.key.partition("[")[0] for q in QUANTITIES}
    return repr(sorted((key, value) for key, value in file_values(params).items() if key not in dynamic))


def random_regressor(params: Parameters, seed: int, lever_spin: bool = True, samples: int = SAMPLES) -> np.ndarray:
    """Y over random (q, q̇, q̈, F_e) in the workspace, rows of every motor stacked, (3·samples, P), SI."""
    rng = np.random.default_rng(seed)
    q = np.radians(rng.uniform(-20.0, 20.0, (samples, 3)))
    qd = rng.uniform(-3.0, 3.0, (samples, 3))
    qdd = rng.uniform(-40.0, 40.0, (samples, 3))
    Fe = rng.uniform(0.0, 3000.0, samples)
    trajectory = Trajectory(np.arange(samples) * 1e-3, q, qd, qdd, Fe, name="random samples")
    Y = regressor(params, trajectory, lever_spin)
    return Y.reshape(-1, Y.shape[-1])


def _round(value: float) -> float:
    return float(f"{value:.{DIGITS}g}")


def _ratio_unit(numerator: str, denominator: str) -> str:
    """The unit of a combination coefficient: the base's unit per the term's."""
    if numerator == denominator:
        return ""
    if not denominator:
        return numerator
    if numerator == "kg·mm²" and denominator == "kg":
        return "mm²"
    if numerator == "N·mm" and denominator == "N":
        return "mm"
    if numerator == "N·mm·s/rad" and denominator == "N·s/mm":
        return "mm²/rad"
    return f"{numerator or '1'}/{denominator}"


def derive(params: Parameters, lever_spin: bool = True, seed: int = 0) -> BaseParameters:
    """The base parameters from one random draw (uncached; :func:`base_parameters` caches it)."""
    P = len(QUANTITIES)
    nominal = np.array([q.nominal for q in QUANTITIES])
    Y = random_regressor(params, seed, lever_spin) * nominal
    norm = np.maximum(np.linalg.norm(Y, axis=0), 1e-300)
    Y /= norm
    # The rank, from QR with column pivoting.
    R = scipy.linalg.qr(Y, mode="r", pivoting=True)[0]
    diagonal = np.abs(np.diag(R))
    rank = int(np.sum(diagonal > RANK_TOLERANCE * diagonal[0]))
    # The independent columns in the fixed order (Gram–Schmidt, reorthogonalised).
    kept: list[int] = []
    basis = np.zeros((Y.shape[0], 0))
    for k in range(P):
        rest = Y[:, k] - basis @ (basis.T @ Y[:, k])
        rest -= basis @ (basis.T @ rest)
        distance = np.linalg.norm(rest)
        if distance > RANK_TOLERANCE and len(kept) < rank:
            kept.append(k)
            basis = np.column_stack([basis, rest / distance])
    dependent = [k for k in range(P) if k not in kept]
    beta = np.zeros((P, P))
    if dependent:
        scaled = np.linalg.lstsq(Y[:, kept], Y[:, dependent], rcond=None)[0]  # R₁⁻¹R₂ in scaled units
        scaled[np.abs(scaled) < 1e-9] = 0.0
        for a, k in enumerate(kept):
            for b, j in enumerate(dependent):
                if scaled[a, b]:
                    beta[k, j] = _round(scaled[a, b] * nominal[k] * norm[j] / (norm[k] * nominal[j]))
    parameters = []
    for k in kept:
        q = QUANTITIES[k]
        terms = tuple(
            (
                QUANTITIES[j].label,
                _round(beta[k, j] * QUANTITIES[j].scale / q.scale),
                _ratio_unit(q.unit, QUANTITIES[j].unit),
            )
            for j in dependent
            if beta[k, j]
        )
        parameters.append(BaseParameter(k, q.label, q.key, q.unit, terms))
    beta.setflags(write=False)
    return BaseParameters(tuple(parameters), tuple(dependent), beta, lever_spin)


#: Base parameters per (geometry, lever spin): a few machines at a time.
_CACHE: dict[tuple[str, bool], BaseParameters] = {}


def base_parameters(params: Parameters, lever_spin: bool = True) -> BaseParameters:
    """The base parameters of a machine's geometry (cached per geometry and lever spin; module docstring)."""
    key = (_geometry(params), lever_spin)
    if key not in _CACHE:
        if len(_CACHE) >= 16:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = derive(params, lever_spin)
    return _CACHE[key]

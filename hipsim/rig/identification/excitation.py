"""Excitation trajectories for identification: finite Fourier series optimised for the regressor's condition.

An identification is only as good as the motion it sees: the ISO 14242-1
cycle moves one harmonic per angle at 1 Hz and leaves some parameters
nearly indistinguishable. :func:`excitation` designs a periodic motion for
the rig instead, each angle and the load a finite Fourier series of one base
frequency f (so that cycles can be averaged):

    q_k(t) = c_k0 + Σ_{l=1..H} a_kl·sin(2πlft) + b_kl·cos(2πlft),   k = α, β, γ, F_e,

whose coefficients minimise the condition number of the identification
regressor (:func:`hipsim.rig.identification.regressor.regressor`, columns scaled
to unit norm, for the parameters of ``quantities``; by default the platform
inertia, the sliders' mass, the screws' rotor inertia and the hip, thrust
and screw friction: what moves the motor torques most) over one period, subject, at
every sample of the period, to

- reach, and a singularity measure (inverse condition number of J) of at least ``min_cond_inv``;
- angles within ±``max_angle_deg``, the load within [``min_load``, ``max_load``];
- slider speed and acceleration within ``max_speed`` and ``max_acceleration``;
- motor torque (the starting machine's inverse dynamics) within ``torque_limit``.

The optimiser is SciPy's SLSQP on the logarithm of the condition number,
from a feasible start (random coefficients scaled down until every limit
holds; the best of a few seeds); it is deterministic for a given seed.
Defaults of the limits: the ISO cycle's needs with some margin (spec §7.2:
~310 mm/s, ~2000 mm/s², ~430 N·mm, singularity measure ≥ 0.36), unless the
parameter file's ``[motor]`` table or torque limit says otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import scipy.optimize

from ...analytic.inverse_kinematics import kinematics
from ...analytic.virtual_work import inverse_dynamics
from ...exceptions import ArgumentError, ExcitationError
from ...files import write_columns
from ...machine.parameters import Parameters
from ...motion.trajectories import Trajectory, iso14242
from .excitation_summary import ExcitationPeaks, ExcitationSummary, limits_verdict
from .quantities import QUANTITIES
from .regressor import column_condition, regressor, regressor_from_kinematics

__all__ = ["DESIGN_QUANTITIES", "Excitation", "Limits", "condition_number", "excitation"]

#: The parameters an excitation is designed for, by label (see the module docstring).
DESIGN_QUANTITIES = (
    "I_m,xx",
    "I_m,yy",
    "I_m,zz",
    "I_m,xy",
    "I_m,xz",
    "I_m,yz",
    "m_L",
    "I_L",
    "μ_h",
    "μ_t",
    "τ_c,screw",
    "b_screw",
)


@dataclass(frozen=True)
class Limits:
    """What the rig allows, SI.

    Attributes:
        max_angle: largest |α|, |β|, |γ| in [rad].
        min_load, max_load: load range in [N].
        max_speed: slider speed in [m/s].
        max_acceleration: slider acceleration in [m/s²].
        torque_limit: motor torque in [N·m].
        min_cond_inv: smallest singularity measure.
    """

    max_angle: float = math.radians(30.0)
    min_load: float = 300.0
    max_load: float = 3000.0
    max_speed: float = 0.35
    max_acceleration: float = 2.5
    torque_limit: float = 0.6
    min_cond_inv: float = 0.25

    @classmethod
    def for_machine(cls, params: Parameters, **changes) -> Limits:
        """The defaults, with the parameter file's motor ratings and torque limit where it has them."""
        values: dict[str, Any] = {}
        if math.isfinite(params.control.torque_limit):
            values["torque_limit"] = params.control.torque_limit
        elif "peak_torque_Nmm" in params.motor:
            values["torque_limit"] = params.motor["peak_torque_Nmm"] * 1e-3
        if "max_speed_rpm" in params.motor:
            values["max_speed"] = params.motor["max_speed_rpm"] / 60.0 * params.lead
        values.update({k: v for k, v in changes.items() if v is not None})
        return cls(**values)


def _design_columns(labels: Sequence[str]) -> list[int]:
    names = [q.label for q in QUANTITIES]
    out = []
    for label in labels:
        if label not in names:
            raise ArgumentError("quantities", label, f"a parameter's label ({', '.join(names)})")
        out.append(names.index(label))
    return out


def condition_number(
    params: Parameters, trajectory: Trajectory, quantities: Sequence[str] = DESIGN_QUANTITIES, lever_spin: bool = True
) -> float:
    """The identification regressor's condition number along a trajectory (unit-norm columns of ``quantities``).

    Parameters the trajectory cannot tell apart make it infinite.
    """
    columns = _design_columns(quantities)
    return column_condition(regressor(params, trajectory, lever_spin)[:, :, columns].reshape(-1, len(columns)))


@dataclass(frozen=True, eq=False)
class Excitation:
    """A designed excitation: Fourier coefficients and what they achieve.

    Attributes:
        frequency: base frequency f in [Hz] (period 1/f).
        harmonics: H.
        coefficients: (4, 2H + 1) rows α, β, γ in [rad] and F_e in [N];
            columns c_0, then a_1, b_1, …, a_H, b_H.
        condition_number: of the regressor over one period.
        iso_condition_number: of the regressor over one ISO 14242-1 cycle, same parameters.
        quantities: the parameters designed for, by label.
        limits: the limits it respects.
        peaks: the largest |angle| [deg], slider speed [mm/s] and acceleration [mm/s²], motor torque [N·mm],
            the smallest singularity measure, the load range [N] (None until :func:`excitation` computes them).
        seconds: the design's run time in [s].
    """

    frequency: float
    harmonics: int
    coefficients: np.ndarray
    condition_number: float
    iso_condition_number: float
    quantities: tuple[str, ...]
    limits: Limits
    peaks: ExcitationPeaks | None = None
    seconds: float = math.nan

    def at(self, t) -> Trajectory:
        """The excitation at times t in [s] (exact derivatives)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        values, rates, accelerations = _series(self.coefficients, self.frequency, t)
        return Trajectory(t, values[:3].T, rates[:3].T, accelerations[:3].T, values[3], name="excitation")

    def trajectory(self, rate: float = 1000.0, duration: float | None = None) -> Trajectory:
        """Sampled at ``rate`` [Hz] over ``duration`` [s] (whole periods, rounded up; default one)."""
        period = 1.0 / self.frequency
        cycles = 1 if duration is None else max(1, math.ceil(duration / period - 1e-9))
        n = int(round(cycles * period * rate))
        return _replaced(self.at(np.arange(n) / rate), periodic=True)

    def write_csv(self, path: str | Path, rate: float = 1000.0, duration: float | None = None) -> Path:
        """A trajectory CSV (t_s, alpha_deg, beta_deg, gamma_deg, Fe_N) that every command reads.

        Whole periods; the last row repeats the first, so readers treat it as periodic.
        """
        trajectory = self.trajectory(rate, duration)
        t = np.append(trajectory.t, trajectory.t[-1] + 1.0 / rate)
        closing = self.at(t[-1:])
        q = np.vstack([trajectory.q, closing.q])
        load = np.append(trajectory.Fe, closing.Fe)
        columns = {
            "t_s": t,
            **{f"{name}_deg": np.degrees(q[:, k]) for k, name in enumerate(("alpha", "beta", "gamma"))},
            "Fe_N": load,
        }
        return write_columns(path, columns)

    def summary(self) -> ExcitationSummary:
        """The design as its record: condition numbers, peaks, their verdict against :attr:`limits`."""
        if self.peaks is None:
            raise ExcitationError("this excitation's peaks were not computed: design it with excitation()")
        return ExcitationSummary(
            frequency_Hz=self.frequency,
            period_s=1.0 / self.frequency,
            harmonics=self.harmonics,
            condition_number=self.condition_number,
            iso_condition_number=self.iso_condition_number,
            quantities=tuple(self.quantities),
            peaks=self.peaks,
            verdict=limits_verdict(self.peaks, self.limits),
            design_seconds=self.seconds,
        )


def _replaced(trajectory: Trajectory, **changes) -> Trajectory:
    """A copy of a trajectory with some fields changed."""
    fields: dict[str, Any] = dict(
        t=trajectory.t,
        q=trajectory.q,
        qd=trajectory.qd,
        qdd=trajectory.qdd,
        Fe=trajectory.Fe,
        name=trajectory.name,
        periodic=trajectory.periodic,
    )
    fields.update(changes)
    return Trajectory(**fields)


def _series(coefficients: np.ndarray, frequency: float, t: np.ndarray):
    """Values, first and second derivatives of the four series at times t: each (4, N)."""
    H = (coefficients.shape[1] - 1) // 2
    w = 2.0 * math.pi * frequency * np.arange(1, H + 1)
    arg = np.outer(w, t)  # (H, N)
    s, c = np.sin(arg), np.cos(arg)
    a, b = coefficients[:, 1::2], coefficients[:, 2::2]  # (4, H)
    values = coefficients[:, :1] + a @ s + b @ c
    rates = (a * w) @ c - (b * w) @ s
    accelerations = -(a * w**2) @ s - (b * w**2) @ c
    return values, rates, accelerations


def _evaluate(params, coefficients, frequency, grid, columns, lever_spin, limits):
    """log cond, and the constraint margins (≥ 0 when met, each scaled to its limit) over one period."""
    return _evaluate_many(params, [coefficients], frequency, grid, columns, lever_spin, limits)[0]


def _evaluate_many(params, sets, frequency, grid, columns, lever_spin, limits):
    """:func:`_evaluate` of several coefficient sets at once: one model run over all their samples, (log cond, margins) per set.

    One run of a few thousand samples costs little more than one of a hundred (the models are vectorised over
    samples), so a finite-difference gradient (one set per coefficient) costs about two evaluations, not ninety.
    """
    n, m = grid.size, len(sets)
    series = [_series(c, frequency, grid) for c in sets]
    values = np.concatenate([v for v, _, _ in series], axis=1)  # (4, m·n)
    rates = np.concatenate([r for _, r, _ in series], axis=1)
    accelerations = np.concatenate([a for _, _, a in series], axis=1)
    t = np.arange(m * n) / (n * frequency)
    trajectory = Trajectory(t, values[:3].T, rates[:3].T, accelerations[:3].T, values[3], name="excitation")
    kin = kinematics(params, trajectory, on_error="flag")
    flagged = np.array(kin.flagged, dtype=bool).reshape(m, n)
    # A set's first sample is compared with the previous set's last for a det J sign change: not a crossing of its own.
    first = kin.cond_inv.reshape(m, n)[:, 0]
    flagged[:, 0] &= ~(np.isfinite(first) & (first >= 1e-6))
    with np.errstate(invalid="ignore", divide="ignore"):
        tau = inverse_dynamics(params, kin, trajectory.Fe, lever_spin).total.reshape(m, n, 3)
        A_all = regressor_from_kinematics(params, kin, trajectory.Fe, lever_spin)[:, :, columns].reshape(
            m, n, 3, len(columns)
        )
    cond_inv = np.asarray(kin.cond_inv).reshape(m, n)
    Ld, Ldd = np.asarray(kin.Ld[:, 0]).reshape(m, n, 3), np.asarray(kin.Ldd[:, 0]).reshape(m, n, 3)
    out = []
    for j in range(m):
        v = values[:, j * n : (j + 1) * n]
        margins = [
            1.0 - np.abs(v[:3]).ravel() / limits.max_angle,
            (v[3] - limits.min_load) / limits.max_load,
            (limits.max_load - v[3]) / limits.max_load,
        ]
        if np.any(flagged[j]):  # out of reach, singular, or through a singularity: no numbers to give
            out.append((math.inf, np.concatenate(margins + [np.full(n, -1.0)] + [np.full(3 * n, -1.0)] * 3)))
            continue
        margins += [
            cond_inv[j] / limits.min_cond_inv - 1.0,
            1.0 - np.abs(Ld[j]).ravel() / limits.max_speed,
            1.0 - np.abs(Ldd[j]).ravel() / limits.max_acceleration,
            1.0 - np.abs(tau[j]).ravel() / limits.torque_limit,
        ]
        A = A_all[j].reshape(-1, len(columns))
        condition = column_condition(A) if np.all(np.isfinite(A)) else math.inf
        out.append((math.log(condition), np.concatenate(margins)))  # log(inf) = inf
    return out


def excitation(
    params: Parameters,
    frequency: float = 0.5,
    harmonics: int = 5,
    limits: Limits | None = None,
    quantities: Sequence[str] = DESIGN_QUANTITIES,
    lever_spin: bool = True,
    samples: int | None = None,
    seeds: int = 1,
    max_iter: int = 40,
    seed: int = 0,
) -> Excitation:
    """Design an excitation trajectory (module docstring).

    Args:
        params: the machine (the torque limit is checked with its inverse dynamics).
        frequency: base frequency f in [Hz]; the period is 1/f.
        harmonics: H, harmonics per series (the highest is H·f).
        limits: the rig's limits; None for :meth:`Limits.for_machine`.
        quantities: the parameters to design for, by label.
        lever_spin: as in the identification.
        samples: time samples per period where limits and regressor are
            evaluated while optimising; None for 20 per highest harmonic (at
            least 100). The result is checked on a grid ten times finer.
        seeds: random starts; the best result is kept.
        max_iter: SLSQP iterations per start.
        seed: the random seed.

    Returns:
        The excitation.

    Raises:
        ArgumentError: impossible settings.
        ExcitationError: no start within the limits, or a design that breaks them between its samples.
    """
    import time

    started = time.perf_counter()
    if isinstance(harmonics, bool) or not isinstance(harmonics, (int, np.integer)) or not 1 <= harmonics <= 50:
        raise ArgumentError("harmonics", harmonics, "a whole number from 1 to 50")
    if not (isinstance(frequency, (int, float)) and math.isfinite(frequency) and 0 < frequency <= 20):
        raise ArgumentError("frequency", frequency, "a base frequency above 0 and at most 20 Hz")
    limits = limits if limits is not None else Limits.for_machine(params)
    if not limits.min_load < limits.max_load:
        raise ArgumentError("limits", (limits.min_load, limits.max_load), "a load range in [N] that is not empty")
    columns = _design_columns(quantities)
    samples = samples or max(100, 20 * harmonics)
    grid = np.arange(samples) / (samples * frequency)
    H = harmonics
    rng = np.random.default_rng(seed)
    centre = np.array([0.0, 0.0, 0.0, 0.5 * (limits.min_load + limits.max_load)])
    span = np.array([limits.max_angle] * 3 + [0.5 * (limits.max_load - limits.min_load)])

    def pack(coefficients):
        return (coefficients / span[:, None]).ravel()

    def unpack(x):
        return x.reshape(4, 2 * H + 1) * span[:, None]

    cache: dict[bytes, tuple[float, np.ndarray]] = {}
    slopes: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def evaluate(x):
        key = x.tobytes()
        if key not in cache:
            if len(cache) > 4096:
                cache.clear()
            cache[key] = _evaluate(params, unpack(x), frequency, grid, columns, lever_spin, limits)
        return cache[key]

    def gradient(x):
        """Forward differences of the objective and the margins, every coefficient's step in one model run.

        The steps are SciPy's own for SLSQP's default ('2-point', relative step √eps).
        """
        key = x.tobytes()
        if key not in slopes:
            if len(slopes) > 64:
                slopes.clear()
            h = math.sqrt(np.finfo(float).eps) * np.where(x >= 0, 1.0, -1.0) * np.maximum(1.0, np.abs(x))
            h = (x + h) - x
            stepped = x + np.diag(h)
            results = _evaluate_many(
                params, [unpack(x)] + [unpack(row) for row in stepped], frequency, grid, columns, lever_spin, limits
            )
            (f0, c0), rest = results[0], results[1:]
            cache.setdefault(key, (f0, c0))
            slopes[key] = (
                np.array([(f - f0) / d for (f, _), d in zip(rest, h)]),
                np.column_stack([(c - c0) / d for (_, c), d in zip(rest, h)]),
            )
        return slopes[key]

    best = None
    for _ in range(max(1, seeds)):
        # A random start, amplitudes falling with the harmonic (a smooth motion), scaled down until it is feasible.
        coefficients = np.zeros((4, 2 * H + 1))
        coefficients[:, 0] = centre
        decay = 1.0 / np.repeat(np.arange(1, H + 1), 2) ** 1.5
        coefficients[:3, 1:] = rng.normal(size=(3, 2 * H)) * decay * span[:3, None] * 0.5
        # The load swings over most of its range: the hip joint and the thrust bearing differ only in
        # the bearing's share of the platform weight, which shows where the load is small.
        coefficients[3, 1:3] = (
            0.9 * span[3] * np.array([math.cos(phase := rng.uniform(0, 2 * math.pi)), math.sin(phase)])
        )
        for _ in range(40):
            x = pack(coefficients)
            value, margins = evaluate(x)
            if np.isfinite(value) and np.all(margins >= 0):
                break
            coefficients[:3, 1:] *= 0.7
        else:
            continue
        with np.errstate(invalid="ignore"):  # a step out of reach: inf − inf, as SciPy's own differences would give
            result = scipy.optimize.minimize(
                lambda x: evaluate(x)[0],
                x,
                method="SLSQP",
                jac=lambda x: gradient(x)[0],
                constraints=[{"type": "ineq", "fun": lambda x: evaluate(x)[1], "jac": lambda x: gradient(x)[1]}],
                options={"maxiter": max_iter, "ftol": 1e-6},
            )
        candidate = result.x
        value, margins = evaluate(candidate)
        if not (np.isfinite(value) and np.all(margins >= -1e-9)):
            candidate = x  # the optimiser ended outside the limits: keep its feasible start
            value, margins = evaluate(candidate)
        if best is None or value < best[0]:
            best = (value, candidate)
    if best is None:
        raise ExcitationError(
            "no excitation within the limits was found: relax the limits (speed, acceleration, torque, singularity measure)"
        )
    coefficients = unpack(best[1])
    # The limits held at the design samples; check them on a grid ten times finer, and shrink the
    # harmonics a little at a time where the motion overshoots between the samples.
    fine = np.arange(10 * samples) / (10 * samples * frequency)
    for _ in range(100):
        value, margins = _evaluate(params, coefficients, frequency, fine, columns, lever_spin, limits)
        if np.isfinite(value) and np.all(margins >= 0):
            break
        coefficients[:, 1:] *= 0.995
    else:
        raise ExcitationError(
            "the designed excitation breaks the limits between its samples: give more samples per period"
        )
    iso = condition_number(params, iso14242(rate=10 * samples), quantities, lever_spin)
    design = Excitation(frequency, H, coefficients, math.exp(value), iso, tuple(quantities), limits)
    trajectory = design.at(fine)
    kin = kinematics(params, trajectory)
    tau = inverse_dynamics(params, kin, trajectory.Fe, lever_spin).total
    peaks = ExcitationPeaks(
        angle_deg=float(np.degrees(np.abs(trajectory.q).max())),
        speed_mm_s=float(np.abs(kin.Ld).max() * 1e3),
        acceleration_mm_s2=float(np.abs(kin.Ldd).max() * 1e3),
        cond_inv_min=float(kin.cond_inv.min()),
        torque_Nmm=float(np.abs(tau).max() * 1e3),
        load_min_N=float(trajectory.Fe.min()),
        load_max_N=float(trajectory.Fe.max()),
    )
    return replace(design, peaks=peaks, seconds=time.perf_counter() - started)

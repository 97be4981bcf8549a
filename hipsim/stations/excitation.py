"""A motion that makes the kinematic calibration well-posed (``hipsim excite --for calibration``).

The calibration sees the per-chain values through ∂q_j/∂δ along the logged
motion (:func:`hipsim.stations.sensitivity.attitude_jacobian`); a motion that
moves one angle at a time, or stays near home, leaves combinations of them
nearly indistinguishable. The design: each angle a finite Fourier series of one
base frequency f, q_k(t) = Σ_{l=1..H} a_kl·sin(2πlft) + b_kl·cos(2πlft), its
coefficients drawn at random (amplitudes falling as 1/l, so the motion stays
smooth), scaled down until every sample of a period keeps the rig's limits
(:class:`hipsim.rig.identification.excitation.Limits`: angles, slider speed
and acceleration, the singularity measure of both platforms), and the best of
``seeds`` draws kept: the one whose calibration Jacobian over the values the
sensors can see (columns scaled to unit norm, each sensor angle's mean removed
when offsets are estimated) has the smallest condition number. A random search,
deterministic for a given seed: the Jacobian costs 40 inverse kinematics per
sample, too much for a gradient optimiser on every candidate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analytic.stations import platform_jacobian, platform_motion
from ..exceptions import ExcitationError
from ..files import write_columns
from ..machine.parameters import Parameters
from ..motion.trajectories import iso14242
from ..physics.orientation import inverse_condition_number
from ..rig.identification.excitation import Limits
from ..rig.identification.excitation_summary import CalibrationExcitationSummary, ExcitationPeaks, limits_verdict
from ..rig.identification.regressor import column_condition
from .sensitivity import Structure, attitude_jacobian, structure

__all__ = ["CalibrationExcitation", "calibration_condition", "calibration_excitation"]

#: Samples of one period the design is judged on.
DESIGN_SAMPLES = 240


def calibration_condition(
    params: Parameters, q: np.ndarray, offsets: bool = False, seen: Structure | None = None
) -> float:
    """The condition number of the calibration Jacobian along a motion q (N, 3) [rad] (both platforms at q).

    Over the values the sensors can see (:func:`~hipsim.stations.sensitivity.structure`), columns scaled to unit norm;
    infinite when the motion cannot tell two of them apart. ``seen``: that structure, if already known.
    """
    seen = seen or structure(params, offsets)
    Y = attitude_jacobian(params, np.stack([q, q], axis=1), seen.independent)
    if offsets:
        Y = Y - Y.mean(axis=0)
    return column_condition(Y.reshape(-1, seen.independent.size))


@dataclass(frozen=True, eq=False)
class CalibrationExcitation:
    """A designed calibration motion.

    Attributes:
        frequency: base frequency f in [Hz].
        coefficients: (3, 2H) rows α, β, γ in [rad]; columns a_1, b_1, …, a_H, b_H.
        condition_number: of the calibration Jacobian over one period.
        iso_condition_number: the same over the ISO 14242-1 cycle.
        peaks: largest |angle| [deg], slider speed [mm/s] and acceleration [mm/s²], smallest singularity measure.
        limits: the rig's limits it keeps.
    """

    frequency: float
    coefficients: np.ndarray
    condition_number: float
    iso_condition_number: float
    peaks: ExcitationPeaks
    limits: Limits

    def summary(self) -> CalibrationExcitationSummary:
        """The design as its record: condition numbers, peaks, their verdict against :attr:`limits`."""
        return CalibrationExcitationSummary(
            for_="calibration",
            frequency_Hz=self.frequency,
            harmonics=self.coefficients.shape[1] // 2,
            condition_number=self.condition_number,
            iso_condition_number=self.iso_condition_number,
            peaks=self.peaks,
            verdict=limits_verdict(self.peaks, self.limits),
        )

    def angles(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q, q̇, q̈ at times t [s] (N,), in [rad], [rad/s], [rad/s²], each (N, 3)."""
        return _series(self.coefficients, self.frequency, np.asarray(t))

    def write_csv(self, path: str | Path, rate: float, duration: float) -> Path:
        """A trajectory CSV (t_s, alpha_deg, beta_deg, gamma_deg, Fe_N at 300 N) of whole periods, the last row the first."""
        period = 1.0 / self.frequency
        cycles = max(1, math.ceil(duration / period - 1e-9))
        t = np.arange(int(round(cycles * period * rate)) + 1) / rate
        q = self.angles(t)[0]
        columns = {"t_s": t, **{f"{a}_deg": np.degrees(q[:, k]) for k, a in enumerate(("alpha", "beta", "gamma"))}}
        return write_columns(path, columns | {"Fe_N": np.full(t.size, 300.0)})


def _series(coefficients: np.ndarray, frequency: float, t: np.ndarray):
    a, b = coefficients[:, 0::2], coefficients[:, 1::2]
    w = 2 * np.pi * frequency * np.arange(1, a.shape[1] + 1)
    arg = t[:, None] * w[None, :]
    s, c = np.sin(arg), np.cos(arg)
    q = s @ a.T + c @ b.T
    qd = (c * w) @ a.T - (s * w) @ b.T
    qdd = -(s * w**2) @ a.T - (c * w**2) @ b.T
    return q, qd, qdd


def _peaks(params: Parameters, coefficients: np.ndarray, frequency: float, t: np.ndarray) -> ExcitationPeaks:
    q, qd, qdd = _series(coefficients, frequency, t)
    speed = acceleration = 0.0
    cond = math.inf
    # m_1's peaks as if its centre were fixed: a stack-up moves its carriages by ~|e|·ω more, far below the limits.
    fixed = params
    if params.geometry is not None and params.chains.stacked:
        fixed = params.replace(geometry=params.geometry.replace(spline=np.zeros(3)))
    for j in (1, 2):
        with np.errstate(invalid="ignore"):
            _, Ld, Ldd = platform_motion(fixed, q, qd, qdd, j)
            c = inverse_condition_number(platform_jacobian(params, q, j))
        speed = max(speed, float(np.nanmax(np.abs(Ld)) if np.all(np.isfinite(Ld)) else math.inf))
        acceleration = max(acceleration, float(np.nanmax(np.abs(Ldd)) if np.all(np.isfinite(Ldd)) else math.inf))
        cond = min(cond, float(np.min(c)) if np.all(np.isfinite(c)) else 0.0)
    return ExcitationPeaks(
        angle_deg=float(np.degrees(np.abs(q).max())),
        speed_mm_s=speed * 1e3,
        acceleration_mm_s2=acceleration * 1e3,
        cond_inv_min=cond,
    )


def calibration_excitation(
    params: Parameters,
    frequency: float = 0.2,
    harmonics: int = 5,
    limits: Limits | None = None,
    seeds: int = 8,
    offsets: bool = False,
    seed: int = 0,
) -> CalibrationExcitation:
    """Design a calibration motion (module docstring).

    Args:
        params: the machine (its drawing, or a calibrated one).
        frequency: base frequency in [Hz] (one period 1/f).
        harmonics: H, harmonics per angle.
        limits: the rig's limits (default :meth:`Limits.for_machine` with ±20° angles).
        seeds: random candidates drawn.
        offsets: judge the design for a calibration that estimates the sensors' offsets.
        seed: the first candidate's seed.
    """
    limits = limits or Limits.for_machine(params, max_angle=math.radians(20.0))
    t = np.arange(DESIGN_SAMPLES) / (DESIGN_SAMPLES * frequency)
    seen = structure(params, offsets)
    best: tuple[float, np.ndarray, ExcitationPeaks] | None = None  # condition number, coefficients, peaks
    for k in range(seeds):
        rng = np.random.default_rng([seed, k])
        coefficients = rng.normal(size=(3, 2 * harmonics)) / np.repeat(np.arange(1, harmonics + 1), 2)[None, :]
        coefficients *= limits.max_angle / np.abs(_series(coefficients, frequency, t)[0]).max()
        for _ in range(40):  # shrink until every limit holds
            peaks = _peaks(params, coefficients, frequency, t)
            if not limits_verdict(peaks, limits).failed:
                break
            coefficients = coefficients * 0.9
        else:
            continue
        q = _series(coefficients, frequency, t)[0]
        condition = calibration_condition(params, q, offsets, seen)
        if best is None or condition < best[0]:
            best = (condition, coefficients, peaks)
    if best is None:
        raise ExcitationError(
            "no calibration motion within the limits: relax --max-angle, --max-speed or --min-cond-inv"
        )
    condition, coefficients, peaks = best
    iso = calibration_condition(params, iso14242(rate=DESIGN_SAMPLES).q, offsets, seen)
    return CalibrationExcitation(frequency, coefficients, condition, iso, peaks, limits)

"""What an excitation design reports (``hipsim excite``): its peaks, its verdict against the rig's limits, its summary.

A design (:func:`hipsim.rig.identification.excitation.excitation`, or
:func:`hipsim.stations.excitation.calibration_excitation` with ``--for
calibration``) keeps the rig's limits (:class:`~hipsim.rig.identification.excitation.Limits`)
by construction; :func:`limits_verdict` states it with the numbers: PASS when every
peak is within its limit (a peak equal to its limit passes), else FAIL, each
limit named with its peak and its margin. A calibration motion has no motor
torque and a constant load: those are said not judged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

from ...records import Level, Record, Verdict, optional

__all__ = [
    "CalibrationExcitationSummary",
    "ExcitationPeaks",
    "ExcitationSummary",
    "limits_verdict",
]


class Limits(Protocol):
    """The rig's limits a motion keeps, SI (:class:`hipsim.rig.identification.excitation.Limits`, which imports this
    module: its fields here, not its import)."""

    @property
    def max_angle(self) -> float: ...
    @property
    def min_load(self) -> float: ...
    @property
    def max_load(self) -> float: ...
    @property
    def max_speed(self) -> float: ...
    @property
    def max_acceleration(self) -> float: ...
    @property
    def torque_limit(self) -> float: ...
    @property
    def min_cond_inv(self) -> float: ...


@dataclass(frozen=True)
class ExcitationPeaks(Record):
    """The extremes of a designed motion over one period, in file units.

    Attributes:
        angle_deg: largest |α|, |β|, |γ|.
        speed_mm_s, acceleration_mm_s2: largest slider speed and acceleration.
        cond_inv_min: smallest singularity measure (inverse condition number of J).
        torque_Nmm: largest motor torque (the starting machine's inverse dynamics); absent for a calibration motion.
        load_min_N, load_max_N: the load's range; absent for a calibration motion (its load is constant).
    """

    angle_deg: float
    speed_mm_s: float
    acceleration_mm_s2: float
    cond_inv_min: float
    torque_Nmm: float | None = optional()
    load_min_N: float | None = optional()
    load_max_N: float | None = optional()


def limits_verdict(peaks: ExcitationPeaks, limits: Limits) -> Verdict:
    """Whether a motion's peaks keep the rig's limits: PASS when each is within (equal passes), else FAIL.

    Args:
        peaks: the motion's peaks (file units).
        limits: the rig's limits (SI, :class:`~hipsim.rig.identification.excitation.Limits`).

    Returns:
        The verdict; its numbers each peak and limit in file units, and each margin (limit minus peak; for the
        singularity measure and the load's lower end, peak minus limit), the smallest margin first named when FAIL.
    """
    checks: list[tuple[str, str, float | None, float, bool]] = [  # (name, unit, peak, limit, a lower limit)
        ("angle", "deg", peaks.angle_deg, math.degrees(limits.max_angle), False),
        ("speed", "mm_s", peaks.speed_mm_s, limits.max_speed * 1e3, False),
        ("acceleration", "mm_s2", peaks.acceleration_mm_s2, limits.max_acceleration * 1e3, False),
        ("cond_inv", "", peaks.cond_inv_min, limits.min_cond_inv, True),
        ("torque", "Nmm", peaks.torque_Nmm, limits.torque_limit * 1e3, False),
        ("load_max", "N", peaks.load_max_N, limits.max_load, False),
        ("load_min", "N", peaks.load_min_N, limits.min_load, True),
    ]
    numbers: dict[str, float] = {}
    broken: list[str] = []
    skipped: list[str] = []
    for name, unit, peak, limit, lower in checks:
        suffix = f"_{unit}" if unit else ""
        if peak is None:
            skipped.append(name)
            continue
        margin = peak - limit if lower else limit - peak
        numbers |= {f"{name}_peak{suffix}": peak, f"{name}_limit{suffix}": limit, f"{name}_margin{suffix}": margin}
        if not margin >= 0:  # NaN fails
            broken.append(f"{name} {peak:.4g} beyond its limit {limit:.4g}{(' ' + unit) if unit else ''}")
    judged = "the motion's peaks against the rig's limits: " + (
        "; ".join(broken) if broken else f"each of {len(checks) - len(skipped)} within"
    )
    not_judged = ""
    if skipped:
        not_judged = (
            f"{', '.join(skipped)}: not computed for this motion (a calibration motion: no torque, a constant load)"
        )
    return Verdict(Level.FAIL if broken else Level.PASS, judged, not_judged, numbers)


@dataclass(frozen=True)
class ExcitationSummary(Record):
    """An excitation for identification (``hipsim excite``): the design, its condition numbers, peaks and verdict.

    Attributes:
        frequency_Hz, period_s, harmonics: the Fourier series' base frequency, period and harmonics.
        condition_number: of the identification regressor over one period (columns of ``quantities``).
        iso_condition_number: the same over one ISO 14242-1 cycle (what the design improves on).
        quantities: the parameters designed for, by label.
        peaks: the motion's extremes.
        verdict: its peaks against the rig's limits (:func:`limits_verdict`).
        design_seconds: the design's run time in [s].
    """

    frequency_Hz: float
    period_s: float
    harmonics: int
    condition_number: float
    iso_condition_number: float
    quantities: tuple[str, ...]
    peaks: ExcitationPeaks
    verdict: Verdict
    design_seconds: float

    @property
    def level(self) -> Level:
        """The verdict's level (for :func:`hipsim.records.exit_status`)."""
        return self.verdict.level


@dataclass(frozen=True)
class CalibrationExcitationSummary(Record):
    """A motion for the kinematic calibration (``hipsim excite --for calibration``): its condition numbers, peaks and
    verdict (``for`` is ``"calibration"``).

    Attributes:
        for_: what the motion is for (printed as ``for``).
        frequency_Hz, harmonics: the Fourier series' base frequency and harmonics.
        condition_number: of the calibration Jacobian over one period; iso_condition_number: over the ISO cycle.
        peaks: the motion's extremes (no torque, a constant load).
        verdict: its peaks against the rig's limits (:func:`limits_verdict`).
    """

    for_: str = field(metadata={"key": "for"})
    frequency_Hz: float
    harmonics: int
    condition_number: float
    iso_condition_number: float
    peaks: ExcitationPeaks
    verdict: Verdict

    @property
    def level(self) -> Level:
        """The verdict's level (for :func:`hipsim.records.exit_status`)."""
        return self.verdict.level

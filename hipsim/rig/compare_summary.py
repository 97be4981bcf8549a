"""What a model-versus-rig comparison reports (:meth:`hipsim.rig.compare.Comparison.summary`): per motor the torque
error and the model's parts, and the error per gait phase when the log repeats."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..records import Record, optional

__all__ = ["ComparisonSummary", "MotorError", "Phases"]


@dataclass(frozen=True)
class MotorError(Record):
    """One motor's model-minus-measured torque error, in [N·mm] and relative to the measured RMS and peak.

    Attributes:
        rms_error_away_from_reversals_Nmm, relative_rms_error_away_from_reversals: the same outside the windows
            around the motor's reversals (NaN when none is left).
        share_near_reversals: the share of the samples inside those windows.
        rms_error_Nmm, peak_error_Nmm, peak_error_t_s: the error's RMS, peak |error| and when.
        measured_rms_Nmm, measured_peak_Nmm: the measured torque's RMS and peak.
        relative_rms_error, relative_peak_error: error over measured (infinite when the measured is 0).
        model_parts_rms_Nmm: the model's torque parts' RMS, by column name (tau_m … tau_f).
    """

    rms_error_away_from_reversals_Nmm: float
    relative_rms_error_away_from_reversals: float
    share_near_reversals: float
    rms_error_Nmm: float
    peak_error_Nmm: float
    peak_error_t_s: float
    measured_rms_Nmm: float
    measured_peak_Nmm: float
    relative_rms_error: float
    relative_peak_error: float
    model_parts_rms_Nmm: dict[str, float]


@dataclass(frozen=True)
class Phases(Record):
    """The RMS error per tenth of the gait cycle: the bins' edges (cycle fractions), from what, its labels."""

    edges: list[float]
    from_: str = field(metadata={"key": "from"})
    heel_strike_s: float | None
    labels: list[str] | None
    rms_error_Nmm: dict[str, list[float]]


@dataclass(frozen=True)
class ComparisonSummary(Record):
    """A log compared with the model (docs/guide/rig.md lists the keys)."""

    log: str
    samples: int
    rate_Hz: float
    cutoff_Hz: float | None
    motion_from: str
    parameters: str
    lever_spin: bool
    motors: dict[str, MotorError]
    cond_inv_min: float
    period_s: float | None
    notes: list[str]
    phases: Phases | None = optional()

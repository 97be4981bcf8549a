"""What ``hipsim feasible`` reports: the limits a protocol crosses, what was checked and what not, the speed at which
it fits, and the verdict (FEASIBLE or NOT FEASIBLE), made beside the check (:mod:`hipsim.design.feasibility`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..motion.noise_check import SUGGESTED_CUTOFF
from ..records import Level, Record
from .feasibility import Crossing, Limits

__all__ = ["CrossingRecord", "FeasibilitySummary", "feasibility_line", "feasibility_summary"]


@dataclass(frozen=True)
class CrossingRecord(Record):
    """One limit crossed: the limit's key, the motor (None for the whole machine), when first, needed and allowed (SI),
    the excess ratio (≥ 1) and the line that says it."""

    limit: str
    motor: int | None
    t_s: float
    needed: float
    allowed: float
    excess: float
    message: str


@dataclass(frozen=True)
class FeasibilitySummary(Record):
    """A protocol against the machine's limits.

    Attributes:
        trajectory, parameters: where the motion and the machine came from.
        feasible: False when a limit is crossed; True when none is and every limit had a figure; None when none
            checked is crossed but some were not checked.
        checked, not_checked: the limits with a figure and those without.
        noise_flagged: the motion's noise check flagged it (its speeds and accelerations carry the noise).
        verdict: the verdict in one line (:func:`feasibility_line`).
        crossings: the limits crossed, worst first.
        speed_factor: the largest speed factor at which it fits (1 when it fits; None: at no speed).
        cycle_frequency_Hz: the cycle frequency at that factor (None without a period).
    """

    trajectory: str
    parameters: str
    feasible: bool | None
    checked: tuple[str, ...]
    not_checked: tuple[str, ...]
    noise_flagged: bool
    verdict: str
    crossings: tuple[CrossingRecord, ...]
    speed_factor: float | None
    cycle_frequency_Hz: float | None

    @property
    def level(self) -> Level:
        """NOT FEASIBLE when a limit is crossed, else FEASIBLE (for :func:`hipsim.records.exit_status`)."""
        return Level.NOT_FEASIBLE if self.crossings else Level.FEASIBLE


def feasibility_line(limits: Limits, crossings: Sequence[Crossing], drive_given: bool, noisy: bool) -> str:
    """The verdict in one line: what was checked, what was not (and why), and whether noise stands behind it.

    "within every machine limit" only when every limit of
    :data:`hipsim.design.feasibility.CHECKED_LIMITS` had a figure; otherwise
    the limits checked and those not, with the file that would give them.
    """
    unchecked = limits.unchecked()
    if crossings:
        text = f"crosses {len(crossings)} of the limits checked ({', '.join(limits.checked())})"
    elif not unchecked:
        text = f"within every machine limit ({', '.join(limits.checked())})"
    else:
        text = f"within the limits checked ({', '.join(limits.checked())})"
    if unchecked:
        where = (
            "not in the drive file or the parameter file's [motor] table"
            if drive_given
            else "no drive data: give --drive, or a [motor] table in the parameter file"
        )
        text += f"; not checked: {', '.join(unchecked)} ({where})"
    if noisy:
        text += (
            f"; on a motion the noise check flagged: its speeds and accelerations carry the noise "
            f"(filter it with --cutoff {SUGGESTED_CUTOFF:g})"
        )
    return text


def feasibility_summary(
    trajectory: str,
    parameters: str,
    limits: Limits,
    crossings: Sequence[Crossing],
    speed_factor: float | None,
    period_s: float | None,
    drive_given: bool,
    noisy: bool,
) -> FeasibilitySummary:
    """The summary of a feasibility check.

    Args:
        trajectory, parameters: names of the motion and the machine.
        limits: the limits checked.
        crossings: the limits crossed (:func:`hipsim.design.feasibility.check_feasibility`).
        speed_factor: the factor at which it fits (:func:`hipsim.design.feasibility.fitting_speed`; 1 without crossings).
        period_s: the cycle's period in [s], None when unknown.
        drive_given: a drive file was given (for the line's advice).
        noisy: the noise check flagged the motion.
    """
    unchecked = limits.unchecked()
    return FeasibilitySummary(
        trajectory=trajectory,
        parameters=parameters,
        feasible=False if crossings else (None if unchecked else True),
        checked=tuple(limits.checked()),
        not_checked=tuple(unchecked),
        noise_flagged=noisy,
        verdict=feasibility_line(limits, crossings, drive_given, noisy),
        crossings=tuple(
            CrossingRecord(c.limit, c.motor, c.t, c.needed, c.allowed, c.excess, c.message()) for c in crossings
        ),
        speed_factor=speed_factor,
        cycle_frequency_Hz=(speed_factor / period_s if speed_factor is not None and period_s else None),
    )

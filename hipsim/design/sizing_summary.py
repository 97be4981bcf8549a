"""What ``hipsim size`` (and the sizing inside ``hipsim report``) prints: typed records of a sizing, a catalogue's
ranking, their verdicts.

:func:`sizing_summary` makes the summary of one run's :class:`~hipsim.design.sizing.Sizing` (its demands, the
drive's checks, the binding one, the verdict of :func:`~hipsim.design.checks.checks_verdict`, and the margins'
bands when an identified file's covariance gave them); :func:`ranking_summary` the summary of a ranked catalogue,
with :func:`ranking_verdict`: FEASIBLE when some combination passes every check, NOT FEASIBLE when none does
though some were checked, NOT MADE when no check could be made at all.

The drive's parts (motor, amplifier, gearbox, screw) are echoed as the mappings their file gave (:func:`drive_summary`):
they are the input, not a result, and each catalogue may carry columns of its own.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from ..machine.drive_parts import Drive, SizingRules, TorqueSpeedCurve
from ..records import Level, Record, Verdict, optional
from .checks import Check, checks_verdict
from .ranking import Candidate
from .sizing import JointSizing, MarginBand, ModuleSizing, Sizing

__all__ = [
    "CandidateSummary",
    "CheckSummary",
    "DriveSummary",
    "MarginBandSummary",
    "RankingSummary",
    "RulesSummary",
    "ScrewChecks",
    "SizingSummary",
    "candidate_summary",
    "check_summary",
    "drive_summary",
    "ranking_summary",
    "ranking_verdict",
    "sizing_summary",
]


@dataclass(frozen=True)
class CheckSummary(Record):
    """One check of one module: value, limit and margin in its unit, pass/fail (null: not checked), its kind's words.

    Attributes:
        module: i (1, 2, 3); name: the check's key; value, limit: in ``unit``; margin: 1 − value/limit (or the inverse
        for a "min" bound); passed: None when not checked; detail: where, or what is missing; trajectory: the run's
        name; label, unit, bound ("max" or "min"), basis: the check's kind.
    """

    module: int
    name: str
    value: float | None
    limit: float | None
    margin: float | None
    passed: bool | None
    detail: str
    trajectory: str
    label: str
    unit: str
    bound: str
    basis: str


def check_summary(check: Check) -> CheckSummary:
    """The record of one :class:`~hipsim.design.checks.Check`, with its kind's label, unit, bound and basis."""
    kind = check.kind
    return CheckSummary(
        check.module,
        check.name,
        check.value,
        check.limit,
        check.margin,
        check.passed,
        check.detail,
        check.trajectory,
        kind.label,
        kind.unit,
        kind.bound,
        kind.basis,
    )


def _checks(checks: Iterable[Check]) -> tuple[CheckSummary, ...]:
    return tuple(check_summary(c) for c in checks)


def _maybe(check: Check | None) -> CheckSummary | None:
    return None if check is None else check_summary(check)


@dataclass(frozen=True)
class DriveSummary(Record):
    """The drive checked: its name, its file, and each part as given (curves as speed [rad/s] and torque [N·m] lists)."""

    name: str
    source: str
    motor: dict[str, Any] | None
    amplifier: dict[str, Any] | None
    gearbox: dict[str, Any] | None
    screw: dict[str, Any] | None


def _part(part: object) -> dict[str, Any] | None:
    """A drive part's figures as given (a torque–speed curve as its two lists); None for a part not fitted."""
    if part is None:
        return None
    out: dict[str, Any] = {}
    for key, value in vars(part).items():
        if isinstance(value, TorqueSpeedCurve):
            value = {"speed_rad_s": value.speed.tolist(), "torque_Nm": value.torque.tolist()}
        out[key] = value
    return out


def drive_summary(drive: Drive) -> DriveSummary:
    """The record of a drive: its parts echoed as mappings (module docstring)."""
    return DriveSummary(
        drive.name, drive.source, _part(drive.motor), _part(drive.amplifier), _part(drive.gearbox), _part(drive.screw)
    )


@dataclass(frozen=True)
class RulesSummary(Record):
    """The sizing rules checked against (:class:`~hipsim.machine.drive_parts.SizingRules`, their units there)."""

    inertia_ratio_max: float
    life_target_cycles: float
    winding_rise_max: float
    rated_winding_rise: float
    critical_speed_factor: float
    buckling_factor: float

    @classmethod
    def of(cls, rules: SizingRules) -> RulesSummary:
        """The record of ``rules``."""
        return cls(
            rules.inertia_ratio_max,
            rules.life_target_cycles,
            rules.winding_rise_max,
            rules.rated_winding_rise,
            rules.critical_speed_factor,
            rules.buckling_factor,
        )


@dataclass(frozen=True)
class MarginBandSummary(Record):
    """A check's margin with the identified parameters' uncertainty: its std, 95 % interval, and one-sided 95 % pass."""

    module: int
    name: str
    margin: float | None
    margin_std: float | None
    margin_lo95: float | None
    margin_hi95: float | None
    passes_with_95_confidence: bool | None

    @classmethod
    def of(cls, band: MarginBand) -> MarginBandSummary:
        """The record of a :class:`~hipsim.design.sizing.MarginBand`."""
        interval = band.interval
        return cls(
            band.check.module,
            band.check.name,
            band.check.margin,
            band.std,
            None if interval is None else interval[0],
            None if interval is None else interval[1],
            band.confident,
        )


@dataclass(frozen=True)
class SizingSummary(Record):
    """One run's sizing: the demand per module and joint, the drive, its rules and checks, the binding check (smallest
    margin), whether every check made passed (null: none made), the verdict, and the margins' bands when given."""

    modules: tuple[ModuleSizing, ...]
    joints: tuple[JointSizing, ...] | None
    drive: DriveSummary | None
    rules: RulesSummary
    checks: tuple[CheckSummary, ...]
    binding: CheckSummary | None
    passed: bool | None
    verdict: Verdict
    margin_bands: tuple[MarginBandSummary, ...] | None = optional()


def sizing_summary(size: Sizing, bands: Sequence[MarginBand] | None = None) -> SizingSummary:
    """The summary of a sizing (and of its margins' bands, None: none); its verdict is
    :func:`~hipsim.design.checks.checks_verdict` over the drive's checks."""
    what = "the drive" if size.drive is None else size.drive.name
    return SizingSummary(
        size.modules,
        size.joints,
        None if size.drive is None else drive_summary(size.drive),
        RulesSummary.of(size.rules),
        _checks(size.checks),
        _maybe(size.binding),
        size.passed,
        checks_verdict(size.checks, what),
        None if bands is None else tuple(MarginBandSummary.of(b) for b in bands),
    )


@dataclass(frozen=True)
class CandidateSummary(Record):
    """One motor × gearbox × screw combination of a ranking: its parts' names, pass/fail, smallest margin, binding
    check, the checks not made, every check, rated power [W] and its source, rotor inertia [kg·cm²], cost, the binding
    check among the motor's, the first failing check, and (ranked by size) that failure in words."""

    drive: str
    motor: str
    gearbox: str | None
    screw: str | None
    passed: bool | None
    margin: float | None
    binding: CheckSummary | None
    unchecked: tuple[str, ...]
    checks: tuple[CheckSummary, ...]
    rated_power_W: float | None
    rated_power_source: str
    rotor_inertia_kgcm2: float | None
    cost: float | None
    motor_binding: CheckSummary | None
    first_failure: CheckSummary | None
    first_failure_text: str | None = optional()


def candidate_summary(candidate: Candidate, first_failure_text: str | None = None) -> CandidateSummary:
    """The record of a ranked :class:`~hipsim.design.ranking.Candidate`; ``first_failure_text``: its first failure
    in words (the caller's sentence), None to leave the key out."""
    drive = candidate.drive
    power, source = candidate.rated_power
    inertia = drive.motor.rotor_inertia
    return CandidateSummary(
        drive.name,
        drive.motor.name,
        None if drive.gearbox is None else drive.gearbox.name,
        None if drive.screw is None else drive.screw.name,
        candidate.passed,
        candidate.margin,
        _maybe(candidate.binding),
        candidate.unchecked,
        _checks(candidate.checks),
        power,
        source,
        None if inertia is None else inertia * 1e4,
        drive.motor.cost,
        _maybe(candidate.motor_binding),
        _maybe(candidate.failure),
        first_failure_text,
    )


@dataclass(frozen=True)
class ScrewChecks(Record):
    """The checks that do not depend on the motor, once per screw (null: the machine's own)."""

    screw: str | None
    checks: tuple[CheckSummary, ...]


@dataclass(frozen=True)
class RankingSummary(Record):
    """``hipsim size --catalogue``: the rules, the combinations shown (best first), the order, the screws' own checks
    (ranked by size), and the verdict over every combination."""

    rules: RulesSummary
    candidates: tuple[CandidateSummary, ...]
    rank: str
    verdict: Verdict
    screw_checks: tuple[ScrewChecks, ...] | None = optional()


def ranking_verdict(candidates: Sequence[Candidate]) -> Verdict:
    """FEASIBLE when some combination passes every check made, NOT FEASIBLE when none passes though some check was
    made, NOT MADE when no check could be made of any (module docstring). Judged: how many combinations pass."""
    passing = sum(1 for c in candidates if c.passed is True)
    made = sum(1 for c in candidates if c.passed is not None)
    numbers = {"combinations": float(len(candidates)), "passing": float(passing), "checked": float(made)}
    unchecked = len(candidates) - made
    not_judged = f"{unchecked} combination(s) with no check made" if unchecked else ""
    if made == 0:
        return Verdict(Level.NOT_MADE, f"no check of any of {len(candidates)} combinations could be made", "", numbers)
    level = Level.FEASIBLE if passing else Level.NOT_FEASIBLE
    return Verdict(level, f"{passing} of {len(candidates)} combinations pass every check", not_judged, numbers)


def ranking_summary(
    candidates: Sequence[Candidate],
    shown: Sequence[Candidate],
    rules: SizingRules,
    rank: str,
    screws: Sequence[tuple[str | None, tuple[Check, ...]]] | None = None,
    failure_texts: Sequence[str | None] | None = None,
) -> RankingSummary:
    """The summary of a ranked catalogue.

    Args:
        candidates: every combination (the verdict is over them all).
        shown: those to list (e.g. the ``--top`` N).
        rules: the rules checked against.
        rank: the order ("size" or "margin").
        screws: (screw name, its motor-independent checks) once per screw; None to leave the key out.
        failure_texts: per shown combination its first failure in words; None to leave the key out.
    """
    texts: Sequence[str | None] = failure_texts if failure_texts is not None else [None] * len(shown)
    return RankingSummary(
        RulesSummary.of(rules),
        tuple(candidate_summary(c, t) for c, t in zip(shown, texts, strict=True)),
        rank,
        ranking_verdict(candidates),
        None if screws is None else tuple(ScrewChecks(name, _checks(checks)) for name, checks in screws),
    )

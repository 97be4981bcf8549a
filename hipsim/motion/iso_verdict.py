"""The ISO 14242-1 verdict on a station: the motion it went through, judged apart from the motion it was asked for.

A station (a platform of the rig, a simulated run) is asked for a desired
motion q_d and goes through q. Its verdict (:func:`station_iso_verdict`):

- the desired motion is ISO 14242-1 (it passes :func:`~hipsim.motion.iso_compliance.iso_check`):
  the station's motion q is judged against the waveform, PASS when every
  whole cycle keeps every quantity within tolerance, else FAIL;
- the desired motion is not ISO 14242-1: the station could not have followed
  the waveform by tracking it, so q's own deviation from the waveform is
  reported, and the station is judged on what it adds: PASS when its motion
  passes the check anyway or when its tracking error |q − q_d| keeps within
  the angle's tolerance at every sample, else FAIL. A line of its own
  (:attr:`StationIso.desired_line`) says that the desired motion is not the
  waveform, by how much, and how well it was tracked.

So a perfectly tracked non-ISO motion reads as a passing station with a
non-ISO input, and a badly tracked ISO motion as a failing station.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..exceptions import TrajectoryError
from ..records import Level, Record, Verdict, optional
from .iso_compliance import DEFAULT_TOLERANCES, QUANTITIES, IsoCheck, Tolerances, iso_check

__all__ = [
    "ANGLES",
    "UNITS",
    "CycleCheck",
    "DesiredIso",
    "IsoCheckSummary",
    "QuantityCheck",
    "StationIso",
    "Tracking",
    "binding_quantity",
    "iso_check_summary",
    "iso_check_verdict",
    "station_iso",
    "station_iso_verdict",
]

#: The angles, as the checks and the columns name them.
ANGLES = ("alpha", "beta", "gamma")

#: Each checked quantity's unit, as the JSON names it.
UNITS = {"alpha": "deg", "beta": "deg", "gamma": "deg", "load": "N", "frequency": "Hz"}


@dataclass(frozen=True)
class Tracking(Record):
    """How the station tracked its desired motion, per angle in [deg].

    Attributes:
        rms_deg: RMS of q − q_d over the samples.
        peak_abs_deg: the largest |q − q_d|.
    """

    rms_deg: dict[str, float]
    peak_abs_deg: dict[str, float]


@dataclass(frozen=True)
class DesiredIso(Record):
    """The desired motion's own ISO 14242-1 check.

    Attributes:
        iso: True when it passes (it is the waveform within tolerance).
        failing: the quantities it fails.
        worst_deg: its worst deviation from the waveform per angle in [deg].
    """

    iso: bool
    failing: tuple[str, ...]
    worst_deg: dict[str, float]


@dataclass(frozen=True)
class StationIso(Record):
    """The ISO 14242-1 verdict on one station (see the module's description for the rule).

    Attributes:
        verdict: PASS, FAIL or NOT MADE.
        judged: what was judged, with its numbers, in a sentence.
        failing: the quantities the station's motion fails against the waveform.
        cycles: whole cycles checked.
        worst_deg: the station's motion's worst deviation from the waveform per angle in [deg].
        desired: the desired motion's own check (None when it was not made).
        tracking: the tracking of the desired motion.
        reason: why the check was not made.
    """

    verdict: Level
    judged: str
    failing: tuple[str, ...] | None = optional()
    cycles: int | None = optional()
    worst_deg: dict[str, float] | None = optional()
    desired: DesiredIso | None = optional()
    tracking: Tracking | None = optional()
    reason: str | None = optional()

    @property
    def level(self) -> Level:
        """The verdict's level (for :func:`hipsim.records.exit_status`)."""
        return self.verdict

    @property
    def desired_line(self) -> str | None:
        """The line that says the desired motion is not the ISO 14242-1 waveform; None when it is (or was not checked)."""
        if self.desired is None or self.desired.iso:
            return None
        worst = max(self.desired.worst_deg.values())
        line = f"the desired motion is not the ISO 14242-1 waveform: worst {worst:.3g}° off"
        if self.tracking is not None:
            rms = ", ".join(f"{a} {v:.3g}°" for a, v in self.tracking.rms_deg.items())
            line += f"; tracking of it: RMS {rms}"
        return line


def _worst(check: IsoCheck) -> dict[str, float]:
    return {a: check.worst(a) for a in ANGLES}


def station_iso_verdict(
    name: str, achieved: IsoCheck, desired: IsoCheck | None, tracking: Tracking | None
) -> StationIso:
    """The verdict on a station from the two checks and its tracking (a pure function; the rule in the module).

    Args:
        name: the station, for the sentence ("m_2", "station 1", "computed torque").
        achieved: the check of the motion the station went through.
        desired: the check of the motion it was asked for; None: not known (judged as ISO).
        tracking: its tracking error per angle; None: not known.
    """
    worst = _worst(achieved)
    tol = achieved.tolerances
    desired_record = None
    if desired is not None:
        desired_record = DesiredIso(desired.passed, desired.failing, _worst(desired))
    common = dict(failing=achieved.failing, cycles=len(achieved.cycles), worst_deg=worst, tracking=tracking)
    against = ", ".join(f"{a} {worst[a]:.3g}°" for a in ANGLES)
    if achieved.passed:
        judged = f"{name}'s motion against the ISO 14242-1 waveform: worst {against}, within tolerance"
        return StationIso(Level.PASS, judged, desired=desired_record, **common)  # type: ignore[arg-type]
    if desired is None or desired.passed or tracking is None:
        judged = (
            f"{name}'s motion against the ISO 14242-1 waveform: worst {against}; fails {', '.join(achieved.failing)}"
        )
        return StationIso(Level.FAIL, judged, desired=desired_record, **common)  # type: ignore[arg-type]
    beyond = [a for a in ANGLES if not tracking.peak_abs_deg[a] <= getattr(tol, a)]
    peaks = ", ".join(f"{a} {tracking.peak_abs_deg[a]:.3g}° (±{getattr(tol, a):.3g}°)" for a in ANGLES)
    judged = (
        f"{name}'s share of its deviation from the ISO 14242-1 waveform (worst {against}), the desired motion "
        f"not being the waveform: its tracking error peaks at {peaks}"
    )
    level = Level.FAIL if beyond else Level.PASS
    return StationIso(level, judged, desired=desired_record, **common)  # type: ignore[arg-type]


def station_iso(
    name: str,
    t: np.ndarray,
    q: np.ndarray,
    q_d: np.ndarray,
    load: np.ndarray,
    tolerances: Tolerances = DEFAULT_TOLERANCES,
    source: str = "run",
    periodic: bool = False,
) -> StationIso:
    """Check a station's motion and its desired motion and give the verdict (NOT MADE when no whole cycle is found).

    Args:
        name: the station, for the sentence.
        t: sample times in [s], (N,).
        q: the motion the station went through [α, β, γ] in [rad], (N, 3).
        q_d: the motion it was asked for in [rad], (N, 3).
        load: the axial load in [N], (N,).
        tolerances: the limits.
        source: the run's name, for messages.
        periodic: the samples cover whole periods.
    """
    e = np.degrees(np.subtract(q, q_d))
    tracking = Tracking(
        {a: float(np.sqrt(np.mean(e[:, k] ** 2))) for k, a in enumerate(ANGLES)},
        {a: float(np.abs(e[:, k]).max()) for k, a in enumerate(ANGLES)},
    )
    try:
        achieved = iso_check(t, q, load, tolerances, source=source, periodic=periodic)
    except TrajectoryError as error:
        reason = error.args[0]  # the message as raised (a TrajectoryError always has one)
        return StationIso(Level.NOT_MADE, f"{name}'s motion: no ISO 14242-1 check", tracking=tracking, reason=reason)
    desired = iso_check(t, q_d, load, tolerances, source=source, periodic=periodic)
    return station_iso_verdict(name, achieved, desired, tracking)


@dataclass(frozen=True)
class QuantityCheck(Record):
    """One quantity over every cycle: its worst deviation, the tolerance, the cycles that left it."""

    unit: str
    worst: float
    tolerance: float
    cycles_failed: int
    passed: bool


@dataclass(frozen=True)
class CycleCheck(Record):
    """One cycle: its start, its frequency, each quantity's deviation (the frequency's from 1 Hz), and its verdict."""

    cycle: int
    start_s: float
    frequency_Hz: float
    alpha: float
    beta: float
    gamma: float
    load: float
    frequency: float
    passed: bool


#: What a run's ISO 14242-1 check does not judge (the verdict's ``not_judged``).
TOLERANCES_ASSUMED = (
    "the tolerances themselves: the defaults are assumed values; confirm them against your copy of ISO 14242-1"
)


def binding_quantity(quantities: Mapping[str, QuantityCheck]) -> str:
    """The quantity that decides a run's check: the first that left its tolerance (in the order given), else the one
    closest to it (the largest worst deviation / tolerance)."""
    failing = [name for name, q in quantities.items() if not q.passed]
    if failing:
        return failing[0]
    return max(quantities, key=lambda name: quantities[name].worst / quantities[name].tolerance)


def iso_check_verdict(quantities: Mapping[str, QuantityCheck], cycles: int) -> Verdict:
    """A run's verdict against ISO 14242-1 (``iso-check``): PASS when every quantity stayed within its tolerance in
    every whole cycle, else FAIL; the quantity that decides it named (:func:`binding_quantity`) with its worst
    deviation and tolerance. A pure function of the per-quantity checks.

    Args:
        quantities: per quantity (alpha, beta, gamma, load, frequency) its check over every cycle.
        cycles: the whole cycles checked.
    """
    numbers: dict[str, float] = {"cycles": float(cycles)}
    for name, q in quantities.items():
        numbers |= {f"{name}_worst_{q.unit}": q.worst, f"{name}_tolerance_{q.unit}": q.tolerance}
    name = binding_quantity(quantities)
    q = quantities[name]
    against = f"{q.worst:.3g} {q.unit} against ±{q.tolerance:.3g} {q.unit}"
    failing = [n for n, c in quantities.items() if not c.passed]
    if failing:
        judged = (
            f"{', '.join(failing)} left the tolerance in {cycles} whole cycle(s) checked; "
            f"worst {name}: {against} ({q.cycles_failed} cycle(s) outside)"
        )
        return Verdict(Level.FAIL, judged, TOLERANCES_ASSUMED, numbers)
    judged = (
        f"every one of {cycles} whole cycle(s) kept every angle, the load and the frequency within tolerance; "
        f"closest: {name}, worst deviation {against}"
    )
    return Verdict(Level.PASS, judged, TOLERANCES_ASSUMED, numbers)


@dataclass(frozen=True)
class IsoCheckSummary(Record):
    """A run checked against ISO 14242-1 (``hipsim iso-check``): the verdict, per quantity and per cycle.

    Attributes:
        source: the log or run checked.
        verdict: PASS when every cycle kept every quantity within tolerance, else FAIL (:func:`iso_check_verdict`).
        failing: the quantities that left their tolerance in a cycle.
        cycles: whole cycles checked.
        tolerances_assumed: the reminder that the default tolerances are assumed.
        quantities: per quantity (alpha, beta, gamma, load, frequency) its check.
        per_cycle: each cycle's check.
    """

    source: str
    verdict: Verdict
    failing: tuple[str, ...]
    cycles: int
    tolerances_assumed: str
    quantities: dict[str, QuantityCheck]
    per_cycle: tuple[CycleCheck, ...]

    @property
    def level(self) -> Level:
        """PASS or FAIL (for :func:`hipsim.records.exit_status`)."""
        return self.verdict.level

    @property
    def passed(self) -> bool:
        """Every cycle kept every quantity within tolerance (the verdict PASS)."""
        return self.verdict.level == Level.PASS


def iso_check_summary(check: IsoCheck) -> IsoCheckSummary:
    """The check as a record: per quantity the worst deviation, tolerance and cycles failed; per cycle each deviation;
    the verdict on them (:func:`iso_check_verdict`)."""
    quantities = {}
    for q in QUANTITIES:
        ok = check.passes(q)
        quantities[q] = QuantityCheck(
            UNITS[q], check.worst(q), getattr(check.tolerances, q), int((~ok).sum()), bool(ok.all())
        )
    cycles = tuple(
        CycleCheck(
            cycle=k + 1,
            start_s=c.start,
            frequency_Hz=c.frequency,
            alpha=c.alpha,
            beta=c.beta,
            gamma=c.gamma,
            load=c.load,
            frequency=c.deviation("frequency"),
            passed=all(bool(check.passes(q)[k]) for q in QUANTITIES),
        )
        for k, c in enumerate(check.cycles)
    )
    return IsoCheckSummary(
        check.source,
        iso_check_verdict(quantities, len(check.cycles)),
        check.failing,
        len(check.cycles),
        "defaults are assumed values: confirm them against your copy of ISO 14242-1",
        quantities,
        cycles,
    )

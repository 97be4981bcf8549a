"""ISO 14242-1 compliance of a run: did each cycle follow the standard's waveforms within tolerance?

Each cycle of the run is laid over the standard's waveforms (hipsim's
built-in cycle, spec §7.2, which approximates the standard's tables) and the
largest deviation of each angle and of the load is compared with a
tolerance, as is the cycle's frequency.

Cycles are aligned by heel strike (:mod:`hipsim.motion.gait_events`), refined
to a fraction of a sample: the load's first rising crossing of the middle of
its range (its 5th and 95th percentiles) after each heel strike, interpolated
between samples, is matched to the same relative crossing of the standard's
load. A cycle
runs from one such crossing to the next, so its period and frequency come
from them, and its phase s = (t − t₀)/T is what the standard's waveforms are
evaluated at. Only whole cycles are checked; a run that covers whole
periods of a motion that repeats (``periodic``) is checked as one period of
an endless run (:func:`periodic_extension`), so that its cycles are whole
wherever its heel strikes fall.

The default tolerances (:data:`DEFAULT_TOLERANCES`: ±3° on each angle, ±3 %
of the standard's 3000 N peak on the load, ±0.1 Hz on the frequency) are
assumed values: confirm them against your copy of the standard and set your
own (:func:`parse_tolerances`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..exceptions import ArgumentError, TrajectoryError
from .gait_events import detect_gait_events
from .trajectories import ISO_LOAD_KNOTS, iso14242_angles, iso14242_load

__all__ = [
    "DEFAULT_TOLERANCES",
    "NOMINAL_FREQUENCY",
    "CycleDeviation",
    "IsoCheck",
    "Tolerances",
    "iso_check",
    "parse_tolerances",
    "periodic_extension",
]

#: The standard's cycle frequency in [Hz].
NOMINAL_FREQUENCY = 1.0

#: The standard's peak load in [N], the reference of a load tolerance given in %.
PEAK_LOAD = max(load for _, load in ISO_LOAD_KNOTS)

#: The checked quantities, in the order of the tables.
QUANTITIES = ("alpha", "beta", "gamma", "load", "frequency")

_UNITS = {"alpha": "°", "beta": "°", "gamma": "°", "load": "N", "frequency": "Hz"}


@dataclass(frozen=True)
class Tolerances:
    """Largest deviations a compliant cycle may have.

    Attributes:
        alpha: flexion/extension in [°].
        beta: abduction/adduction in [°].
        gamma: internal/external rotation in [°].
        load: axial load in [N].
        frequency: cycle frequency in [Hz], from :data:`NOMINAL_FREQUENCY`.
    """

    alpha: float = 3.0
    beta: float = 3.0
    gamma: float = 3.0
    load: float = 0.03 * PEAK_LOAD
    frequency: float = 0.1

    def __post_init__(self):
        for field in fields(self):
            value = getattr(self, field.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
                raise ArgumentError("tolerance", f"{field.name}={value!r}", "a positive finite number")


#: The assumed default tolerances (see the module's description).
DEFAULT_TOLERANCES = Tolerances()


def parse_tolerances(text: str, base: Tolerances = DEFAULT_TOLERANCES) -> Tolerances:
    """Tolerances from ``"alpha=3,beta=3,gamma=3,load=3%,frequency=0.1"``; unnamed ones keep ``base``'s.

    Angles in [°], the load in [N] or in % of the standard's 3000 N peak, the frequency in [Hz].

    Raises:
        ArgumentError: an unknown name, a missing ``=``, or a value that is not a positive number.
    """
    changes = {}
    for item in (part.strip() for part in text.split(",")):
        if not item:
            continue
        name, sep, value = (s.strip() for s in item.partition("="))
        if not sep or name not in QUANTITIES:
            raise ArgumentError("--iso-tolerance", item, f"NAME=VALUE with NAME one of {', '.join(QUANTITIES)}")
        percent = value.endswith("%")
        if percent and name != "load":
            raise ArgumentError("--iso-tolerance", item, "a percentage for the load only")
        try:
            number = float(value.rstrip("%").strip())
        except ValueError:
            raise ArgumentError("--iso-tolerance", item, "a number after '='") from None
        changes[name] = number / 100.0 * PEAK_LOAD if percent else number
    return replace(base, **changes)


@dataclass(frozen=True)
class CycleDeviation:
    """One cycle's largest deviations from the standard.

    Attributes:
        start: time of the cycle's heel strike in [s].
        frequency: the cycle's frequency in [Hz].
        alpha, beta, gamma: largest absolute deviations of the angles in [°].
        load: largest absolute deviation of the load in [N].
    """

    start: float
    frequency: float
    alpha: float
    beta: float
    gamma: float
    load: float

    def deviation(self, quantity: str) -> float:
        """The deviation of ``quantity`` (one of :data:`QUANTITIES`), the frequency's from the nominal 1 Hz."""
        if quantity == "frequency":
            return abs(self.frequency - NOMINAL_FREQUENCY)
        return getattr(self, quantity)


@dataclass(frozen=True)
class IsoCheck:
    """The verdict on a run: per cycle and per quantity, within tolerance or not.

    Attributes:
        cycles: each whole cycle's deviations, in time order.
        tolerances: the limits applied.
        source: the log or run checked, for reports.
    """

    cycles: tuple[CycleDeviation, ...]
    tolerances: Tolerances
    source: str

    def passes(self, quantity: str) -> np.ndarray:
        """Per cycle, whether ``quantity`` kept within its tolerance, bool shape (cycles,)."""
        limit = getattr(self.tolerances, quantity)
        return np.array([cycle.deviation(quantity) <= limit for cycle in self.cycles], dtype=bool)

    def worst(self, quantity: str) -> float:
        """The largest deviation of ``quantity`` over all cycles (unit of :data:`QUANTITIES`)."""
        return max(cycle.deviation(quantity) for cycle in self.cycles)

    @property
    def failing(self) -> tuple[str, ...]:
        """The quantities that left their tolerance in at least one cycle, in the order of :data:`QUANTITIES`."""
        return tuple(q for q in QUANTITIES if not self.passes(q).all())

    @property
    def passed(self) -> bool:
        """True when every cycle kept every quantity within tolerance."""
        return not self.failing

    def summary(self) -> list[str]:
        """One line per quantity: worst deviation, tolerance, cycles failed."""
        lines = []
        for q in QUANTITIES:
            ok = self.passes(q)
            verdict = "pass" if ok.all() else f"FAIL in {int((~ok).sum())} of {ok.size} cycles"
            lines.append(
                f"{q}: worst {self.worst(q):.3g} {_UNITS[q]} (tolerance {getattr(self.tolerances, q):.3g} {_UNITS[q]}): {verdict}"
            )
        return lines


def _percentile_levels(load: np.ndarray) -> tuple[float, float]:
    low, high = np.percentile(load, [5.0, 95.0])
    return float(low), float(high)


def _rising_crossings(t: np.ndarray, y: np.ndarray, level: float) -> np.ndarray:
    """Times in [s] where y rises through ``level``, linearly interpolated between samples."""
    below = y < level
    k = np.flatnonzero(below[:-1] & ~below[1:])
    return t[k] + (level - y[k]) / (y[k + 1] - y[k]) * (t[k + 1] - t[k])


def _reference_crossing() -> float:
    """Cycle fraction at which the standard's load rises through the middle of its 5th–95th percentile range."""
    s = np.linspace(0.0, 1.0, 100_001)[:-1]
    load = iso14242_load(s)
    low, high = _percentile_levels(load)
    return float(_rising_crossings(s, load, 0.5 * (low + high))[0])


def periodic_extension(
    t: np.ndarray, q: np.ndarray, load: np.ndarray, copies: int = 3
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A periodic run's samples repeated ``copies`` times, the original in the middle copy (t, q, load as given).

    Args:
        t: evenly spaced sample times in [s], (N,), covering whole periods (the last sample not repeating the first).
        q: angles, (N, 3).
        load: load in [N], (N,).
        copies: an odd number of copies.
    """
    t, q, load = (np.asarray(x, dtype=float) for x in (t, q, load))
    span = (t[-1] - t[0]) * t.size / (t.size - 1)
    shifts = np.arange(copies) - copies // 2
    return (np.concatenate([t + k * span for k in shifts]), np.tile(q, (copies, 1)), np.tile(load, copies))


def iso_check(
    t: np.ndarray,
    q: np.ndarray,
    load: np.ndarray,
    tolerances: Tolerances = DEFAULT_TOLERANCES,
    source: str = "run",
    periodic: bool = False,
) -> IsoCheck:
    """Check each whole cycle of a run against the ISO 14242-1 waveforms (see the module's description).

    Args:
        t: sample times in [s], shape (N,), increasing.
        q: platform angles [α, β, γ] in [rad], shape (N, 3), as the gait curves give them.
        load: axial load in [N], shape (N,).
        tolerances: the limits.
        source: the log or run, for messages and reports.
        periodic: the samples cover whole periods of a motion that repeats
            (evenly spaced, the last not repeating the first): checked as one
            period of an endless run, each of its cycles once.

    Returns:
        The per-cycle deviations and the verdict.

    Raises:
        TrajectoryError: shapes that do not match, or fewer than one whole cycle.
    """
    t, q, load = (np.asarray(x, dtype=float) for x in (t, q, load))
    if t.ndim != 1 or q.shape != (t.size, 3) or load.shape != t.shape:
        raise TrajectoryError(f"times {t.shape}, angles {q.shape} and load {load.shape} do not match", source=source)
    if periodic and t.size > 1:
        step = (t[-1] - t[0]) / (t.size - 1)
        span = step * t.size
        whole = iso_check(*periodic_extension(t, q, load), tolerances, source)
        within = tuple(c for c in whole.cycles if t[0] - 0.5 * step <= c.start < t[0] + span - 0.5 * step)
        return IsoCheck(within, tolerances, source)
    low, high = _percentile_levels(load) if t.size else (0.0, 0.0)
    if not high - low > 1e-9 * max(abs(high), 1.0):
        raise TrajectoryError(
            "the load has no stance and swing levels, so no heel strike to align the cycles on", source=source
        )
    # The twin-peak load rises through its middle twice a cycle: take the first rise after each heel strike.
    mid = _rising_crossings(t, load, 0.5 * (low + high))
    strikes = detect_gait_events(t, load, source=source).t_heel_strikes
    after = np.searchsorted(mid, strikes)
    crossings = np.unique(mid[after[after < mid.size]])
    s_ref = _reference_crossing()
    dt = float(np.median(np.diff(t)))
    cycles: list[CycleDeviation] = []
    for first, second in zip(crossings[:-1], crossings[1:]):
        period = second - first
        start = first - s_ref * period
        inside = (t >= start) & (t < start + period)
        # A cycle is whole when its samples reach both of its ends.
        if start < t[0] - 0.5 * dt or start + period > t[-1] + 1.5 * dt:
            continue
        s = (t[inside] - start) / period
        q_ref, _, _ = iso14242_angles(s)
        deviation = np.degrees(np.abs(q[inside] - q_ref)).max(axis=0)
        load_deviation = float(np.abs(load[inside] - iso14242_load(s)).max())
        alpha, beta, gamma = (float(d) for d in deviation)
        cycles.append(CycleDeviation(float(start), 1.0 / period, alpha, beta, gamma, load_deviation))
    if not cycles:
        raise TrajectoryError(
            f"found no whole gait cycle ({crossings.size} heel strike(s) in {t[-1] - t[0]:.3g} s): the check needs at least one",
            source=source,
        )
    return IsoCheck(tuple(cycles), tolerances, source)

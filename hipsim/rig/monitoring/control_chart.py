"""The control chart of a wear test's friction: baseline, two-sided EWMA, engineering threshold, alarms and notices.

Per snapshot k (sorted by cycle) an estimate x_k of the load friction
coefficient a = r_h·μ_h + r_t·μ_t with standard error s_k: the two stations'
mean, or one station's when the loads separate them. A baseline period
(cycles FROM…TO, after running-in) gives the reference level μ₀ (mean of its
snapshots) and the between-snapshot spread σ₀ (their standard deviation, but
never below the estimates' own RMS standard error: with few baseline
snapshots the sample deviation can come out small by chance).

The chart is an EWMA (Roberts 1959; Montgomery, *Introduction to Statistical
Quality Control*, §9.2): z_k = λ·x_k + (1 − λ)·z_{k−1}, z₀ = μ₀, over the
snapshots after the baseline, with the control limits
μ₀ ± L·σ₀·√(λ/(2 − λ)·(1 − (1 − λ)^{2k})), λ = 0.2, L = 3, both sides: a
fall of the load term matters as much as a rise (a load-cell gain drift, a
specimen that lost contact, a wrong load). Why EWMA rather than CUSUM: the
failures a lab fears (lubricant breakdown, wear through a coating) start as
small persistent shifts, which EWMA is best at; its statistic is itself an
estimate of the current level in the estimates' unit, so it is drawn on the
same axes as the estimates; and combined with the engineering threshold it
reacts to a large step at the first snapshot after it (a step Δ moves z by
λ·Δ, beyond the limit when Δ > 5σ₀ for λ = 0.2, L = 3).

A snapshot is **significant** when z_k is beyond a limit (the chart's
signal: +1 above, −1 below). It is an **alarm** when, besides, the
snapshot's own change of the hip friction coefficient, (x_k − μ₀)/r_h, lies
on the same side and its worst case exceeds the engineering threshold D
(``alarm_rise``, 0.01 by default); a significant change below the threshold
is a **notice**: real, said, but not what the lab set as mattering. The worst
case: when the two stations share one load and cannot be told apart, x is
their mean, and a change d of the mean is up to 2d in one station (the other
unchanged), so the alarm holds 2·|d| against D (``worst`` = 2). Snapshots
before the baseline's end (running-in and the baseline itself) are shown,
never flagged.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import ArgumentError

__all__ = [
    "DEFAULT_ALARM_RISE",
    "DEFAULT_BASELINE",
    "EWMA_L",
    "EWMA_LAMBDA",
    "LEAST_BASELINE",
    "MIN_BASELINE",
    "Chart",
    "chart",
    "check_baseline_min",
    "parse_baseline",
]

#: The default engineering threshold: a rise of the hip friction coefficient of 0.01.
DEFAULT_ALARM_RISE = 0.01
#: The default baseline, in cycles: after half a million cycles of running-in (ISO 14242-2 weighs wear from
#: 0.5 million cycles on), the next half million.
DEFAULT_BASELINE = (500_000, 1_000_000)
#: EWMA weight λ and limit width L (in standard deviations of the EWMA statistic).
EWMA_LAMBDA = 0.2
EWMA_L = 3.0
#: Snapshots the baseline needs before the chart starts, by default: with three, σ₀ is so uncertain (its 95 % interval
#: spans a factor 6) that a chart on it gives notices and early alarms (issue 47); ``baseline_min`` changes it.
MIN_BASELINE = 5
#: The fewest a baseline may be set to need: a spread needs two.
LEAST_BASELINE = 2


def parse_baseline(text: str) -> tuple[int, int]:
    """``"500000:1000000"`` → (500000, 1000000), cycles, FROM ≤ TO.

    Raises:
        ArgumentError: anything else.
    """
    parts = str(text).replace("_", "").split(":")
    try:
        low, high = (int(float(p)) for p in parts) if len(parts) == 2 else (-1, -1)
    except (ValueError, OverflowError):
        low = high = -1
    if low < 0 or high < low:
        raise ArgumentError("baseline", text, "FROM:TO in cycles, 0 ≤ FROM ≤ TO, e.g. 500000:1000000")
    return low, high


def check_baseline_min(baseline_min: int) -> int:
    """``baseline_min`` checked: a whole number of snapshots ≥ :data:`LEAST_BASELINE`.

    Raises:
        ArgumentError: anything else.
    """
    if (
        isinstance(baseline_min, bool)
        or not isinstance(baseline_min, (int, np.integer))
        or baseline_min < LEAST_BASELINE
    ):
        raise ArgumentError("baseline_min", baseline_min, f"a whole number of snapshots ≥ {LEAST_BASELINE}")
    return int(baseline_min)


@dataclass(frozen=True)
class Chart:
    """The chart over the snapshots (arrays in the snapshots' order, sorted by cycle).

    Attributes:
        phase: per snapshot "running-in", "baseline" or "monitoring".
        mean: μ₀ in [mm], NaN without a complete baseline.
        spread: σ₀ in [mm].
        baseline_count: snapshots in the baseline.
        change: the hip friction coefficient's change (x − μ₀)/r_h, NaN without a baseline or estimate.
        change_std: its standard deviation (the snapshot's and the baseline mean's).
        ewma: z_k in [mm] (NaN before the monitoring phase, and where the snapshot has no estimate).
        lower: the lower control limit in [mm] (NaN likewise).
        upper: the upper control limit in [mm] (NaN likewise).
        signal: +1 where z is above the upper limit, −1 below the lower, else 0.
        flag: "alarm", "notice" or "" per snapshot (module docstring).
        worst: the factor from this chart's change to the worst station's (2: two stations' mean; 1: one station).
        threshold: (low, high) in [mm]: μ₀ ∓ D·r_h/worst, the engineering threshold on the estimate.
        note: why there is no chart yet, or "".
    """

    phase: np.ndarray
    mean: float
    spread: float
    baseline_count: int
    change: np.ndarray
    change_std: np.ndarray
    ewma: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    signal: np.ndarray
    flag: np.ndarray
    worst: float
    threshold: tuple[float, float]
    note: str = ""

    @property
    def alarm(self) -> np.ndarray:
        """1 where the snapshot is an alarm, else 0."""
        return (self.flag == "alarm").astype(int)


def chart(
    cycles: Sequence[int] | np.ndarray,
    estimate: Sequence[float] | np.ndarray,
    std: Sequence[float] | np.ndarray,
    hip_radius_mm: float,
    baseline: tuple[int, int] = DEFAULT_BASELINE,
    alarm_rise: float = DEFAULT_ALARM_RISE,
    worst: float = 1.0,
    lam: float = EWMA_LAMBDA,
    width: float = EWMA_L,
    baseline_min: int = MIN_BASELINE,
) -> Chart:
    """The control chart of the load friction estimates.

    Args:
        cycles: each snapshot's first cycle, sorted ascending.
        estimate: load friction coefficient in [mm] per snapshot (NaN: none for this snapshot; it is skipped).
        std: its standard deviation in [mm].
        hip_radius_mm: r_h in [mm], to turn a change of the estimate into one of μ_h.
        baseline: (FROM, TO) cycles of the baseline period.
        alarm_rise: the engineering threshold D, a change of μ_h in one station.
        worst: the worst station's change per change of the estimate (2 for the mean of two stations).
        lam: EWMA weight λ in (0, 1].
        width: limit width L.
        baseline_min: snapshots the baseline needs before the chart starts (at least :data:`LEAST_BASELINE`).
    """
    if not (isinstance(alarm_rise, (int, float)) and math.isfinite(alarm_rise) and alarm_rise > 0):
        raise ArgumentError("alarm_rise", alarm_rise, "a positive rise of the hip friction coefficient, e.g. 0.01")
    if not (math.isfinite(worst) and worst >= 1.0):
        raise ArgumentError("worst", worst, "the worst station's change per change of the estimate, at least 1")
    check_baseline_min(baseline_min)
    first = np.asarray(cycles, dtype=np.int64)
    x, s = np.asarray(estimate, dtype=float), np.asarray(std, dtype=float)
    n = x.size
    low, high = baseline
    phase = np.where(first < low, "running-in", np.where(first <= high, "baseline", "monitoring")).astype(object)
    nan = np.full(n, math.nan)
    known = np.isfinite(x)
    inside = (phase == "baseline") & known
    count = int(np.count_nonzero(inside))
    none = np.zeros(n, dtype=int)
    if count < baseline_min:
        note = (
            f"baseline incomplete: {count} of the {baseline_min} snapshots it needs within cycles {low}-{high}; "
            "the chart starts once it has them (widen --baseline or log snapshots more often"
            + (f"; --baseline-min {count} would chart on fewer, with notices and early alarms)" if count >= 2 else ")")
        )
        blank = np.full(n, "", dtype=object)
        return Chart(
            phase,
            math.nan,
            math.nan,
            count,
            nan,
            nan.copy(),
            nan.copy(),
            nan.copy(),
            nan.copy(),
            none,
            blank,
            worst,
            (math.nan, math.nan),
            note,
        )
    mean = float(np.mean(x[inside]))
    spread = max(float(np.std(x[inside], ddof=1)), float(np.sqrt(np.mean(s[inside] ** 2))))
    change = (x - mean) / hip_radius_mm
    change_std = np.sqrt(s**2 + spread**2 / count) / hip_radius_mm
    ewma, lower, upper = nan.copy(), nan.copy(), nan.copy()
    z, k = mean, 0
    for j in np.flatnonzero((phase == "monitoring") & known):
        k += 1
        z = lam * x[j] + (1.0 - lam) * z
        ewma[j] = z
        half = width * spread * math.sqrt(lam / (2.0 - lam) * (1.0 - (1.0 - lam) ** (2 * k)))
        lower[j], upper[j] = mean - half, mean + half
    with np.errstate(invalid="ignore"):
        signal = np.where(ewma > upper, 1, np.where(ewma < lower, -1, 0))
        beyond = (np.sign(change) == signal) & (worst * np.abs(change) > alarm_rise)
    flag = np.where(signal != 0, np.where(beyond, "alarm", "notice"), "").astype(object)
    margin = alarm_rise * hip_radius_mm / worst
    return Chart(
        phase,
        mean,
        spread,
        count,
        change,
        change_std,
        ewma,
        lower,
        upper,
        signal,
        flag,
        worst,
        (mean - margin, mean + margin),
    )

"""Gait events from the load curve: heel strike and toe-off, the cycle count and period, each sample's phase.

A hip simulator's load is high in stance and low in swing, so the load alone
marks the gait's events, in a log as in a trajectory file:

- **Detection, with hysteresis.** With ``low`` and ``high`` the load's 5th and
  95th percentiles, a sample is in stance once the load rises above
  ``low + rise·(high − low)`` and stays there until it falls below
  ``low + fall·(high − low)`` (defaults 25 % and 10 %). Noise that wanders
  around one level cannot flip the state twice; a log that starts in mid
  stance counts no heel strike until it has seen a swing.
- **Refinement to the load's rise.** The level crossing comes some samples
  after the load leaves its swing baseline. Heel strike is moved back to the
  last sample still at that baseline (the median of the preceding swing plus
  three times the sample noise, estimated from the swing's sample-to-sample
  differences); toe-off forward, symmetrically, to the first sample back at
  the following swing's baseline. A swing cut short by the log's start or end
  is measured on all the log's swing samples instead. On a noise-free curve that is the sample
  at the start of the rise, within one sample whatever the log's first
  sample; with noise, a few samples later.

A cycle runs from one heel strike to the next; its period is their interval.
:func:`gait_phase` gives every sample its percentage of the gait cycle from
heel strike and whether it is in stance (heel strike to toe-off) or swing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import TrajectoryError

__all__ = ["DEFAULT_FALL", "DEFAULT_RISE", "GaitEvents", "detect_gait_events", "gait_cycles", "gait_phase"]

#: Stance starts when the load rises above this fraction of its range above the swing level.
DEFAULT_RISE = 0.25

#: Stance ends when the load falls below this fraction of its range above the swing level.
DEFAULT_FALL = 0.10

#: Noise multiple above the swing baseline that still counts as baseline.
_NOISE_MULTIPLE = 3.0


@dataclass(frozen=True, eq=False)
class GaitEvents:
    """Heel strikes and toe-offs found in a load curve.

    Attributes:
        heel_strikes: sample indices of the heel strikes, increasing, shape (H,).
        toe_offs: sample indices of the toe-offs, increasing, shape (K,).
        t_heel_strikes: their times in [s], shape (H,).
        t_toe_offs: their times in [s], shape (K,).
        low: the swing level in [N] (the load's 5th percentile).
        high: the stance level in [N] (the load's 95th percentile).
    """

    heel_strikes: np.ndarray
    toe_offs: np.ndarray
    t_heel_strikes: np.ndarray
    t_toe_offs: np.ndarray
    low: float
    high: float

    @property
    def cycles(self) -> int:
        """Whole cycles, from one heel strike to the next."""
        return max(len(self.heel_strikes) - 1, 0)

    @property
    def periods(self) -> np.ndarray:
        """Each whole cycle's period in [s], shape (cycles,)."""
        return np.diff(self.t_heel_strikes)

    @property
    def period(self) -> float:
        """The median cycle period in [s]; NaN without a whole cycle."""
        return float(np.median(self.periods)) if self.cycles else float("nan")


def _swing_baseline(load: np.ndarray, start: int, stop: int) -> tuple[float, float]:
    """(median, noise) of the load over samples start:stop of a swing; noise from the sample-to-sample differences."""
    segment = load[max(start, 0) : max(stop, start + 1)]
    if segment.size == 0:
        return float("nan"), 0.0
    baseline = float(np.median(segment))
    steps = np.diff(segment)
    # The median absolute step of white noise σ is 0.6745·√2·σ.
    noise = float(np.median(np.abs(steps - np.median(steps)))) / (0.6745 * np.sqrt(2.0)) if steps.size >= 3 else 0.0
    return baseline, noise


def detect_gait_events(
    t: np.ndarray,
    load: np.ndarray,
    rise: float = DEFAULT_RISE,
    fall: float = DEFAULT_FALL,
    source: str = "load",
) -> GaitEvents:
    """Find heel strikes and toe-offs in a load curve (see the module's description).

    Args:
        t: sample times in [s], shape (N,), increasing.
        load: the axial load in [N], shape (N,).
        rise: stance starts above ``low + rise·(high − low)``, 0 < rise < 1.
        fall: stance ends below ``low + fall·(high − low)``, 0 < fall ≤ rise.
        source: the file or run the load comes from, for messages.

    Returns:
        The events; none when the load has no swing and stance levels (a constant load).

    Raises:
        TrajectoryError: shapes that differ, or thresholds out of order.
    """
    t = np.asarray(t, dtype=float)
    load = np.asarray(load, dtype=float)
    if t.shape != load.shape or t.ndim != 1:
        raise TrajectoryError(f"times {t.shape} and load {load.shape} must be 1-D of one length", source=source)
    if not (0.0 < fall <= rise < 1.0):
        raise TrajectoryError(
            f"gait event thresholds must satisfy 0 < fall ≤ rise < 1, got rise {rise}, fall {fall}", source=source
        )
    empty = np.zeros(0, dtype=int)
    if load.size < 3:
        return GaitEvents(empty, empty, np.zeros(0), np.zeros(0), float("nan"), float("nan"))
    low, high = (float(x) for x in np.percentile(load, [5.0, 95.0]))
    span = high - low
    if not span > 1e-9 * max(abs(high), 1.0):
        return GaitEvents(empty, empty, np.zeros(0), np.zeros(0), low, high)
    state = np.full(load.size, np.nan)
    state[load > low + rise * span] = 1.0
    state[load < low + fall * span] = 0.0
    known = np.flatnonzero(~np.isnan(state))
    # Forward-fill: between the thresholds a sample keeps the last state seen.
    filled = state[known[np.maximum(np.searchsorted(known, np.arange(load.size), side="right") - 1, 0)]]
    filled[: known[0]] = np.nan
    change = np.flatnonzero(np.diff(filled) != 0) + 1
    change = change[~np.isnan(filled[change - 1]) & ~np.isnan(filled[change])]
    ups = change[filled[change] == 1.0]
    downs = change[filled[change] == 0.0]

    # A swing cut by the log's start or end is too short to measure: those use every swing sample's level.
    swing = np.flatnonzero(filled == 0.0)
    overall = _swing_baseline(load[swing], 0, swing.size)

    heel, toe = [], []
    for k in ups:
        previous_down = downs[downs < k]
        start = int(previous_down[-1]) if previous_down.size else 0
        baseline, noise = _swing_baseline(load, start, k) if previous_down.size else overall
        level = baseline + max(_NOISE_MULTIPLE * noise, 1e-9 * span)
        at_base = np.flatnonzero(load[start:k] <= level)
        if at_base.size:  # else the log starts during the rise: that heel strike is not in it
            heel.append(start + int(at_base[-1]))
    for k in downs:
        next_up = ups[ups > k]
        stop = int(next_up[0]) if next_up.size else load.size
        baseline, noise = _swing_baseline(load, k, stop) if next_up.size else overall
        level = baseline + max(_NOISE_MULTIPLE * noise, 1e-9 * span)
        at_base = np.flatnonzero(load[k:stop] <= level)
        if at_base.size:  # else the log ends before the load is back at its swing level
            toe.append(k + int(at_base[0]))
    heel_strikes, toe_offs = np.array(heel, dtype=int), np.array(toe, dtype=int)
    return GaitEvents(heel_strikes, toe_offs, t[heel_strikes], t[toe_offs], low, high)


def gait_phase(t: np.ndarray, events: GaitEvents) -> tuple[np.ndarray, np.ndarray]:
    """Each sample's phase in the gait cycle from heel strike, and whether it is in stance.

    Inside a whole cycle the phase runs linearly from 0 % at one heel strike
    to 100 % at the next; before the first heel strike and after the last it
    continues with the median period.

    Args:
        t: sample times in [s], shape (N,).
        events: the events of the same samples (:func:`detect_gait_events`).

    Returns:
        (phase in [%] in [0, 100), shape (N,); stance, bool, shape (N,)).

    Raises:
        TrajectoryError: fewer than two heel strikes (no whole cycle to measure the period on).
    """
    t = np.asarray(t, dtype=float)
    strikes = events.t_heel_strikes
    if strikes.size < 2:
        raise TrajectoryError(
            f"found {strikes.size} heel strike(s) in the load; a whole gait cycle (two heel strikes) is needed to know the phase"
        )
    period = events.period
    k = np.clip(np.searchsorted(strikes, t, side="right") - 1, 0, strikes.size - 2)
    inside = (t >= strikes[0]) & (t < strikes[-1])
    length = np.where(inside, strikes[k + 1] - strikes[k], period)
    start = np.where(t < strikes[0], strikes[0], np.where(t >= strikes[-1], strikes[-1], strikes[k]))
    phase = np.mod(100.0 * (t - start) / length, 100.0)
    # Stance lasts from a heel strike to the first toe-off before the next heel strike.
    stance_percent = np.full(strikes.size - 1, np.nan)
    for i, (begin, end) in enumerate(zip(strikes[:-1], strikes[1:])):
        toe = events.t_toe_offs[(events.t_toe_offs > begin) & (events.t_toe_offs < end)]
        if toe.size:
            stance_percent[i] = 100.0 * (toe[0] - begin) / (end - begin)
    typical = float(np.nanmedian(stance_percent)) if np.isfinite(stance_percent).any() else float("nan")
    stance_percent = np.where(np.isnan(stance_percent), typical, stance_percent)
    return phase, phase < np.where(inside, stance_percent[k], typical)


def gait_cycles(motion) -> GaitEvents:
    """The gait events of a trajectory or a log's motion (anything with ``t`` in [s] and ``Fe`` in [N]; a rig log's ``trajectory``).

    Its :attr:`GaitEvents.cycles` is the log's cycle count (whole cycles,
    heel strike to heel strike) and :attr:`GaitEvents.period` its cycle period in [s].
    """
    motion = getattr(motion, "trajectory", motion)
    return detect_gait_events(motion.t, motion.Fe, source=getattr(motion, "name", "load"))

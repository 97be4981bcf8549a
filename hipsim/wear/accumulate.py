"""Wear over a test from the motion each station actually had: per-cycle integrals held over intervals of cycles.

A test's motion is known at a few moments: the monitor's snapshots (a few
cycles logged every so often), or one motion per station (a ``stations`` or
``simulate`` output) that stands for the whole test. Each known motion's
per-cycle integrals (:class:`~hipsim.wear.factors.MotionIntegrals`) stand for
an interval of cycles: a snapshot at cycle c_k for the cycles from the midpoint
with the one before to the midpoint with the one after; the first from the
test's first stop, the last to its last stop (:func:`snapshot_intervals`).

A factor k of a kind predicts the volume worn between cycles c₀ and c₁ as
k·Σ_k (overlap of [c₀, c₁] with interval k)·(interval k's integral): the
prediction at every stop (:meth:`Exposure.predicted_mm3`) is held against the
weighings per interval (:func:`interval_table`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError
from ..motion.gait_events import gait_cycles
from ..motion.trajectories import Trajectory
from ..records import Record
from .factors import KINDS, MotionIntegrals

__all__ = ["Exposure", "IntervalRow", "interval_table", "snapshot_intervals", "whole_cycles"]


def whole_cycles(trajectory: Trajectory) -> tuple[Trajectory, float]:
    """The trajectory from its first heel strike to its last (whole cycles), and the median cycle time in [s].

    Raises:
        ArgumentError: fewer than two heel strikes in the load (no whole cycle).
    """
    events = gait_cycles(trajectory)
    if events.cycles < 1:
        raise ArgumentError(
            trajectory.name, "fewer than two heel strikes", "a snapshot of at least one whole cycle (two heel strikes)"
        )
    first, last = int(events.heel_strikes[0]), int(events.heel_strikes[-1])
    return trajectory.slice(slice(first, last)), float(
        events.t_heel_strikes[-1] - events.t_heel_strikes[0]
    ) / events.cycles


def snapshot_intervals(snapshot_cycles: np.ndarray, first: float, last: float) -> np.ndarray:
    """The boundaries of the cycles each snapshot stands for, (K + 1,): midpoints between snapshots, the first from
    min(``first``, the first snapshot) and the last to max(``last``, the last snapshot).

    Raises:
        ArgumentError: snapshots not in increasing order of cycle.
    """
    c = np.asarray(snapshot_cycles, dtype=float)
    if c.ndim != 1 or c.size < 1 or np.any(np.diff(c) <= 0):
        raise ArgumentError("snapshot cycles", c, "increasing cycles, at least one")
    middle = (c[1:] + c[:-1]) / 2.0
    return np.concatenate([[min(first, c[0])], middle, [max(last, c[-1])]])


@dataclass(frozen=True, eq=False)
class Exposure:
    """One station's motion over the test: interval k, cycles ``boundaries[k]`` to ``boundaries[k + 1]``, had the
    per-cycle integrals ``motions[k]``.

    Attributes:
        station: the station.
        boundaries: (K + 1,) cycles, increasing.
        motions: (K,) each interval's integrals.
        source: where the motion came from, in words.
    """

    station: str
    boundaries: np.ndarray
    motions: tuple[MotionIntegrals, ...]
    source: str

    def __post_init__(self):
        b = np.asarray(self.boundaries, dtype=float)
        if b.ndim != 1 or b.size != len(self.motions) + 1 or np.any(np.diff(b) <= 0):
            raise ArgumentError("boundaries", b, f"{len(self.motions) + 1} increasing cycles")
        object.__setattr__(self, "boundaries", b)

    def integral(self, kind: str, c0: float, c1: float) -> float:
        """Σ over the intervals of (cycles of [c0, c1] in it) × its per-cycle integral of ``kind``, in [N·m]; cycles
        before the first interval take the first's motion, after the last the last's."""
        b = self.boundaries.copy()
        b[0], b[-1] = -math.inf, math.inf
        total = 0.0
        for k, motion in enumerate(self.motions):
            overlap = min(c1, b[k + 1]) - max(c0, b[k])
            if overlap > 0:
                total += overlap * motion.integral(kind)
        return total

    def mean(self, c0: float, c1: float) -> MotionIntegrals:
        """The mean per-cycle integrals over cycles c0 … c1 (the motion a fitted k belongs to)."""
        cycles = c1 - c0
        if not cycles > 0:
            first = self.motions[0] if c1 <= self.boundaries[0] else self.motions[-1]
            return first
        local, track = (self.integral(kind, c0, c1) / cycles for kind in KINDS)
        weights = []
        b = self.boundaries.copy()
        b[0], b[-1] = -math.inf, math.inf
        for k, motion in enumerate(self.motions):
            weights.append(max(min(c1, b[k + 1]) - max(c0, b[k]), 0.0) * motion.load_slide_integral_Nm)
        cs = np.array([m.cross_shear_work_weighted for m in self.motions])
        w = np.array(weights)
        mean_cs = float(np.sum(w * cs) / np.sum(w)) if np.sum(w) > 0 else math.nan
        return MotionIntegrals(local, track, mean_cs, f"{self.source}, cycles {c0:.0f} to {c1:.0f}")

    def predicted_mm3(self, k: float, kind: str, cycles: np.ndarray) -> np.ndarray:
        """The volume k predicts worn from ``cycles[0]`` to each of ``cycles`` in [mm³]."""
        c = np.asarray(cycles, dtype=float)
        return np.array([k * self.integral(kind, c[0], ck) for ck in c])


@dataclass(frozen=True)
class IntervalRow(Record):
    """One interval between stops: the volume measured and predicted in [mm³]."""

    station: str
    first_cycle: int
    last_cycle: int
    measured_mm3: float
    predicted_mm3: float


def interval_table(
    station: str, cycles: tuple[int, ...], volume_mm3: tuple[float, ...], exposure: Exposure, k: float, kind: str
) -> tuple[IntervalRow, ...]:
    """Per interval between stops: measured and predicted volume (k of ``kind`` over the exposure)."""
    predicted = exposure.predicted_mm3(k, kind, np.asarray(cycles, dtype=float))
    return tuple(
        IntervalRow(
            station,
            int(cycles[j]),
            int(cycles[j + 1]),
            float(volume_mm3[j + 1] - volume_mm3[j]),
            float(predicted[j + 1] - predicted[j]),
        )
        for j in range(len(cycles) - 1)
    )

"""The model against the rig: the model's torques along a rig log, beside the measured ones.

The logs are :mod:`hipsim.rig.logs.log`' (:func:`~hipsim.rig.logs.log.load_log` reads
one whole, :class:`~hipsim.rig.logs.log.LogPieces` in pieces); a comparison goes
through a log's windows, so it takes either.

:func:`compare_torques` runs the analytic model along the logged motion and load and
sets its torques (total and parts) beside the measured ones, per motor: RMS
and peak error, absolute and relative, where the peak error occurs, and the
error per phase of the cycle when the log repeats. The model's torques go
through the same low-pass as the measurement (a Coulomb friction step is as
sharp in the model as on the rig, and the filter smooths both alike), so the
error is the model's, not the filter's.

The model runs with the universal joints' lever spin (``lever_spin=True``),
the physics of the real joints; ``lever_spin=False`` gives the spec's
spin-free levers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analytic.engine import AnalyticModel
from ..machine.parameters import Parameters
from ..motion.gait_events import detect_gait_events
from ..results import ExactSum, Run, Torques
from .compare_summary import ComparisonSummary, MotorError, Phases
from .logs.log import Log, LogInfo, MeasuredLog
from .logs.reversals import reversal_mask
from .logs.smoothing import REVERSAL_PERIODS, lowpass

__all__ = [
    "FIGURE_SAMPLES",
    "PERIOD_SAMPLES",
    "REVERSAL_PERIODS",
    "Comparison",
    "compare_torques",
    "compare_log",
    "detect_period",
    "model_torques",
    "reversal_mask",
]

#: Most samples the period is detected from (:func:`detect_period`); a longer log's angles are taken every k-th sample.
PERIOD_SAMPLES = 1 << 18
#: Most samples a comparison in pieces keeps for its figures (every k-th; the statistics use every sample).
FIGURE_SAMPLES = 20_000


def model_torques(params: Parameters, log: MeasuredLog, lever_spin: bool = True) -> tuple[Run, dict[str, np.ndarray]]:
    """The analytic model along the log's motion and load, and its torques filtered as the log's were.

    Args:
        params: the machine.
        log: the log.
        lever_spin: as in :class:`hipsim.analytic.AnalyticModel`.

    Returns:
        The model run (all samples, unfiltered) and, by :class:`~hipsim.results.Torques`
        field (``total`` and the parts), the filtered torques in [N·m], (N, 3) each.

    Raises:
        PoseError: naming the time of a logged pose out of reach or singular.
    """
    run = AnalyticModel(params, lever_spin=lever_spin).run(log.trajectory)
    parts = {}
    for field in ("total", *Torques.PARTS):
        values = getattr(run.torques, field)
        parts[field] = values if log.cutoff is None else lowpass(values, log.rate, log.cutoff, log.name)
    return run, parts


def detect_period(t: np.ndarray, q: np.ndarray, threshold: float = 0.9) -> float | None:
    """The period of a repeating motion, or None.

    The first lag beyond the first dip where the autocorrelation of the angles
    (means removed, summed over the three) exceeds ``threshold`` of its value
    at zero, refined to the lag where the motion best repeats itself (to a
    fraction of a sample); the log must hold two periods at least.

    Args:
        t: evenly spaced times in [s], (N,).
        q: angles, (N, 3).
    """
    n = len(t)
    if n < 8:
        return None
    x = q - q.mean(axis=0)
    size = 1 << (2 * n - 1).bit_length()
    spectrum = np.fft.rfft(x, size, axis=0)
    correlation = np.fft.irfft(np.abs(spectrum) ** 2, size, axis=0)[:n].sum(axis=1)
    if correlation[0] <= 0:
        return None
    correlation /= correlation[0] * (n - np.arange(n)) / n  # unbiased: each lag over the samples it overlaps
    below = np.flatnonzero(correlation < 0.5)
    if below.size == 0:
        return None
    candidates = np.flatnonzero((np.arange(n) > below[0]) & (np.arange(n) <= n // 2) & (correlation > threshold))
    if candidates.size == 0:
        return None
    # The first peak above the threshold; then the lag where the motion best repeats itself (least mean
    # squared difference of x(t + lag) and x(t)), refined by a parabola through its neighbours.
    k = candidates[0]
    while k + 1 <= n // 2 and correlation[k + 1] > correlation[k]:
        k += 1

    def misfit(lag):
        return np.mean((x[lag:] - x[:-lag]) ** 2) if 0 < lag <= n // 2 else np.inf

    while misfit(k - 1) < misfit(k):
        k -= 1
    while misfit(k + 1) < misfit(k):
        k += 1
    a, b, c = misfit(k - 1), misfit(k), misfit(k + 1)
    shift = 0.5 * (a - c) / (a - 2 * b + c) if np.isfinite(a + c) and a - 2 * b + c > 0 else 0.0
    return float((k + shift) * (t[-1] - t[0]) / (n - 1))


class _ErrorSums:
    """The per-motor and per-phase error statistics of a comparison, gathered piece by piece with exact sums.

    Sums of squares are :class:`~hipsim.results.ExactSum` (the result does
    not depend on where the pieces are cut), peaks keep their first
    occurrence, so one piece and many give the same numbers from the same samples.
    """

    def __init__(self, period: float | None, t0: float, phase_bins: int):
        self.period, self.t0, self.bins = period, t0, phase_bins
        # Columns: error², measured², error² and measured² away from reversals (N·mm², 3 each),
        # the parts² (N·mm², 3 per part), the error² per phase bin (N·m², 3 per bin).
        self.sums = ExactSum(12 + 3 * len(Torques.PARTS) + (3 * phase_bins if period is not None else 0))
        self.samples, self.away, self.phase_samples = (
            0,
            np.zeros(3, dtype=np.int64),
            np.zeros(phase_bins, dtype=np.int64),
        )
        self.error_peak, self.error_peak_t, self.measured_peak = np.full(3, -1.0), np.zeros(3), np.zeros(3)
        self.cond_inv_min = math.inf

    #: Samples summed at a time: the exact sums' working arrays (some 60 columns) stay near 100 MB.
    BLOCK = 1 << 15

    def add(
        self, t: np.ndarray, measured: np.ndarray, model: dict[str, np.ndarray], cond_inv: np.ndarray, near: np.ndarray
    ) -> None:
        """Add samples: times in [s] (M,), torques in [N·m] (M, 3), singularity measure (M,), near reversals (M, 3)."""
        for a in range(0, t.size, self.BLOCK):
            part = slice(a, a + self.BLOCK)
            self._add(
                t[part],
                measured[part],
                {field: values[part] for field, values in model.items()},
                cond_inv[part],
                near[part],
            )

    def _add(self, t, measured, model, cond_inv, near) -> None:
        error = model["total"] - measured
        error_nmm, measured_nmm = error * 1e3, measured * 1e3
        away = ~near
        columns = [
            error_nmm**2,
            measured_nmm**2,
            np.where(away, error_nmm**2, 0.0),
            np.where(away, measured_nmm**2, 0.0),
        ]
        columns += [(model[part] * 1e3) ** 2 for part in Torques.PARTS]
        if self.period is not None:
            phase = np.mod((t - self.t0) / self.period, 1.0)
            which = np.minimum((phase * self.bins).astype(int), self.bins - 1)
            columns += [np.where((which == b)[:, None], error**2, 0.0) for b in range(self.bins)]
            self.phase_samples += np.bincount(which, minlength=self.bins)
        self.sums.add(np.hstack(columns))
        self.samples += t.size
        self.away += away.sum(axis=0)
        magnitude = np.abs(error_nmm)
        worst = np.argmax(magnitude, axis=0)
        for i in range(3):
            if magnitude[worst[i], i] > self.error_peak[i]:  # strictly: the first occurrence of the peak is kept
                self.error_peak[i], self.error_peak_t[i] = magnitude[worst[i], i], t[worst[i]]
        self.measured_peak = np.maximum(self.measured_peak, np.abs(measured_nmm).max(axis=0))
        self.cond_inv_min = min(self.cond_inv_min, float(np.min(cond_inv)))

    def result(self) -> tuple[dict[str, Any], np.ndarray | None]:
        """(statistics: ``motors``, ``parts``, ``cond_inv_min``, ``samples``), and the RMS error per phase bin and motor in [N·m] (B, 3) or None."""
        total = self.sums.total()
        n = self.samples
        error_rms, measured_rms = np.sqrt(total[0:3] / n), np.sqrt(total[3:6] / n)
        with np.errstate(invalid="ignore", divide="ignore"):
            away_rms, away_measured = np.sqrt(total[6:9] / self.away), np.sqrt(total[9:12] / self.away)
        parts = total[12 : 12 + 3 * len(Torques.PARTS)].reshape(-1, 3)
        motors, part_rms = {}, {}
        for i in range(3):
            has_away = self.away[i] > 0
            away, away_m = (float(away_rms[i]), float(away_measured[i])) if has_away else (math.nan, math.nan)
            motors[str(i + 1)] = {
                "rms_error_away_from_reversals_Nmm": away,
                "relative_rms_error_away_from_reversals": away / away_m if away_m > 0 else math.inf,
                "share_near_reversals": float((n - self.away[i]) / n),
                "rms_error_Nmm": float(error_rms[i]),
                "peak_error_Nmm": float(self.error_peak[i]),
                "peak_error_t_s": float(self.error_peak_t[i]),
                "measured_rms_Nmm": float(measured_rms[i]),
                "measured_peak_Nmm": float(self.measured_peak[i]),
                "relative_rms_error": float(error_rms[i] / measured_rms[i]) if measured_rms[i] > 0 else math.inf,
                "relative_peak_error": float(self.error_peak[i] / self.measured_peak[i])
                if self.measured_peak[i] > 0
                else math.inf,
            }
            part_rms[str(i + 1)] = {
                Torques.COLUMN[field]: float(np.sqrt(parts[p, i] / n)) for p, field in enumerate(Torques.PARTS)
            }
        phase_rms = None
        if self.period is not None:
            squares = total[12 + 3 * len(Torques.PARTS) :].reshape(self.bins, 3)
            phase_rms = np.full((self.bins, 3), np.nan)
            filled = self.phase_samples > 0
            phase_rms[filled] = np.sqrt(squares[filled] / self.phase_samples[filled, None])
        statistics = {"motors": motors, "parts": part_rms, "cond_inv_min": self.cond_inv_min, "samples": n}
        return statistics, phase_rms


@dataclass(frozen=True, eq=False)
class Comparison:
    """The model's torques along a log, beside the measured ones (usable samples only).

    The statistics (:meth:`motor_errors`, :meth:`summary`, ``phase_rms``) are
    over every usable sample; the arrays are the samples kept for the figures:
    all of them (:func:`compare_torques`), or every k-th (:func:`compare_log`).

    Attributes:
        log: the log's description (:meth:`hipsim.rig.logs.log.Log.info`).
        params: the machine the model ran with.
        lever_spin: whether the model's levers spin as their universal joints impose.
        t: sample times in [s], (N,).
        measured: measured motor torques in [N·m], (N, 3), filtered.
        model: the model's torques by field (``total`` and the five parts) in [N·m], (N, 3) each, filtered alike.
        cond_inv: the singularity measure along the log, (N,).
        near_reversal: samples near each motor's reversal (:func:`reversal_mask`), (N, 3) bool.
        period: the log's period in [s] when it repeats, else None.
        phase_edges: cycle fractions bounding the phase bins, (B + 1,), or None.
        phase_rms: RMS error per phase bin and motor in [N·m], (B, 3), or None.
        heel_strike: the time in [s] phase 0 is anchored at: a heel strike found in the
            load (:mod:`hipsim.motion.gait_events`), or the first usable sample when
            the load shows none; None without phases.
        stance: per phase bin, whether its middle lies in stance (from heel strike to toe-off), (B,) bool, or None.
        statistics: the error statistics over every usable sample (``motors``, ``parts``, ``cond_inv_min``, ``samples``).
    """

    log: LogInfo
    params: Parameters
    lever_spin: bool
    t: np.ndarray
    measured: np.ndarray
    model: dict[str, np.ndarray]
    cond_inv: np.ndarray
    near_reversal: np.ndarray
    period: float | None
    phase_edges: np.ndarray | None
    phase_rms: np.ndarray | None
    statistics: dict[str, Any]
    heel_strike: float | None = None
    stance: np.ndarray | None = None

    @property
    def error(self) -> np.ndarray:
        """Model minus measured motor torque in [N·m], (N, 3)."""
        return self.model["total"] - self.measured

    def motor_errors(self) -> dict[str, dict[str, float]]:
        """Per motor ("1", "2", "3"): RMS and peak error in [N·mm], relative to the measured RMS and peak, and when the peak occurs.

        ``*_away_from_reversals`` are the same over the samples outside the
        windows around that motor's reversals (:func:`reversal_mask`).
        """
        return {i: dict(entry) for i, entry in self.statistics["motors"].items()}

    def summary(self) -> ComparisonSummary:
        """Everything a script needs, torques in [N·mm] (:class:`hipsim.rig.compare_summary.ComparisonSummary`)."""
        motors = {
            i: MotorError(**entry, model_parts_rms_Nmm=dict(self.statistics["parts"][i]))
            for i, entry in self.motor_errors().items()
        }
        phases = None
        if self.phase_rms is not None and self.phase_edges is not None:  # computed together
            phases = Phases(
                edges=[float(x) for x in self.phase_edges],
                from_="heel strike" if self.stance is not None else "first sample",
                heel_strike_s=self.heel_strike,
                labels=None if self.stance is None else ["stance" if s else "swing" for s in self.stance],
                rms_error_Nmm={str(i + 1): [float(x) for x in self.phase_rms[:, i] * 1e3] for i in range(3)},
            )
        return ComparisonSummary(
            log=self.log.name,
            samples=int(self.statistics["samples"]),
            rate_Hz=float(self.log.rate),
            cutoff_Hz=self.log.cutoff,
            motion_from=self.log.motion_from,
            parameters=self.params.source,
            lever_spin=self.lever_spin,
            motors=motors,
            cond_inv_min=float(self.statistics["cond_inv_min"]),
            period_s=self.period,
            notes=list(self.log.notes),
            phases=phases,
        )


def _period(period: float | None, t: np.ndarray, q: np.ndarray | None, t_first: float, t_last: float) -> float | None:
    """The period to bin phases by: given, detected from the angles (when None), or None (0, or fewer than two cycles)."""
    if period is None:
        period = detect_period(t, q) if q is not None else None  # no angles: a period given, or none
    elif period <= 0:
        period = None
    if period is not None and (t_last - t_first) < 2 * period * (1 - 1e-9):
        period = None  # fewer than two cycles: no phases to average
    return period


def _phase_anchor(log: Log, period: float, first: int) -> tuple[float, float | None]:
    """Phase 0's time in [s] and the stance share of the cycle (None if unknown), from the load of the log's first window.

    The first heel strike of that window anchors the phases, so the per-phase
    table does not depend on where the log starts; a load without gait
    events leaves phase 0 at the first usable sample, as before.
    """
    window, core, _ = next(iter(log.windows()))
    t, load = window.trajectory.t, window.trajectory.Fe
    events = detect_gait_events(t, load, source=log.name)
    if events.heel_strikes.size == 0:
        return float(log.t[first]), None
    strikes, toes = events.t_heel_strikes, events.t_toe_offs
    stance = [
        (toes[toes > hs][0] - hs) / period for hs in strikes if (toes > hs).any() and (toes[toes > hs][0] - hs) < period
    ]
    return float(strikes[0]), (float(np.median(stance)) if stance else None)


def _gather(
    params: Parameters, windows, lever_spin: bool, period: float | None, t0: float, phase_bins: int, stride: int
):
    """Run the model along each (window, usable part, index of its first sample), its statistics and every ``stride``-th sample kept."""
    sums = _ErrorSums(period, t0, phase_bins)
    kept: dict[str, list] = {
        "t": [],
        "measured": [],
        "cond_inv": [],
        "near": [],
        **{f"model.{f}": [] for f in ("total", *Torques.PARTS)},
    }
    for window, part, start in windows:
        run, parts = model_torques(params, window, lever_spin)
        near = reversal_mask(params, window)[part]
        t, measured, cond_inv = window.t[part], window.tau[part], run.cond_inv[part]
        model = {field: values[part] for field, values in parts.items()}
        sums.add(t, measured, model, cond_inv, near)
        keep = np.flatnonzero((start + np.arange(t.size)) % stride == 0) if stride > 1 else slice(None)
        kept["t"].append(t[keep])
        kept["measured"].append(measured[keep])
        kept["cond_inv"].append(cond_inv[keep])
        kept["near"].append(near[keep])
        for field, values in model.items():
            kept[f"model.{field}"].append(values[keep])
    statistics, phase_rms = sums.result()
    arrays = {name: np.concatenate(values) for name, values in kept.items()}
    model = {field: arrays[f"model.{field}"] for field in ("total", *Torques.PARTS)}
    edges = np.linspace(0.0, 1.0, phase_bins + 1) if period is not None else None
    return arrays, model, statistics, edges, phase_rms


def compare_torques(
    params: Parameters,
    log: Log,
    lever_spin: bool = True,
    period: float | None = None,
    phase_bins: int = 10,
    figure_samples: int | None = None,
    period_samples: int | None = None,
    progress=None,
) -> Comparison:
    """The analytic model's torques along a log against the measured ones.

    The log goes window by window (:meth:`hipsim.rig.logs.log.Log.windows`): a log
    read in pieces gives the statistics of the whole log to round-off (see
    :class:`~hipsim.rig.logs.log.LogPieces`), in constant memory.

    Args:
        params: the machine.
        log: the log (:func:`~hipsim.rig.logs.log.load_log`, :class:`~hipsim.rig.logs.log.LogPieces`, or built from arrays).
        lever_spin: give the levers the universal joints' spin (the real
            joints' physics); False for the spec's spin-free levers.
        period: the log's period in [s]; None to detect it from the filtered
            angles (:func:`detect_period`); 0 for none.
        phase_bins: bins of the cycle for the error per phase.
        figure_samples: most samples kept for the figures (every k-th usable sample); None for all.
        period_samples: most samples the period is detected from (every k-th, so a
            very long log's period is found to a fraction of k samples rather than of one); None for all.
        progress: called with (samples done, samples in all) after each window.

    Returns:
        The comparison over the log's usable samples.

    Raises:
        PoseError: a logged pose out of reach or singular, naming its time.
    """
    first, stop = log.usable.start, log.usable.stop
    t = log.t
    if period is None:
        period = _period(None, *log.filtered_angles(period_samples), t[first], t[stop - 1])
    else:
        period = _period(period, t, None, t[first], t[stop - 1])
    stride = 1 if figure_samples is None else max(1, -(-(stop - first) // figure_samples))

    def windows():
        n = len(log)
        for window, core, start in log.windows():
            a, b = max(start, first), min(start + core.stop - core.start, stop)
            if a < b:
                yield window, slice(core.start + a - start, core.start + b - start), a - first
            if progress is not None:
                progress(start + core.stop - core.start, n)

    anchor, stance_share = _phase_anchor(log, period, first) if period is not None else (None, None)
    arrays, model, statistics, edges, phase_rms = _gather(
        params,
        windows(),
        lever_spin,
        period,
        anchor if anchor is not None else t[first],
        phase_bins,
        stride,
    )
    stance = None
    if edges is not None and stance_share is not None:
        stance = 0.5 * (edges[:-1] + edges[1:]) < stance_share
    return Comparison(
        log.info(),
        params,
        lever_spin,
        arrays["t"],
        arrays["measured"],
        model,
        arrays["cond_inv"],
        arrays["near"],
        period,
        edges,
        phase_rms,
        statistics,
        anchor,
        stance,
    )


def compare_log(
    params: Parameters,
    log: Log,
    lever_spin: bool = True,
    period: float | None = None,
    phase_bins: int = 10,
    figure_samples: int = FIGURE_SAMPLES,
    progress=None,
) -> Comparison:
    """:func:`compare_torques` for a log of any length: at most ``figure_samples`` kept for the figures, the period from at most :data:`PERIOD_SAMPLES`."""
    return compare_torques(params, log, lever_spin, period, phase_bins, figure_samples, PERIOD_SAMPLES, progress)

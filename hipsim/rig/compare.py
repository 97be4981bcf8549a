"""The model against the rig: measured logs in machine terms, and the model's torques along them.

:func:`load_log` reads a rig log (:mod:`hipsim.rig.logs`), turns
encoder heights into platform angles with the forward kinematics (checking
them against the attitude sensor when the log has both), low-passes and
differentiates the motion, and low-passes the torques and the load alike.

:func:`compare` runs the analytic model along the logged motion and load and
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
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analytic.engine import AnalyticModel
from ..analytic.forward_kinematics import forward_kinematics
from ..analytic.inverse_kinematics import slider_heights
from ..exceptions import ArgumentError, PoseError, TrajectoryError
from ..machine.parameters import Parameters, load_parameters
from .logs import (
    DEFAULT_CUTOFF,
    MeasuredLog,
    RigLogFile,
    edge_samples,
    filter_halo,
    lowpass,
    minimum_samples,
    smooth_motion,
)
from ..motion.trajectories import ANGLE_NAMES
from ..results import ExactSum, Run, Torques

__all__ = [
    "DEFAULT_TOLERANCE_DEG",
    "PIECE",
    "REVERSAL_PERIODS",
    "Comparison",
    "LogInfo",
    "LogPieces",
    "compare",
    "compare_log",
    "detect_period",
    "load_log",
    "model_torques",
    "reversal_mask",
]

#: Largest disagreement in [deg] allowed between the attitude sensor and the encoders' forward kinematics.
DEFAULT_TOLERANCE_DEG = 0.5
#: Half-width of the window around each motor's reversal, in periods of the low-pass cutoff (see :func:`reversal_mask`).
REVERSAL_PERIODS = 1.5
#: Samples per piece of a log compared in pieces (:class:`LogPieces`): some 70 MB of the model's working arrays.
PIECE = 20_000
#: How much an interpolating quintic spline's response to one sample shrinks per sample (its B-spline's root of largest modulus < 1).
SPLINE_DECAY = 0.4305753470999737
#: Samples beyond which that response is below round-off twice over (2⁻¹⁰⁶): a piece's spline reaches this far. Twice,
#: because a piece's end condition errs by as much as the second derivative of noisy samples, many times the angles.
SPLINE_HALO = int(math.ceil(106 * math.log(2) / -math.log(SPLINE_DECAY))) + 4
#: Most samples the period is detected from (:func:`detect_period`); a longer log's angles are taken every k-th sample.
PERIOD_SAMPLES = 1 << 18
#: Most samples a comparison in pieces keeps for its figures (every k-th; the statistics use every sample).
FIGURE_SAMPLES = 20_000


def load_log(
    path: str | Path,
    params: Parameters | None = None,
    torque_constant: float | None = None,
    cutoff: float | None = DEFAULT_CUTOFF,
    tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
) -> MeasuredLog:
    """Read a rig log and make it ready for the models.

    Args:
        path: the CSV log (columns in :mod:`hipsim.rig.logs`).
        params: the machine (for the encoders' forward kinematics); None for the published one.
        torque_constant: the motors' torque constant in [N·m/A], for logs of motor currents.
        cutoff: low-pass cutoff in [Hz] for motion, load and torques; None for
            none (signals already clean: the angles are then only splined).
        tolerance_deg: largest disagreement in [deg] between the attitude
            sensor's angles and the encoders' when the log has both (the
            encoders are used; beyond this the log is refused).

    Returns:
        The log, filtered and differentiated; its first and last
        :func:`~hipsim.rig.logs.edge_samples` samples are marked as the filter's edges.

    Raises:
        TrajectoryError: naming the file, line and column: the reader's
            errors, encoder heights no pose reaches, a disagreement of the two
            motion sources, a log too short to filter.
    """
    with LogPieces(path, params, torque_constant, cutoff, tolerance_deg) as pieces:
        return pieces.whole()


class LogPieces:
    """A rig log in overlapping pieces, each made ready for the models as :func:`load_log` makes the whole.

    The file is scanned once (:class:`~hipsim.rig.logs.RigLogFile`:
    every check, the times kept); encoder heights are turned into angles piece
    by piece, each piece continuing from the last pose of the one before, and
    the attitude sensor checked against them. :meth:`windows` then hands out
    the log a piece (``piece`` samples) at a time with :attr:`halo` samples of
    the log on either side: the low-pass, the spline, the model's low-pass and
    the reversal windows of a piece so see the log around it as the whole log
    does. The halo is two of the filter's transients
    (:func:`~hipsim.rig.logs.filter_halo`: its impulse response below
    round-off), the quintic spline's reach (its influence shrinks by
    :data:`SPLINE_DECAY` a sample) and a reversal window: the pieces then give
    the whole log's values to round-off (the forward kinematics, started from
    another pose, and the filters, started in another state, round differently
    in the last digits).

    Args:
        path, params, torque_constant, cutoff, tolerance_deg: as :func:`load_log`.
        piece: samples per piece (at least what the filter needs).

    Raises:
        TrajectoryError: as :func:`load_log`.
    """

    def __init__(
        self,
        path: str | Path,
        params: Parameters | None = None,
        torque_constant: float | None = None,
        cutoff: float | None = DEFAULT_CUTOFF,
        tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
        piece: int = PIECE,
    ):
        if isinstance(piece, bool) or not isinstance(piece, int) or piece < 1:
            raise ArgumentError("piece", piece, "a positive number of samples")
        self.params = params if params is not None else load_parameters()
        self.raw = raw = RigLogFile(path, torque_constant, block=max(piece, 1000))  # the scan's blocks no larger than a piece
        self.name, self.rate, self.cutoff, self.source = Path(raw.source).name, raw.rate, cutoff, raw.source
        notes = []
        if raw.ignored:
            notes.append(f"columns not used: {', '.join(raw.ignored)}")
        if raw.torque_from == "currents":
            notes.append(f"torques from the motor currents × {torque_constant:g} N·m/A")
        elif torque_constant is not None:
            notes.append("the log gives torques: the torque constant was not needed")
        n = len(raw)
        if cutoff is None:
            self.edge, self.halo, smallest = 0, SPLINE_HALO, 6
        else:
            lowpass(raw.t, self.rate, cutoff, raw.source)  # refuses a log too short to filter, before any work
            self.edge = edge_samples(self.rate, cutoff)
            self.halo = 2 * filter_halo(self.rate, cutoff) + SPLINE_HALO + _reversal_half(self.rate, cutoff) + 2
            smallest = minimum_samples(self.rate, cutoff)
        self.piece = max(piece, smallest)
        self._q = None
        if raw.has_heights:
            self.motion_from = "encoders"
            self._q = tempfile.TemporaryFile()
            worst = first = None  # (difference in deg, sample, angle) at worst and first beyond the tolerance
            q0 = None
            for a, b in self._cores():
                part = raw.piece(a, b)
                start = (part.angles[0] if part.angles is not None else None) if q0 is None else q0
                try:
                    q = forward_kinematics(self.params, part.heights, part.t, q0=start)
                except PoseError as error:
                    raise TrajectoryError(f"encoder heights L_11_mm … at {error}", source=raw.source, line=int(part.lines[error.index])) from None
                q0 = q[-1]
                np.ascontiguousarray(q).tofile(self._q)
                if part.angles is not None:
                    difference = np.degrees(np.abs(q - part.angles))
                    k, j = np.unravel_index(np.argmax(difference), difference.shape)
                    if worst is None or difference[k, j] > worst[0]:
                        worst = (float(difference[k, j]), a + int(k), int(j))
                    beyond = np.argwhere(difference > tolerance_deg)
                    if first is None and beyond.size:
                        k, j = beyond[0]
                        first = (float(difference[k, j]), a + int(k), int(j))
            if first is not None:
                raise TrajectoryError(
                    f"the attitude sensor and the encoders disagree by {first[0]:.3g}° in {ANGLE_NAMES[first[2]]} "
                    f"(tolerance {tolerance_deg:g}°; {worst[0]:.3g}° at worst, line {int(raw.lines[worst[1]])}): "
                    "check the sensor's mounting, zero and sign conventions, or the machine's parameters",
                    source=raw.source, line=int(raw.lines[first[1]]), column=f"{ANGLE_NAMES[first[2]]}_{raw.angle_unit}",
                )
            if worst is not None:
                notes.append(f"encoders used; the attitude sensor agrees within {worst[0]:.3g}° (tolerance {tolerance_deg:g}°)")
        else:
            self.motion_from = "angles"
        if cutoff is not None:
            notes.append(f"low-passed at {cutoff:g} Hz (zero-phase Butterworth); the first and last {self.edge / self.rate:.3g} s are the filter's edges")
        self.notes = tuple(notes)

    def __len__(self) -> int:
        return len(self.raw)

    def __enter__(self) -> "LogPieces":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Drop the temporary stores."""
        self.raw.close()
        if self._q is not None:
            self._q.close()

    @property
    def usable(self) -> slice:
        """The samples between the filter's edges."""
        return slice(self.edge, len(self) - self.edge)

    def _cores(self):
        n = len(self)
        for a in range(0, n, self.piece):
            yield a, min(a + self.piece, n)

    def _angles(self, lo: int, hi: int) -> np.ndarray:
        if self._q is None:
            return self.raw.piece(lo, hi).angles
        self._q.seek(lo * 24)
        return np.fromfile(self._q, dtype=float, count=3 * (hi - lo)).reshape(-1, 3)

    def _window(self, lo: int, hi: int, edge: int) -> MeasuredLog:
        raw = self.raw.piece(lo, hi)
        trajectory = smooth_motion(raw.t, self._angles(lo, hi), raw.Fe, self.cutoff, self.name, rate=self.rate)
        tau = raw.tau if self.cutoff is None else lowpass(raw.tau, self.rate, self.cutoff, self.source)
        return MeasuredLog(trajectory, tau, self.cutoff, self.name, self.motion_from, self.notes, raw.lines, edge, self.rate)

    def whole(self) -> MeasuredLog:
        """The whole log at once: what :func:`load_log` returns."""
        return self._window(0, len(self), self.edge)

    def windows(self):
        """The log in pieces.

        Yields:
            (window, core, start): a piece with its halo as a :class:`MeasuredLog` (no edges),
            the piece's samples in it (a slice), and the log's index of the piece's first sample.
        """
        n = len(self)
        for a, b in self._cores():
            lo, hi = max(0, a - self.halo), min(n, b + self.halo)
            yield self._window(lo, hi, 0), slice(a - lo, b - lo), a

    def filtered_angles(self, most: int) -> tuple[np.ndarray, np.ndarray]:
        """Times in [s] and low-passed angles in [rad] of the usable samples, every k-th so that at most ``most`` are kept."""
        first, stop = self.usable.start, self.usable.stop
        stride = max(1, -(-(stop - first) // most))
        times, angles = [], []
        n = len(self)
        for a, b in self._cores():
            lo, hi = max(0, a - self.halo), min(n, b + self.halo)
            q = self._angles(lo, hi)
            if self.cutoff is not None:
                q = lowpass(q, self.rate, self.cutoff, self.source)
            start = max(a, first)
            start += (first - start) % stride
            keep = np.arange(start, min(b, stop), stride)
            times.append(self.raw.t[keep])
            angles.append(q[keep - lo])
        return np.concatenate(times), np.concatenate(angles)


def _reversal_half(rate: float, cutoff: float) -> int:
    """Half-width in samples of the window around a reversal."""
    return int(math.ceil(REVERSAL_PERIODS * rate / cutoff))


def reversal_mask(params: Parameters, log: MeasuredLog) -> np.ndarray:
    """Samples near a reversal of each motor, (N, 3) bool.

    Where a slider reverses, its Coulomb friction flips, and the real motion
    sticks for a few milliseconds while the servo builds up the torque to
    move on; the low-passed motion runs smoothly through it, so the model
    along that motion cannot reproduce the torque there: the filtered
    torques differ by a short doublet around the reversal. A fit leaves these
    samples out of that motor's rows, and a comparison reports its errors
    with and without them. The window is :data:`REVERSAL_PERIODS` periods of
    the cutoff on either side of each sign change of the slider speed; an
    unfiltered log has none.
    """
    n = len(log)
    mask = np.zeros((n, 3), dtype=bool)
    if log.cutoff is None:
        return mask
    with np.errstate(invalid="ignore"):
        speed = np.gradient(slider_heights(params, log.trajectory.q * params.angle_signs)[:, 0, :], axis=0)
    half = _reversal_half(log.rate, log.cutoff)
    for i in range(3):
        crossings = np.flatnonzero(np.sign(speed[1:, i]) != np.sign(speed[:-1, i]))
        if crossings.size:
            marks = np.zeros(n + 1, dtype=int)
            np.add.at(marks, np.maximum(crossings - half, 0), 1)
            np.add.at(marks, np.minimum(crossings + half + 2, n), -1)
            mask[:, i] = np.cumsum(marks)[:n] > 0
    return mask


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
        self.samples, self.away, self.phase_samples = 0, np.zeros(3, dtype=np.int64), np.zeros(phase_bins, dtype=np.int64)
        self.error_peak, self.error_peak_t, self.measured_peak = np.full(3, -1.0), np.zeros(3), np.zeros(3)
        self.cond_inv_min = math.inf

    #: Samples summed at a time: the exact sums' working arrays (some 60 columns) stay near 100 MB.
    BLOCK = 1 << 15

    def add(self, t: np.ndarray, measured: np.ndarray, model: dict[str, np.ndarray], cond_inv: np.ndarray, near: np.ndarray) -> None:
        """Add samples: times in [s] (M,), torques in [N·m] (M, 3), singularity measure (M,), near reversals (M, 3)."""
        for a in range(0, t.size, self.BLOCK):
            part = slice(a, a + self.BLOCK)
            self._add(t[part], measured[part], {field: values[part] for field, values in model.items()}, cond_inv[part], near[part])

    def _add(self, t, measured, model, cond_inv, near) -> None:
        error = model["total"] - measured
        error_nmm, measured_nmm = error * 1e3, measured * 1e3
        away = ~near
        columns = [error_nmm**2, measured_nmm**2, np.where(away, error_nmm**2, 0.0), np.where(away, measured_nmm**2, 0.0)]
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
        parts = total[12:12 + 3 * len(Torques.PARTS)].reshape(-1, 3)
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
                "relative_peak_error": float(self.error_peak[i] / self.measured_peak[i]) if self.measured_peak[i] > 0 else math.inf,
            }
            part_rms[str(i + 1)] = {Torques.COLUMN[field]: float(np.sqrt(parts[p, i] / n)) for p, field in enumerate(Torques.PARTS)}
        phase_rms = None
        if self.period is not None:
            squares = total[12 + 3 * len(Torques.PARTS):].reshape(self.bins, 3)
            phase_rms = np.full((self.bins, 3), np.nan)
            filled = self.phase_samples > 0
            phase_rms[filled] = np.sqrt(squares[filled] / self.phase_samples[filled, None])
        statistics = {"motors": motors, "parts": part_rms, "cond_inv_min": self.cond_inv_min, "samples": n}
        return statistics, phase_rms


@dataclass(frozen=True)
class LogInfo:
    """What a comparison reports of its log when the log was compared in pieces (a :class:`MeasuredLog`'s description).

    Attributes:
        name: the log's name (its file).
        rate: sample rate in [Hz].
        cutoff: the low-pass cutoff in [Hz], or None.
        motion_from: "angles" or "encoders".
        notes: how the log was read.
    """

    name: str
    rate: float
    cutoff: float | None
    motion_from: str
    notes: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class Comparison:
    """The model's torques along a log, beside the measured ones (usable samples only).

    The statistics (:meth:`motor_errors`, :meth:`summary`, ``phase_rms``) are
    over every usable sample; the arrays are the samples kept for the figures:
    all of a log compared whole (:func:`compare`), every k-th of one compared
    in pieces (:func:`compare_log`).

    Attributes:
        log: the log (its description, :class:`LogInfo`, when compared in pieces).
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
        statistics: the error statistics over every usable sample (``motors``, ``parts``, ``cond_inv_min``, ``samples``).
    """

    log: MeasuredLog | LogInfo
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

    def summary(self) -> dict[str, Any]:
        """Everything a script needs, JSON-ready, torques in [N·mm]."""
        motors = self.motor_errors()
        for i, entry in motors.items():
            entry["model_parts_rms_Nmm"] = dict(self.statistics["parts"][i])
        out: dict[str, Any] = {
            "log": self.log.name,
            "samples": int(self.statistics["samples"]),
            "rate_Hz": float(self.log.rate),
            "cutoff_Hz": self.log.cutoff,
            "motion_from": self.log.motion_from,
            "parameters": self.params.source,
            "lever_spin": self.lever_spin,
            "motors": motors,
            "cond_inv_min": float(self.statistics["cond_inv_min"]),
            "period_s": self.period,
            "notes": list(self.log.notes),
        }
        if self.phase_rms is not None:
            out["phases"] = {
                "edges": [float(x) for x in self.phase_edges],
                "rms_error_Nmm": {str(i + 1): [float(x) for x in self.phase_rms[:, i] * 1e3] for i in range(3)},
            }
        return out


def _period(period: float | None, t: np.ndarray, q: np.ndarray | None, t_first: float, t_last: float) -> float | None:
    """The period to bin phases by: given, detected from the angles (when None), or None (0, or fewer than two cycles)."""
    if period is None:
        period = detect_period(t, q)
    elif period <= 0:
        period = None
    if period is not None and (t_last - t_first) < 2 * period * (1 - 1e-9):
        period = None  # fewer than two cycles: no phases to average
    return period


def _gather(params: Parameters, windows, lever_spin: bool, period: float | None, t0: float, phase_bins: int, stride: int):
    """Run the model along each (window, usable part, index of its first sample), its statistics and every ``stride``-th sample kept."""
    sums = _ErrorSums(period, t0, phase_bins)
    kept: dict[str, list] = {"t": [], "measured": [], "cond_inv": [], "near": [], **{f"model.{f}": [] for f in ("total", *Torques.PARTS)}}
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


def compare(
    params: Parameters,
    log: MeasuredLog,
    lever_spin: bool = True,
    period: float | None = None,
    phase_bins: int = 10,
) -> Comparison:
    """The analytic model's torques along a log against the measured ones.

    Args:
        params: the machine.
        log: the log (:func:`load_log`).
        lever_spin: give the levers the universal joints' spin (the real
            joints' physics); False for the spec's spin-free levers.
        period: the log's period in [s]; None to detect it from the angles
            (:func:`detect_period`); 0 for none.
        phase_bins: bins of the cycle for the error per phase.

    Returns:
        The comparison over the log's usable samples.

    Raises:
        PoseError: a logged pose out of reach or singular, naming its time.
    """
    keep = log.usable
    t = log.t[keep]
    period = _period(period, t, log.trajectory.q[keep] if period is None else None, t[0], t[-1])
    arrays, model, statistics, edges, phase_rms = _gather(params, [(log, keep, 0)], lever_spin, period, t[0], phase_bins, 1)
    return Comparison(log, params, lever_spin, arrays["t"], arrays["measured"], model, arrays["cond_inv"], arrays["near"],
                      period, edges, phase_rms, statistics)


def compare_log(
    params: Parameters,
    pieces: LogPieces,
    lever_spin: bool = True,
    period: float | None = None,
    phase_bins: int = 10,
    figure_samples: int = FIGURE_SAMPLES,
    progress=None,
) -> Comparison:
    """:func:`compare` of a log of any length in constant memory: the log in pieces (:class:`LogPieces`).

    The statistics are :func:`compare`'s of the whole log to round-off (see
    :class:`LogPieces`); the arrays kept for the figures are every k-th usable
    sample, at most ``figure_samples``. The period, when detected, comes from
    the filtered angles (every k-th when the log has more than
    :data:`PERIOD_SAMPLES` usable samples, so a very long log's period is
    found to a fraction of k samples rather than of one).

    Args:
        params: the machine.
        pieces: the log.
        lever_spin, period, phase_bins: as :func:`compare`.
        figure_samples: most samples kept for the figures.
        progress: called with (samples done, samples in all) after each piece.

    Raises:
        PoseError: a logged pose out of reach or singular, naming its time.
    """
    first, stop = pieces.usable.start, pieces.usable.stop
    t = pieces.raw.t
    if period is None:
        period = _period(None, *pieces.filtered_angles(PERIOD_SAMPLES), t[first], t[stop - 1])
    else:
        period = _period(period, t, None, t[first], t[stop - 1])
    stride = max(1, -(-(stop - first) // figure_samples))

    def windows():
        n = len(pieces)
        for window, core, start in pieces.windows():
            a, b = max(start, first), min(start + core.stop - core.start, stop)
            if a < b:
                yield window, slice(core.start + a - start, core.start + b - start), a - first
            if progress is not None:
                progress(start + core.stop - core.start, n)

    arrays, model, statistics, edges, phase_rms = _gather(params, windows(), lever_spin, period, t[first], phase_bins, stride)
    info = LogInfo(pieces.name, pieces.rate, pieces.cutoff, pieces.motion_from, pieces.notes)
    return Comparison(info, params, lever_spin, arrays["t"], arrays["measured"], model, arrays["cond_inv"], arrays["near"],
                      period, edges, phase_rms, statistics)

"""The model against the rig: measured logs in machine terms, and the model's torques along them.

:func:`load_log` reads a rig log (:mod:`hipsim.motion.rig_logs`), turns
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
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analytic.engine import AnalyticModel
from ..analytic.forward_kinematics import forward_kinematics
from ..analytic.inverse_kinematics import slider_heights
from ..exceptions import PoseError, TrajectoryError
from ..machine.parameters import Parameters, load_parameters
from ..motion.rig_logs import DEFAULT_CUTOFF, MeasuredLog, edge_samples, lowpass, read_rig_log, smooth_motion
from ..motion.trajectories import ANGLE_NAMES
from ..results import Run, Torques, peak_and_rms

__all__ = ["DEFAULT_TOLERANCE_DEG", "REVERSAL_PERIODS", "Comparison", "compare", "detect_period", "load_log", "model_torques", "reversal_mask"]

#: Largest disagreement in [deg] allowed between the attitude sensor and the encoders' forward kinematics.
DEFAULT_TOLERANCE_DEG = 0.5
#: Half-width of the window around each motor's reversal, in periods of the low-pass cutoff (see :func:`reversal_mask`).
REVERSAL_PERIODS = 1.5


def load_log(
    path: str | Path,
    params: Parameters | None = None,
    torque_constant: float | None = None,
    cutoff: float | None = DEFAULT_CUTOFF,
    tolerance_deg: float = DEFAULT_TOLERANCE_DEG,
) -> MeasuredLog:
    """Read a rig log and make it ready for the models.

    Args:
        path: the CSV log (columns in :mod:`hipsim.motion.rig_logs`).
        params: the machine (for the encoders' forward kinematics); None for the published one.
        torque_constant: the motors' torque constant in [N·m/A], for logs of motor currents.
        cutoff: low-pass cutoff in [Hz] for motion, load and torques; None for
            none (signals already clean: the angles are then only splined).
        tolerance_deg: largest disagreement in [deg] between the attitude
            sensor's angles and the encoders' when the log has both (the
            encoders are used; beyond this the log is refused).

    Returns:
        The log, filtered and differentiated; its first and last
        :func:`~hipsim.motion.rig_logs.edge_samples` samples are marked as the filter's edges.

    Raises:
        TrajectoryError: naming the file, line and column: the reader's
            errors, encoder heights no pose reaches, a disagreement of the two
            motion sources, a log too short to filter.
    """
    params = params if params is not None else load_parameters()
    raw = read_rig_log(path, torque_constant)
    name = Path(raw.source).name
    rate = raw.rate
    notes = []
    if raw.ignored:
        notes.append(f"columns not used: {', '.join(raw.ignored)}")
    if raw.torque_from == "currents":
        notes.append(f"torques from the motor currents × {torque_constant:g} N·m/A")
    elif torque_constant is not None:
        notes.append("the log gives torques: the torque constant was not needed")
    if cutoff is not None:
        lowpass(raw.t, rate, cutoff, raw.source)  # refuses a log too short to filter, before any work

    if raw.heights is not None:
        try:
            q = forward_kinematics(params, raw.heights, raw.t, q0=None if raw.angles is None else raw.angles[0])
        except PoseError as error:
            raise TrajectoryError(f"encoder heights L_11_mm … at {error}", source=raw.source, line=int(raw.lines[error.index])) from None
        motion_from = "encoders"
        if raw.angles is not None:
            difference = np.degrees(np.abs(q - raw.angles))
            worst = np.unravel_index(np.argmax(difference), difference.shape)
            if difference[worst] > tolerance_deg:
                k, a = np.argwhere(difference > tolerance_deg)[0]  # the first line beyond the tolerance
                raise TrajectoryError(
                    f"the attitude sensor and the encoders disagree by {difference[k, a]:.3g}° in {ANGLE_NAMES[a]} "
                    f"(tolerance {tolerance_deg:g}°; {difference[worst]:.3g}° at worst, line {int(raw.lines[worst[0]])}): "
                    "check the sensor's mounting, zero and sign conventions, or the machine's parameters",
                    source=raw.source, line=int(raw.lines[k]), column=f"{ANGLE_NAMES[a]}_{raw.angle_unit}",
                )
            notes.append(f"encoders used; the attitude sensor agrees within {difference[worst]:.3g}° (tolerance {tolerance_deg:g}°)")
    else:
        q = raw.angles
        motion_from = "angles"

    trajectory = smooth_motion(raw.t, q, raw.Fe, cutoff, name)
    if cutoff is None:
        tau, edge = raw.tau, 0
    else:
        tau = lowpass(raw.tau, rate, cutoff, raw.source)
        edge = edge_samples(rate, cutoff)
        notes.append(f"low-passed at {cutoff:g} Hz (zero-phase Butterworth); the first and last {edge / rate:.3g} s are the filter's edges")
    return MeasuredLog(trajectory, tau, cutoff, name, motion_from, tuple(notes), raw.lines, edge)


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
    half = int(math.ceil(REVERSAL_PERIODS * log.rate / log.cutoff))
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


@dataclass(frozen=True, eq=False)
class Comparison:
    """The model's torques along a log, beside the measured ones (usable samples only).

    Attributes:
        log: the log.
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
    """

    log: MeasuredLog
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

    @property
    def error(self) -> np.ndarray:
        """Model minus measured motor torque in [N·m], (N, 3)."""
        return self.model["total"] - self.measured

    def motor_errors(self) -> dict[str, dict[str, float]]:
        """Per motor ("1", "2", "3"): RMS and peak error in [N·mm], relative to the measured RMS and peak, and when the peak occurs.

        ``*_away_from_reversals`` are the same over the samples outside the
        windows around that motor's reversals (:func:`reversal_mask`).
        """
        error_peak, error_rms = peak_and_rms(self.error * 1e3)
        measured_peak, measured_rms = peak_and_rms(self.measured * 1e3)
        worst = np.argmax(np.abs(self.error), axis=0)
        out = {}
        for i in range(3):
            away = ~self.near_reversal[:, i]
            away_rms = float(np.sqrt(np.mean(self.error[away, i] ** 2)) * 1e3) if np.any(away) else math.nan
            away_measured = float(np.sqrt(np.mean(self.measured[away, i] ** 2)) * 1e3) if np.any(away) else math.nan
            out[str(i + 1)] = {
                "rms_error_away_from_reversals_Nmm": away_rms,
                "relative_rms_error_away_from_reversals": away_rms / away_measured if away_measured > 0 else math.inf,
                "share_near_reversals": float(np.mean(self.near_reversal[:, i])),
                "rms_error_Nmm": float(error_rms[i]),
                "peak_error_Nmm": float(error_peak[i]),
                "peak_error_t_s": float(self.t[worst[i]]),
                "measured_rms_Nmm": float(measured_rms[i]),
                "measured_peak_Nmm": float(measured_peak[i]),
                "relative_rms_error": float(error_rms[i] / measured_rms[i]) if measured_rms[i] > 0 else math.inf,
                "relative_peak_error": float(error_peak[i] / measured_peak[i]) if measured_peak[i] > 0 else math.inf,
            }
        return out

    def summary(self) -> dict[str, Any]:
        """Everything a script needs, JSON-ready, torques in [N·mm]."""
        motors = self.motor_errors()
        for i, entry in motors.items():
            entry["model_parts_rms_Nmm"] = {
                Torques.COLUMN[field]: float(peak_and_rms(self.model[field][:, int(i) - 1] * 1e3)[1]) for field in Torques.PARTS
            }
        out: dict[str, Any] = {
            "log": self.log.name,
            "samples": int(self.t.size),
            "rate_Hz": float(self.log.rate),
            "cutoff_Hz": self.log.cutoff,
            "motion_from": self.log.motion_from,
            "parameters": self.params.source,
            "lever_spin": self.lever_spin,
            "motors": motors,
            "cond_inv_min": float(np.min(self.cond_inv)),
            "period_s": self.period,
            "notes": list(self.log.notes),
        }
        if self.phase_rms is not None:
            out["phases"] = {
                "edges": [float(x) for x in self.phase_edges],
                "rms_error_Nmm": {str(i + 1): [float(x) for x in self.phase_rms[:, i] * 1e3] for i in range(3)},
            }
        return out


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
    run, parts = model_torques(params, log, lever_spin)
    keep = log.usable
    t = log.t[keep]
    if period is None:
        period = detect_period(t, log.trajectory.q[keep])
    elif period <= 0:
        period = None
    if period is not None and (t[-1] - t[0]) < 2 * period * (1 - 1e-9):
        period = None  # fewer than two cycles: no phases to average
    model = {field: values[keep] for field, values in parts.items()}
    measured = log.tau[keep]
    edges = phase_rms = None
    if period is not None:
        phase = np.mod((t - t[0]) / period, 1.0)
        edges = np.linspace(0.0, 1.0, phase_bins + 1)
        which = np.minimum((phase * phase_bins).astype(int), phase_bins - 1)
        error = model["total"] - measured
        phase_rms = np.full((phase_bins, 3), np.nan)
        for b in range(phase_bins):
            inside = which == b
            if np.any(inside):
                phase_rms[b] = np.sqrt(np.mean(error[inside] ** 2, axis=0))
    near = reversal_mask(params, log)[keep]
    return Comparison(log, params, lever_spin, t, measured, model, run.cond_inv[keep], near, period, edges, phase_rms)

"""The zero-phase low-pass that measured signals need, and the windows it sets.

Filtering. Measured signals are noisy and differentiating them twice
amplifies the noise, so the motion is low-passed before it is differentiated:
a Butterworth filter of order :data:`FILTER_ORDER` run forwards and backwards
(SciPy's ``sosfiltfilt``: zero phase, so nothing is delayed, and the squared
magnitude response of order 2·4) at ``cutoff`` Hz, :data:`DEFAULT_CUTOFF` by
default: the ISO gait and the excitations of :mod:`hipsim.rig.excitation`
have their content below ~6 Hz, so 20 Hz passes it unchanged (gain 1 − 3e-7
at 6 Hz) while cutting the noise power of a 1 kHz log 25-fold. The filtered
angles are then differentiated through an interpolating quintic spline, as
trajectory files are. The same filter is applied to the torques and the load
that a comparison or a fit uses, so that model and measurement see the same
bandwidth. The first and last :func:`edge_samples` samples, where a
forward-backward filter has no data on one side, are dropped.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.signal import butter, sosfilt, sosfiltfilt

from ..exceptions import TrajectoryError
from ..motion.trajectories import Trajectory

__all__ = [
    "DEFAULT_CUTOFF",
    "EDGE_PERIODS",
    "FILTER_ORDER",
    "REVERSAL_PERIODS",
    "edge_samples",
    "filter_halo",
    "lowpass",
    "minimum_samples",
    "reversal_half",
    "smooth_motion",
]

#: Default low-pass cutoff in [Hz] for measured motion and torques.
DEFAULT_CUTOFF = 20.0
#: Order of the Butterworth low-pass (run twice: forwards and backwards).
FILTER_ORDER = 4
#: Samples left out at each end of a filtered log, in periods of the cutoff: the
#: forward-backward filter lacks data on one side there (its impulse response
#: decays to 1e-4 within four periods at the order used).
EDGE_PERIODS = 4.0
#: Half-width of the window around each motor's reversal, in periods of the low-pass cutoff (see :func:`reversal_mask`).
REVERSAL_PERIODS = 1.5


def _check_cutoff(rate: float, cutoff: float, source: str | None) -> None:
    if isinstance(cutoff, bool) or not (isinstance(cutoff, (int, float)) and math.isfinite(cutoff) and cutoff > 0):
        raise TrajectoryError(f"the low-pass cutoff must be a positive frequency in Hz, got {cutoff!r}", source=source)
    if cutoff >= 0.5 * rate:
        raise TrajectoryError(
            f"the low-pass cutoff {cutoff:g} Hz is not below the Nyquist frequency {0.5 * rate:g} Hz of a {rate:g} Hz log",
            source=source,
        )


def edge_samples(rate: float, cutoff: float) -> int:
    """Samples dropped at each end of a log filtered at ``cutoff`` [Hz] and sampled at ``rate`` [Hz]."""
    return int(math.ceil(EDGE_PERIODS * rate / cutoff))


def minimum_samples(rate: float, cutoff: float) -> int:
    """The fewest samples a log needs to be filtered: both edges and as many samples again between them."""
    padding = 3 * (2 * (FILTER_ORDER // 2 + FILTER_ORDER % 2) + 1)  # sosfiltfilt's default odd extension
    return max(4 * edge_samples(rate, cutoff), padding + 1, 6)


def filter_halo(rate: float, cutoff: float) -> int:
    """Samples after which a start in the wrong state no longer shows in :func:`lowpass` (below round-off, 2⁻⁵³).

    A piece of a log filtered on its own differs from the whole log filtered
    only by the filter's response to the piece's ends, which decays as the
    filter's impulse response: this is where that response (of one pass,
    relative to its peak) stays below the double-precision round-off for good.
    Args:
        rate: sample rate in [Hz].
        cutoff: cutoff frequency in [Hz].
    """
    _check_cutoff(rate, cutoff, None)
    sos = butter(FILTER_ORDER, cutoff, fs=rate, output="sos")
    length = 64
    while True:
        impulse = np.zeros(length)
        impulse[0] = 1.0
        response = np.abs(sosfilt(sos, impulse))
        above = np.flatnonzero(response > 2.0**-53 * response.max())
        if above[-1] < length // 2:
            return int(above[-1]) + 1
        length *= 2


def lowpass(x: np.ndarray, rate: float, cutoff: float, source: str | None = None) -> np.ndarray:
    """Zero-phase Butterworth low-pass along the first axis (``sosfiltfilt``, order :data:`FILTER_ORDER`).

    Args:
        x: samples, (N, ...), in any unit.
        rate: sample rate in [Hz].
        cutoff: cutoff frequency in [Hz] (−3 dB of one pass, −6 dB of both).
        source: the log's name, for messages.

    Raises:
        TrajectoryError: a cutoff not below the Nyquist frequency, or a log too short to filter.
    """
    _check_cutoff(rate, cutoff, source)
    x = np.asarray(x, dtype=float)
    needed = minimum_samples(rate, cutoff)
    if len(x) < needed:
        raise TrajectoryError(
            f"{len(x)} samples ({len(x) / rate:.3g} s) are too short to filter at {cutoff:g} Hz: at least {needed} "
            f"({needed / rate:.3g} s) are needed, {EDGE_PERIODS:g}/cutoff at each end being dropped",
            source=source,
        )
    sos = butter(FILTER_ORDER, cutoff, fs=rate, output="sos")
    # An odd extension as long as the dropped edge: the filter starts on a smooth continuation of the signal.
    return sosfiltfilt(sos, x, axis=0, padlen=min(edge_samples(rate, cutoff), len(x) - 1))


def smooth_motion(
    t: np.ndarray, q: np.ndarray, Fe: np.ndarray, cutoff: float | None, name: str = "log", rate: float | None = None
) -> Trajectory:
    """Low-passed angles and load, the angles differentiated through an interpolating quintic spline.

    Args:
        t: evenly spaced sample times in [s], (N,).
        q: gait angles in [rad], (N, 3).
        Fe: load in [N], (N,).
        cutoff: low-pass cutoff in [Hz]; None for no filter (the spline only).
        name: the log's name, for messages and the trajectory.
        rate: the sample rate in [Hz]; None for the times' (a piece of a log
            passes the whole log's, so that every piece has the same filter).

    Returns:
        The filtered trajectory, all N samples (the caller drops the edges).
    """
    if cutoff is not None:
        rate = rate if rate is not None else (t.size - 1) / (t[-1] - t[0])
        q = lowpass(q, rate, cutoff, name)
        Fe = np.maximum(lowpass(Fe, rate, cutoff, name), 0.0)  # a magnitude; ringing must not make it negative
    if t.size < 6:
        raise TrajectoryError(f"{t.size} samples; at least 6 are needed to differentiate", source=name)
    spline = make_interp_spline(t, q, k=5, axis=0)
    return Trajectory(t, q, spline(t, 1), spline(t, 2), Fe, name=name)


def reversal_half(rate: float, cutoff: float) -> int:
    """Half-width in samples of the window around a reversal (:func:`hipsim.rig.reversals.reversal_mask`)."""
    return int(math.ceil(REVERSAL_PERIODS * rate / cutoff))

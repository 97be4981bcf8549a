"""The zero-phase low-pass that measured motion needs before it is differentiated: one filter for trajectory files and rig logs.

Differentiating a measured angle twice amplifies its noise by the square of
the sample rate, so gait labs low-pass their kinematics first (about 6 Hz).
The filter: a Butterworth filter of order :data:`FILTER_ORDER` run forwards
and backwards (SciPy's ``sosfiltfilt``: zero phase, so nothing is delayed, and
the squared magnitude response of order 2·4) at ``cutoff`` Hz.

Edge handling. A forward-backward filter lacks data beyond the ends of a
record. :func:`lowpass` extends each end by an odd (point-symmetric)
reflection about the end sample, :func:`edge_samples` long (4 periods of the
cutoff): the extension keeps the end's value and slope, so the filter starts
on a smooth continuation of the signal; within that distance of each end the
filtered values are the least reliable. :func:`lowpass_periodic` filters one
period of a periodic record as if it repeated endlessly (the period wrapped
around on both sides), so a periodic record has no edges at all.

The rig-log path (:mod:`hipsim.rig.logs.log`) uses the same functions and drops
the :func:`edge_samples` samples at each end of a log.

SciPy's signal module is imported where a record is filtered, not with this
module: importing it is about 0.6 s of CPU, most of a command's start-up, and
every command that reads a trajectory imports this module, filtering or not.
"""

from __future__ import annotations

import math

import numpy as np

from ..exceptions import TrajectoryError

__all__ = [
    "EDGE_PERIODS",
    "FILTER_ORDER",
    "check_cutoff",
    "edge_samples",
    "filter_halo",
    "lowpass",
    "lowpass_periodic",
    "lowpass_record",
    "minimum_samples",
]

#: Order of the Butterworth low-pass (run twice: forwards and backwards).
FILTER_ORDER = 4
#: Samples left out at each end of a filtered log, in periods of the cutoff: the
#: forward-backward filter lacks data on one side there (its impulse response
#: decays to 1e-4 within four periods at the order used).
EDGE_PERIODS = 4.0


def check_cutoff(rate: float, cutoff: float, source: str | None) -> None:
    """Refuse a cutoff in [Hz] that is not a positive frequency below the Nyquist frequency of ``rate`` [Hz]."""
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
    from scipy.signal import butter, sosfilt

    check_cutoff(rate, cutoff, None)
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


def lowpass(x: np.ndarray, rate: float, cutoff: float, source: str | None = None, axis: int = 0) -> np.ndarray:
    """Zero-phase Butterworth low-pass along the first axis, or ``axis`` (``sosfiltfilt``, order :data:`FILTER_ORDER`).

    Args:
        x: samples, (N, ...), in any unit.
        rate: sample rate in [Hz].
        cutoff: cutoff frequency in [Hz] (−3 dB of one pass, −6 dB of both).
        source: the log's name, for messages.
        axis: the samples' axis, if not the first (the last, of components-first arrays (..., N), filters them
            without SciPy's transposing copies; each signal's numbers are the same either way).

    Raises:
        TrajectoryError: a cutoff not below the Nyquist frequency, or a log too short to filter.
    """
    from scipy.signal import butter, sosfiltfilt

    check_cutoff(rate, cutoff, source)
    x = np.asarray(x, dtype=float)
    needed = minimum_samples(rate, cutoff)
    n = x.shape[axis]
    if n < needed:
        raise TrajectoryError(
            f"{n} samples ({n / rate:.3g} s) are too short to filter at {cutoff:g} Hz: at least {needed} "
            f"({needed / rate:.3g} s) are needed, {EDGE_PERIODS:g}/cutoff at each end being dropped",
            source=source,
        )
    sos = butter(FILTER_ORDER, cutoff, fs=rate, output="sos")
    # An odd extension as long as the dropped edge: the filter starts on a smooth continuation of the signal.
    return sosfiltfilt(sos, x, axis=axis, padlen=min(edge_samples(rate, cutoff), n - 1))


def lowpass_periodic(x: np.ndarray, rate: float, cutoff: float, source: str | None = None) -> np.ndarray:
    """:func:`lowpass` of one period of a periodic signal, wrapped around: no edges.

    Args:
        x: one period's samples, (N, ...), the first not repeated at the end.
        rate: sample rate in [Hz].
        cutoff: cutoff frequency in [Hz].
        source: the record's name, for messages.

    Raises:
        TrajectoryError: a cutoff not a positive frequency below the Nyquist frequency.
    """
    from scipy.signal import butter, sosfiltfilt

    check_cutoff(rate, cutoff, source)
    x = np.asarray(x, dtype=float)
    n = len(x)
    # Enough whole periods on each side for the filter's response to die out (its edge length).
    copies = int(math.ceil(edge_samples(rate, cutoff) / n)) + 1
    tiled = np.concatenate([x] * (2 * copies + 1), axis=0)
    sos = butter(FILTER_ORDER, cutoff, fs=rate, output="sos")
    return sosfiltfilt(sos, tiled, axis=0, padlen=0)[copies * n : (copies + 1) * n]


def lowpass_record(
    x: np.ndarray, rate: float, cutoff: float, periodic: bool = False, source: str | None = None
) -> np.ndarray:
    """The low-pass of a whole record that keeps every sample: wrapped around when periodic, else with odd extensions at the ends.

    Unlike the rig-log path, nothing is dropped: a record of any length from a
    few samples is filtered, its first and last :func:`edge_samples` the least
    reliable (module docstring).

    Args:
        x: samples, (N, ...), in any unit; a periodic record's last sample repeats its first.
        rate: sample rate in [Hz].
        cutoff: cutoff frequency in [Hz].
        periodic: filter as one period of an endless repetition.
        source: the record's name, for messages.

    Raises:
        TrajectoryError: a cutoff not a positive frequency below the Nyquist frequency.
    """
    from scipy.signal import butter, sosfiltfilt

    check_cutoff(rate, cutoff, source)
    x = np.asarray(x, dtype=float)
    if periodic:
        one = lowpass_periodic(x[:-1], rate, cutoff, source)
        return np.concatenate([one, one[:1]], axis=0)
    n, pad = len(x), min(edge_samples(rate, cutoff), len(x) - 1)
    sos = butter(FILTER_ORDER, cutoff, fs=rate, output="sos")
    if n < 8:
        return sosfiltfilt(sos, x, axis=0, padlen=pad)
    extended = np.concatenate([_extension(x[::-1], pad)[::-1], x, _extension(x, pad)], axis=0)
    return sosfiltfilt(sos, extended, axis=0, padlen=0)[pad : pad + n]


def _extension(x: np.ndarray, pad: int) -> np.ndarray:
    """``pad`` samples after the end of ``x``: a quadratic fitted to its last samples, carried on, plus the odd reflection of what it leaves.

    A plain odd reflection keeps the end's value and slope but flips its
    curvature, which the filter turns into a wrong second derivative near the
    end; carrying the end's quadratic trend keeps the curvature too.
    """
    n = len(x)
    m = max(min(pad // 4, n // 2), 3)  # one period of the cutoff: short enough for a quadratic to follow
    k = np.arange(-m + 1, 1, dtype=float)  # the last m samples, the end at 0
    flat = x.reshape(n, -1)
    trend = np.polynomial.polynomial.polyfit(k, flat[n - m :], 2)  # (3, columns)
    ahead = np.arange(1, pad + 1, dtype=float)
    powers = np.vstack([np.ones_like(ahead), ahead, ahead**2]).T
    behind = np.arange(-1, -pad - 1, -1, dtype=float)
    mirror = np.vstack([np.ones_like(behind), behind, behind**2]).T
    # x(end + i) ≈ p(i) − (x(end − i) − p(−i)): the residual reflected oddly about the end.
    back = flat[np.clip(n - 1 - np.arange(1, pad + 1), 0, n - 1)]
    residual_end = flat[n - 1] - trend[0]
    out = powers @ trend - (back - mirror @ trend) + 2 * residual_end
    return out.reshape((pad,) + x.shape[1:])

"""The zero-phase low-pass that measured signals need, and the windows it sets.

Filtering. Measured signals are noisy and differentiating them twice
amplifies the noise, so the motion is low-passed before it is differentiated:
a Butterworth filter of order :data:`FILTER_ORDER` run forwards and backwards
(SciPy's ``sosfiltfilt``: zero phase, so nothing is delayed, and the squared
magnitude response of order 2·4) at ``cutoff`` Hz, :data:`DEFAULT_CUTOFF` by
default: the ISO gait and the excitations of :mod:`hipsim.rig.identification.excitation`
have their content below ~6 Hz, so 20 Hz passes it unchanged (gain 1 − 3e-7
at 6 Hz) while cutting the noise power of a 1 kHz log 25-fold. The filtered
angles are then differentiated through an interpolating quintic spline, as
trajectory files are. The same filter is applied to the torques and the load
that a comparison or a fit uses, so that model and measurement see the same
bandwidth. The first and last :func:`edge_samples` samples, where a
forward-backward filter has no data on one side, are dropped.

The filter itself is :mod:`hipsim.motion.filtering`'s, the one trajectory
files get with ``--cutoff``; this module adds what logs need of it.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import make_interp_spline

from ...exceptions import TrajectoryError
from ...motion.filtering import EDGE_PERIODS, FILTER_ORDER, edge_samples, filter_halo, lowpass, minimum_samples
from ...motion.trajectories import Trajectory

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
#: Half-width of the window around each motor's reversal, in periods of the low-pass cutoff (see :func:`reversal_mask`).
REVERSAL_PERIODS = 1.5


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
    """Half-width in samples of the window around a reversal (:func:`hipsim.rig.logs.reversals.reversal_mask`)."""
    return int(math.ceil(REVERSAL_PERIODS * rate / cutoff))

"""The samples around each motor's reversal, where the model along the filtered motion cannot follow the rig."""

from __future__ import annotations

import numpy as np

from ...analytic.inverse_kinematics import slider_heights
from ...machine.parameters import Parameters
from .log import MeasuredLog
from .smoothing import REVERSAL_PERIODS, reversal_half

__all__ = ["REVERSAL_PERIODS", "reversal_mask"]


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
    half = reversal_half(log.rate, log.cutoff)
    for i in range(3):
        crossings = np.flatnonzero(np.sign(speed[1:, i]) != np.sign(speed[:-1, i]))
        if crossings.size:
            marks = np.zeros(n + 1, dtype=int)
            np.add.at(marks, np.maximum(crossings - half, 0), 1)
            np.add.at(marks, np.minimum(crossings + half + 2, n), -1)
            mask[:, i] = np.cumsum(marks)[:n] > 0
    return mask

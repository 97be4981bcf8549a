"""Does a calibration make sense? Its residuals, its chains' moves and its held-out logs, held to the gates.

The gates and thresholds are :mod:`hipsim.fit_checks`'s. The noise of each
sensor angle is measured in the log itself, model-free
(:func:`~hipsim.fit_checks.difference_noise`: fourth differences, which a
smooth motion cancels), never below :data:`SENSOR_FLOOR_DEG` (a sensor's
resolution: a noiseless synthetic log is not held to zero). The fit's own noise
estimate is its residual and cannot judge it: a prior of 0.5 µm (``--prior
0.0005``, metres typed for mm) leaves 0.2° of residual that the fit calls
noise, the difference noise of the same sensor is 0.01°.

Each estimated per-chain value's move from the start is held to 5 prior
standard deviations: a sensor's 3° zero absorbed as 13 mm of chain (prior
0.5 mm) is 26σ. When a gate fails, the sensors are set against the starting
machine's predictions (:func:`~hipsim.fit_checks.column_pattern`) to name the
likely cause: the two platforms' columns swapped, a sign, a sensor's offset,
radians read as degrees.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..fit_checks import PATTERNS, FitCheck, column_pattern, difference_noise, prior_gate, residual_gate
from ..machine.parameters import Parameters
from . import deviations as dv
from .calibration import Calibration, CalibrationLog, prediction_errors

__all__ = ["SENSOR_COLUMNS", "SENSOR_FLOOR_DEG", "check_calibration", "sensor_noise"]

#: The noise of an attitude sensor angle is taken as at least this, in [deg] (a sensor's resolution).
SENSOR_FLOOR_DEG = 0.005
#: The sensor angles, in the order of a log's (2, 3) sensors.
SENSOR_COLUMNS = ("alpha_1", "beta_1", "gamma_1", "alpha_2", "beta_2", "gamma_2")


def sensor_noise(log: CalibrationLog) -> np.ndarray:
    """Each sensor angle's white noise in [deg], (6,): the difference noise, at least :data:`SENSOR_FLOOR_DEG`."""
    measured = difference_noise(np.degrees(np.asarray(log.sensors).reshape(len(log.sensors), 6)))
    return np.maximum(np.nan_to_num(measured, nan=SENSOR_FLOOR_DEG), SENSOR_FLOOR_DEG)


def _pattern(machine: Parameters, log: CalibrationLog, kinds: Sequence[str] = PATTERNS) -> str:
    try:
        _, _, q = prediction_errors(machine, log, False)
    except Exception:
        return ""
    n = len(log.sensors)
    found = column_pattern(
        np.degrees(np.asarray(log.sensors).reshape(n, 6)), np.degrees(q.reshape(n, 6)), SENSOR_COLUMNS, "°", kinds=kinds
    )
    return f" (likely cause in {log.name}: {found})" if found else ""


def check_calibration(
    result: Calibration,
    logs: Sequence[CalibrationLog],
    held: Sequence[CalibrationLog] = (),
    held_rms: Sequence[np.ndarray] = (),
) -> FitCheck:
    """The gates of :mod:`hipsim.fit_checks` on a calibration.

    Args:
        result: the calibration.
        logs: the logs fitted, in the order of ``result.residual_rms``.
        held: the held-out logs (``--validate``).
        held_rms: each held-out log's RMS error per sensor angle with the calibrated machine in [rad], (2, 3).

    Returns:
        The check: no findings when every gate passes.
    """
    findings: list[str] = []
    for log, rms in zip(logs, result.residual_rms):
        residual = residual_gate(np.degrees(np.asarray(rms).ravel()), sensor_noise(log), SENSOR_COLUMNS, "°")
        if residual:
            findings.append(f"{log.name}: {residual}" + _pattern(result.start, log))
        else:  # a swap or a sign the chains absorb leaves residuals at the noise: looked for whatever they are
            swapped = _pattern(result.start, log, ("swap", "sign"))
            if swapped:
                findings.append(f"{log.name}: the fit absorbs a slip of the columns{swapped}")
    estimated = np.asarray(result.structure.independent)
    start = dv.deviation(result.start)
    moved = prior_gate(
        result.theta[estimated] * 1e3,
        start[estimated] * 1e3,
        np.full(estimated.size, result.prior * 1e3),
        [dv.names()[k] for k in estimated],
        "mm",
    )
    if moved:
        cause = "".join(_pattern(result.start, log) for log in logs[:1])
        findings.append(
            f"per-chain values {moved}: they absorb something else{cause or ' (a sensor offset or column?)'}"
        )
    for log, rms in zip(held, held_rms):
        off = residual_gate(np.degrees(np.asarray(rms).ravel()), sensor_noise(log), SENSOR_COLUMNS, "°")
        if off:
            findings.append(f"held-out {log.name} is not predicted: {off}" + _pattern(result.machine, log))
    return FitCheck("calibrate", tuple(findings))

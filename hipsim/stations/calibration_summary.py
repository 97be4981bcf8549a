"""What a kinematic calibration reports (``hipsim calibrate``): typed records, made where the calibration is.

:func:`calibration_summary` turns a :class:`~hipsim.stations.calibration.Calibration`
and its held-out checks (:func:`held_out_residual`: each held-out log's RMS
error per sensor angle with the calibrated and with the starting machine) into a
:class:`CalibrationSummary`: angles in [deg], per-chain values in [mm]. The
verdict is the calibration's self-check's (:func:`hipsim.fit_checks.fit_verdict`,
through :func:`hipsim.stations.calibration_check.check_calibration`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..machine.parameters import Parameters
from ..records import Record
from . import deviations as dv
from .calibration import Calibration, CalibrationLog, Confounding, prediction_errors

__all__ = ["CalibrationSummary", "ChainValue", "HeldOutResidual", "calibration_summary", "held_out_residual"]


@dataclass(frozen=True)
class ChainValue(Record):
    """One per-chain value: its deviation from the drawing and standard deviation in [mm], whether the logs determine it."""

    value: str
    deviation_mm: float
    std_mm: float
    determined: bool


@dataclass(frozen=True)
class HeldOutResidual(Record):
    """A held-out log's RMS error per sensor angle in [deg], rows m_1, m_2 and columns α, β, γ, (2, 3): with the
    calibrated machine (``rms_deg``) and with the starting one (``start_rms_deg``)."""

    log: str
    rms_deg: list[list[float]]
    start_rms_deg: list[list[float]]


@dataclass(frozen=True)
class CalibrationSummary(Record):
    """A kinematic calibration (``hipsim calibrate``): angles in [deg], per-chain values in [mm].

    Attributes:
        logs: the logs fitted.
        samples: samples fitted; iterations: Gauss–Newton iterations made.
        noise_deg: each sensor angle's residual standard deviation, (2, 3).
        residual_rms_deg, start_residual_rms_deg: per log, the RMS residual per sensor angle with the calibrated and
            the starting machine, (K, 2, 3).
        offsets_deg: per log, the sensor offsets estimated (zero when not), (K, 2, 3).
        values: every per-chain value.
        unseen: the values no log of this kind can see (kept at the start).
        weak: the values these logs barely see (posterior std above half the prior's).
        combinations: each estimated value that absorbs others, as a combination.
        confounded: with sensor offsets, each offset and the values it trades with.
        validation: per held-out log (``--validate``), its errors.
    """

    logs: tuple[str, ...]
    samples: int
    iterations: int
    noise_deg: list[list[float]]
    residual_rms_deg: list[list[list[float]]]
    start_residual_rms_deg: list[list[list[float]]]
    offsets_deg: list[list[list[float]]]
    values: tuple[ChainValue, ...]
    unseen: tuple[str, ...]
    weak: tuple[str, ...]
    combinations: tuple[str, ...]
    confounded: tuple[Confounding, ...]
    validation: tuple[HeldOutResidual, ...]


def _deg(values: np.ndarray) -> list:
    return np.degrees(np.asarray(values, dtype=float)).tolist()


def _rms(errors: np.ndarray) -> np.ndarray:
    """RMS over the samples of errors (N, 2, 3) in [rad]: (2, 3)."""
    return np.sqrt(np.mean(np.asarray(errors) ** 2, axis=0))


def held_out_residual(
    calibration: Calibration, start: Parameters, log: CalibrationLog, offsets: bool
) -> HeldOutResidual:
    """A held-out log predicted by the calibrated machine and by ``start`` (the machine the calibration started from).

    Args:
        calibration: the calibration.
        start: the starting machine.
        log: the held-out log.
        offsets: fit (and take out) a constant offset per sensor angle first, as the calibration did.
    """
    after = prediction_errors(calibration.machine, log, offsets)[0]
    before = prediction_errors(start, log, offsets)[0]
    return HeldOutResidual(log.name, _deg(_rms(after)), _deg(_rms(before)))


def calibration_summary(calibration: Calibration, validation: Sequence[HeldOutResidual] = ()) -> CalibrationSummary:
    """The record of a calibration and its held-out checks (:class:`CalibrationSummary`)."""
    values = tuple(
        ChainValue(
            name,
            float(calibration.theta[k] * 1e3),
            float(calibration.theta_std[k] * 1e3),
            bool(calibration.determined[k]),
        )
        for k, name in enumerate(dv.names())
    )
    return CalibrationSummary(
        logs=tuple(calibration.logs),
        samples=int(calibration.samples),
        iterations=int(calibration.iterations),
        noise_deg=_deg(calibration.noise),
        residual_rms_deg=_deg(calibration.residual_rms),
        start_residual_rms_deg=_deg(calibration.start_rms),
        offsets_deg=_deg(calibration.offsets),
        values=values,
        unseen=tuple(calibration.unseen),
        weak=tuple(calibration.weak),
        combinations=tuple(calibration.structure.definitions()),
        confounded=tuple(calibration.confounded),
        validation=tuple(validation),
    )

"""A log's attitude sensors against what the machine's model predicts from its carriages, per platform and angle.

``hipsim stations --sliders LOG`` predicts both platforms' attitudes from the
log's carriages (each platform's forward kinematics on the parameter file's
machine). When the log also has the sensors' columns (``alpha_1_deg`` …
``gamma_2_deg``, as a rig's acquisition or ``hipsim simulate`` write them),
:func:`compare_sensors` says how far measured is from predicted, per platform
and angle, beside the prediction's own uncertainty: for a machine from
``hipsim calibrate``, the posterior covariance of the per-chain values its
``[identification]`` table records (:func:`calibration_covariance`), carried
to the attitudes through their sensitivity
(:func:`hipsim.stations.sensitivity.attitude_jacobian`), as
:meth:`hipsim.stations.calibration.Calibration.prediction_std` does; for any
other file, none (NaN).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..machine.chains import ChainGeometry
from ..machine.parameters import Parameters
from ..records import Record
from ..results import rms_and_signed_peak
from .sensitivity import attitude_jacobian

__all__ = ["SensorAgreement", "SensorComparison", "calibration_covariance", "compare_sensors", "prediction_std"]

_ANGLES = ("alpha", "beta", "gamma")


@dataclass(frozen=True)
class SensorAgreement(Record):
    """One platform's angle over a log: measured − predicted.

    Attributes:
        platform: 1 or 2; angle: "alpha", "beta" or "gamma".
        rms_deg, mean_deg: RMS and mean of measured − predicted in [deg].
        peak_deg, peak_at_s: the difference of largest magnitude (signed) and when.
        prediction_std_deg: the prediction's standard deviation from the model's uncertainty, RMS over the
            samples, in [deg]; None when the model carries none.
    """

    platform: int
    angle: str
    rms_deg: float
    mean_deg: float
    peak_deg: float
    peak_at_s: float
    prediction_std_deg: float | None


@dataclass(frozen=True)
class SensorComparison(Record):
    """A log's sensors against the model's prediction; ``uncertainty`` says where the prediction's spread came from."""

    samples: int
    uncertainty: str
    entries: tuple[SensorAgreement, ...]

    def entry(self, platform: int, angle: str) -> SensorAgreement:
        return self.entries[3 * (platform - 1) + _ANGLES.index(angle)]


def prediction_std(params: Parameters, q: np.ndarray, theta_covariance: np.ndarray) -> np.ndarray:
    """Standard deviation in [rad] of both platforms' predicted attitudes q (N, 2, 3) [rad] from the per-chain values'
    covariance [m²] (COUNT, COUNT) (hipsim.stations.deviations.COUNT): √(J·Σ·Jᵀ) per platform and angle with J = ∂q/∂δ, (N, 2, 3)."""
    J = attitude_jacobian(params, np.asarray(q))
    return np.sqrt(np.sum((J @ np.asarray(theta_covariance)) * J, axis=-1))


def calibration_covariance(record: Mapping[str, Any]) -> np.ndarray | None:
    """The per-chain values' covariance [m²] (COUNT, COUNT) (hipsim.stations.deviations.COUNT) from a calibrated file's ``[identification]`` table; None without one.

    The posterior covariance of the estimated values where the file has it (``estimated``, ``covariance_mm2``), the
    values kept at the start with none (the attitudes do not see them); else, for a file written before it, the
    standard deviations ``std_mm`` taken as independent (which overstates the spread of correlated values).
    """
    if record.get("kind") != "kinematic calibration":
        return None
    names = ChainGeometry.names()
    estimated, covariance = record.get("estimated"), record.get("covariance_mm2")
    if isinstance(estimated, list) and isinstance(covariance, list) and all(n in names for n in estimated):
        index = [names.index(n) for n in estimated]
        out = np.zeros((len(names), len(names)))
        out[np.ix_(index, index)] = np.asarray(covariance) * 1e-6
        return out
    std = record.get("std_mm")
    if isinstance(std, list) and len(std) == len(names):
        return np.diag((np.asarray(std) * 1e-3) ** 2)
    return None


def compare_sensors(
    params: Parameters,
    t: np.ndarray,
    predicted: np.ndarray,
    measured: np.ndarray,
    theta_covariance: np.ndarray | None = None,
    uncertainty: str = "the covariance given",
) -> SensorComparison:
    """Measured − predicted attitudes per platform and angle, with the prediction's spread.

    Args:
        params: the model that predicted.
        t: sample times [s], (N,).
        predicted: both platforms' predicted attitudes [rad], (N, 2, 3).
        measured: the sensors' [rad], (N, 2, 3).
        theta_covariance: the per-chain values' covariance [m²], (COUNT, COUNT) (hipsim.stations.deviations.COUNT); None: the prediction carries none.
        uncertainty: where ``theta_covariance`` came from, for the record ("none" without one).
    """
    difference = np.degrees(np.asarray(measured) - np.asarray(predicted))
    spread = None
    if theta_covariance is not None:
        spread = np.sqrt(np.mean(np.degrees(prediction_std(params, predicted, theta_covariance)) ** 2, axis=0))
    entries = []
    for j in range(2):
        for k, angle in enumerate(_ANGLES):
            d = difference[:, j, k]
            rms, peak, peak_at = rms_and_signed_peak(t, d)
            std = None if spread is None else float(spread[j, k])
            entries.append(SensorAgreement(j + 1, angle, rms, float(np.mean(d)), peak, peak_at, std))
    return SensorComparison(len(t), "none" if spread is None else uncertainty, tuple(entries))

"""The calibrated machine as a parameter file: the starting file with the calibrated ``[geometry]``, and the record.

The file every command takes: the starting machine's tables
(:func:`hipsim.machine.toml_writer.parameter_toml`), its ``[geometry]`` table
the calibrated deviations, then an ``[identification]`` table saying how it was
made (``kind = "kinematic calibration"``: the logs, the prior, every value with
its deviation and standard deviation and whether the logs determined it, the
values no log can see and the combinations that hold them, each sensor's noise
and residual, the held-out checks) and its ``[identification.provenance]``
(hipsim's version, the time, the command line, each log's SHA-256). Loading
skips the ``[identification]`` table. One function writes it
(:func:`write_calibrated`), to be switched to the rig's identified-file
schema when there is one.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..files import write_atomic
from ..machine.toml_writer import parameter_toml, table_toml
from . import deviations as dv
from .calibration import Calibration

__all__ = ["CALIBRATED_MARK", "calibrated_toml", "calibration_record", "write_calibrated"]

#: The first line of a parameter file ``hipsim calibrate`` wrote.
CALIBRATED_MARK = "# Calibrated by hipsim calibrate"


def _deg(values: np.ndarray) -> list:
    return np.round(np.degrees(values), 9).tolist()


def calibration_record(
    calibration: Calibration, validation: Sequence[Mapping[str, Any]] = (), start: str = "the published machine"
) -> dict[str, Any]:
    """The ``[identification]`` entries of a calibrated file (module docstring), JSON- and TOML-ready.

    Args:
        calibration: the fit.
        validation: per held-out log, ``{"log": name, "rms_deg": (2, 3), "start_rms_deg": (2, 3)}``.
        start: where the starting machine came from (its file).
    """
    names = list(dv.names())
    return {
        "kind": "kinematic calibration",
        "start": start,
        "logs": list(calibration.logs),
        "samples": calibration.samples,
        "iterations": calibration.iterations,
        "prior_mm": calibration.prior * 1e3,
        "sensor_offsets": "per-log" if np.any(calibration.offsets) else "none",
        "values": names,
        "deviation_mm": np.round(calibration.theta * 1e3, 12).tolist(),
        "std_mm": np.round(calibration.theta_std * 1e3, 12).tolist(),
        "determined": calibration.determined.tolist(),
        "unseen": calibration.unseen,
        "combinations": calibration.structure.definitions(),
        "noise_deg": _deg(calibration.noise.ravel()),
        "offsets_deg": [_deg(o.ravel()) for o in calibration.offsets],
        "residual_rms_deg": [_deg(r.ravel()) for r in calibration.residual_rms],
        "start_residual_rms_deg": [_deg(r.ravel()) for r in calibration.start_rms],
        "validation_logs": [str(v["log"]) for v in validation],
        "validation_rms_deg": [_deg(np.asarray(v["rms"]).ravel()) for v in validation],
        "validation_start_rms_deg": [_deg(np.asarray(v["start_rms"]).ravel()) for v in validation],
    }


def calibrated_toml(
    calibration: Calibration,
    validation: Sequence[Mapping[str, Any]] = (),
    provenance: Mapping[str, Any] | None = None,
    start: str = "the published machine",
) -> str:
    """The text of the calibrated parameter file (module docstring)."""
    record = calibration_record(calibration, validation, start)
    header = [
        f"{CALIBRATED_MARK} from {len(calibration.logs)} log(s), {calibration.samples} samples: "
        + ", ".join(calibration.logs),
        f"# Start: {start}; prior ±{calibration.prior * 1e3:g} mm on every per-chain value.",
        "# Sensor noise [deg] m_1 α β γ, m_2 α β γ: " + ", ".join(f"{v:.4g}" for v in record["noise_deg"]),
        "# Not seen by these logs (kept at the start): " + (", ".join(calibration.unseen) or "none"),
        "# The combinations estimated and the [identification] record follow the machine's tables.",
    ]
    text = (
        "\n".join(header) + "\n\n" + parameter_toml(calibration.machine) + "\n" + table_toml("identification", record)
    )
    if provenance:
        flat = {k: v for k, v in provenance.items() if isinstance(v, (str, int, float, bool, list))}
        text += "\n" + table_toml("identification.provenance", flat)
    return text


def write_calibrated(
    path: str | Path,
    calibration: Calibration,
    validation: Sequence[Mapping[str, Any]] = (),
    provenance: Mapping[str, Any] | None = None,
    start: str = "the published machine",
) -> Path:
    """Write the calibrated parameter file atomically (nothing is written if anything fails)."""
    return write_atomic(path, calibrated_toml(calibration, validation, provenance, start))

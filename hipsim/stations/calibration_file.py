"""The calibrated machine as a parameter file: the starting file with the calibrated ``[geometry]``, and the record.

The file every command takes: the starting machine's tables
(:func:`hipsim.machine.toml_writer.parameter_toml`), its ``[geometry]`` table
the calibrated deviations, then an ``[identification]`` table saying how it was
made (``kind = "kinematic calibration"``: the logs, the prior, every value with
its deviation and standard deviation and whether the logs determined it, the
values no log can see and the combinations that hold them, each sensor's noise
and residual, the held-out checks) and its ``[identification.provenance]``
(hipsim's version, the time, the command line, each log's SHA-256). Written
through the rig's one identified-file schema
(:mod:`hipsim.rig.identification.identified_file`), which reads it back
(:func:`~hipsim.rig.identification.identified_file.read_identified_file`:
its logs, start and provenance; no dynamic base parameters); loading the
machine skips the ``[identification]`` table.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..rig.identification.identified_file import FileProvenance, identified_toml, write_identified_file
from . import deviations as dv
from .calibration import Calibration
from .calibration_summary import HeldOutResidual

__all__ = ["CALIBRATED_MARK", "calibrated_toml", "calibration_record", "write_calibrated"]

#: The first line of a parameter file ``hipsim calibrate`` wrote.
CALIBRATED_MARK = "# Calibrated by hipsim calibrate"


def _deg(values: np.ndarray) -> list:
    return np.round(np.degrees(values), 9).tolist()


def calibration_record(
    calibration: Calibration, validation: Sequence[HeldOutResidual] = (), start: str = "the published machine"
) -> dict[str, Any]:
    """The ``[identification]`` entries of a calibrated file (module docstring), JSON- and TOML-ready: a TOML table
    (the file's schema, read back by :mod:`~hipsim.rig.identification.identified_file`), not a summary.

    Args:
        calibration: the fit.
        validation: per held-out log, its errors (:func:`~hipsim.stations.calibration_summary.held_out_residual`).
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
        "value_determined": calibration.determined.tolist(),
        # The posterior covariance of the estimated values (their names in order): what carries the calibration's
        # uncertainty to a prediction (stations --sliders), the correlations included.
        "estimated": [names[k] for k in calibration.structure.independent],
        "covariance_mm2": [[float(f"{v:.12g}") for v in row] for row in calibration.covariance * 1e6],
        "unseen": calibration.unseen,
        "combinations": calibration.structure.definitions(),
        "confounded_offsets": [c.sensor for c in calibration.confounded],
        "confounded_values": [", ".join(c.values) for c in calibration.confounded],
        "noise_deg": _deg(calibration.noise.ravel()),
        "offsets_deg": [_deg(o.ravel()) for o in calibration.offsets],
        "residual_rms_deg": [_deg(r.ravel()) for r in calibration.residual_rms],
        "start_residual_rms_deg": [_deg(r.ravel()) for r in calibration.start_rms],
        "validation_logs": [v.log for v in validation],
        "validation_rms_deg": [np.round(np.ravel(v.rms_deg), 9).tolist() for v in validation],
        "validation_start_rms_deg": [np.round(np.ravel(v.start_rms_deg), 9).tolist() for v in validation],
    }


def _comments(calibration: Calibration, record: Mapping[str, Any], start: str) -> list[str]:
    return [
        f"{CALIBRATED_MARK} from {len(calibration.logs)} log(s), {calibration.samples} samples: "
        + ", ".join(calibration.logs),
        f"# Start: {start}; prior ±{calibration.prior * 1e3:g} mm on every per-chain value.",
        "# Sensor noise [deg] m_1 α β γ, m_2 α β γ: " + ", ".join(f"{v:.4g}" for v in record["noise_deg"]),
        "# Not seen by these logs (kept at the start): " + (", ".join(calibration.unseen) or "none"),
        *(
            f"# Sensor offset {c.sensor} not told apart from {', '.join(c.values)} (R² {c.explained:.4f}); "
            "a fixture's known-attitude rows separate them."
            for c in calibration.confounded
        ),
    ]


def calibrated_toml(
    calibration: Calibration,
    validation: Sequence[HeldOutResidual] = (),
    provenance: FileProvenance | None = None,
    start: str = "the published machine",
) -> str:
    """The text of the calibrated parameter file (module docstring)."""
    record = calibration_record(calibration, validation, start)
    return identified_toml(calibration.machine, record, provenance, _comments(calibration, record, start))


def write_calibrated(
    path: str | Path,
    calibration: Calibration,
    validation: Sequence[HeldOutResidual] = (),
    provenance: FileProvenance | None = None,
    start: str = "the published machine",
) -> Path:
    """Write the calibrated parameter file atomically (nothing is written if anything fails)."""
    record = calibration_record(calibration, validation, start)
    return write_identified_file(path, calibration.machine, record, provenance, _comments(calibration, record, start))

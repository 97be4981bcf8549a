"""What a station run reports: its columns, and per platform and angle the RMS and peak error and when it peaks.

The columns (the CSV/Parquet contract ``hipsim stations`` writes and other
commands read): ``t_s``, the carriage commands ``L_11_mm, L_12_mm, L_13_mm``
(in the encoders' reading), each platform's attitude ``alpha_1_deg`` …
``gamma_2_deg``, its error against the desired ``err_alpha_1_deg`` …
``err_gamma_2_deg``, and ``Fe_N`` when the motion carries a load.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..exceptions import TrajectoryError
from ..motion.iso_compliance import DEFAULT_TOLERANCES, iso_check
from .commands import StationMotion

__all__ = ["ANGLES", "attitude_columns", "error_columns", "station_columns", "station_summary"]

#: The angles, as the columns name them.
ANGLES = ("alpha", "beta", "gamma")


def attitude_columns() -> list[str]:
    """``alpha_1_deg`` … ``gamma_2_deg``: platform 1's three angles, then platform 2's."""
    return [f"{a}_{j}_deg" for j in (1, 2) for a in ANGLES]


def error_columns() -> list[str]:
    """``err_alpha_1_deg`` … ``err_gamma_2_deg``."""
    return [f"err_{name}" for name in attitude_columns()]


def station_columns(motion: StationMotion, load: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The run as named columns in the file's units (s, mm, degrees, N); ``Fe_N`` only with a load."""
    columns = {"t_s": motion.t}
    columns |= {f"L_1{i + 1}_mm": motion.carriages[:, i] * 1e3 for i in range(3)}
    q = np.degrees(motion.attitudes).reshape(len(motion.t), 6)
    e = np.degrees(motion.errors).reshape(len(motion.t), 6)
    columns |= {name: q[:, k] for k, name in enumerate(attitude_columns())}
    columns |= {name: e[:, k] for k, name in enumerate(error_columns())}
    if load is not None:
        columns["Fe_N"] = np.asarray(load, dtype=float)
    return columns


def _iso(t, q, load, source, periodic) -> dict[str, Any]:
    try:
        check = iso_check(t, q, load, DEFAULT_TOLERANCES, source=source, periodic=periodic)
    except TrajectoryError as error:
        return {"verdict": "not made", "reason": error.args[0] if error.args else str(error)}
    return {
        "verdict": "PASS" if check.passed else "FAIL",
        "failing": list(check.failing),
        "cycles": len(check.cycles),
        "worst_deg": {a: check.worst(a) for a in ANGLES},
    }


def station_summary(
    motion: StationMotion, load: np.ndarray | None = None, source: str = "trajectory", periodic: bool = False
) -> dict[str, Any]:
    """Per platform and angle the RMS and peak error in [deg] and the time of the peak; each station's ISO verdict.

    Args:
        motion: the run.
        load: the axial load in [N], (N,), for the ISO 14242-1 check of each station's motion; None: no check.
        source: the desired motion's name.
        periodic: the samples cover whole periods (the ISO check then wraps around).
    """
    e = np.degrees(motion.errors)
    platforms = []
    for j in range(2):
        angles = {}
        for k, a in enumerate(ANGLES):
            values = e[:, j, k]
            peak = int(np.argmax(np.abs(values)))
            angles[a] = {
                "rms_deg": float(np.sqrt(np.mean(values**2))),
                "peak_deg": float(values[peak]),
                "peak_at_s": float(motion.t[peak]),
            }
        entry: dict[str, Any] = {"platform": j + 1, "angles": angles}
        entry["controlled"] = motion.control in (str(j + 1), "both")
        if load is not None:
            entry["iso"] = _iso(motion.t, motion.attitudes[:, j], load, f"{source}, station {j + 1}", periodic)
        platforms.append(entry)
    squared = float(np.sum(e**2))
    return {
        "control": motion.control,
        "weights": list(motion.weights),
        "samples": len(motion.t),
        "duration_s": float(motion.t[-1] - motion.t[0]) if len(motion.t) > 1 else 0.0,
        "sum_squared_error_deg2": squared,
        "rms_error_deg": math.sqrt(squared / max(1, e.size)),
        "platforms": platforms,
    }

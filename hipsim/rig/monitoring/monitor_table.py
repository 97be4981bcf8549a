"""The monitor's table as a file (CSV or Parquet by the suffix), keyed by its set-up's fingerprint so a rerun extends it.

One row a snapshot, sorted by cycle, columns :data:`COLUMNS`. The set-up's
fingerprints (:meth:`hipsim.rig.monitoring.monitor_fit.MonitorSetup.fingerprints`)
are kept with the rows: a Parquet file's key-value metadata (``hipsim``,
JSON), a CSV file's first line ``# hipsim monitor: {JSON}`` (pandas:
``read_csv(path, comment="#")``). A rerun of the same set-up keeps the rows of
the snapshots it already has (by file name and SHA-256: a file whose bytes
changed is estimated again) and estimates only the new ones; a rerun of another
set-up into the file is refused (:meth:`hipsim.result_table.ResultTable.resume`,
the rule ``hipsim sweep`` resumes by). Numbers are written so that they read
back to the same bits (CSV: Python's shortest round-trip form; Parquet:
float64), NaN as an empty CSV cell.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ...result_table import ResultTable
from .monitor_fit import ESTIMATE_COLUMNS

__all__ = [
    "COLUMNS",
    "CSV_METADATA",
    "MONITOR_TABLE",
    "PARTS",
    "TEXT_COLUMNS",
    "read_metadata",
    "read_table",
    "table_rows",
    "write_table",
]

_STATIONS = tuple(
    f"{name}_{p}{unit}" for p in (1, 2) for name, unit in (("hip_mu_change", ""), ("hip_mu_change", "_std"))
)
#: The table's columns, in order.
COLUMNS = (
    "cycle",
    "last_cycle",
    "file",
    "samples",
    "phase",
    "load_friction_mm",
    "load_friction_mm_std",
    "hip_mu_change",
    "hip_mu_change_std",
    "weight_friction_Nmm",
    "weight_friction_Nmm_std",
    "screw_coulomb_Nmm",
    "screw_coulomb_Nmm_std",
    "screw_viscous_Nmm_s_rad",
    "screw_viscous_Nmm_s_rad_std",
    "load_friction_1_mm",
    "load_friction_1_mm_std",
    "load_friction_2_mm",
    "load_friction_2_mm_std",
    "stations",
    *_STATIONS,
    "load_gain",
    "load_gain_change",
    "residual_rms_Nmm",
    "ewma_mm",
    "lcl_mm",
    "ucl_mm",
    *(f"{name}_{p}_mm" for p in (1, 2) for name in ("ewma", "lcl", "ucl")),
    "flag",
    "alarm",
    "state",
    "acknowledged",
    "note",
    "bytes",
    "sha256",
)
#: Columns holding text.
TEXT_COLUMNS = ("file", "phase", "stations", "flag", "state", "note", "sha256")
#: The monitor's table: its rows, the set-up beside them (:class:`hipsim.result_table.ResultTable`).
MONITOR_TABLE = ResultTable("monitor", TEXT_COLUMNS)
#: A CSV file's first line, a comment, holding the set-up (JSON follows).
CSV_METADATA = MONITOR_TABLE.csv_metadata
#: What each part of the fingerprint comes from, for a refusal.
PARTS = {
    "parameters": "the parameter file",
    "model": "the model options (cutoff, torque constant, tolerance, rate)",
    "window": "--window",
    "estimator": "the estimator (another hipsim version)",
}
_INTEGERS = ("cycle", "last_cycle", "samples", "bytes")


def write_table(path: str | Path, columns: Mapping[str, Sequence[Any]], metadata: Mapping[str, Any]) -> Path:
    """Write the rows atomically with the set-up's description."""
    return MONITOR_TABLE.write(path, columns, metadata)


def read_table(path: str | Path) -> dict[str, list[Any]]:
    """The columns of a file :func:`write_table` wrote.

    Raises:
        FileRowError: naming the file (line and column in a CSV) when it is not such a table.
    """
    return MONITOR_TABLE.read(path)


def read_metadata(path: str | Path) -> dict[str, Any] | None:
    """The set-up :func:`write_table` kept with the rows; None when the file holds none."""
    return MONITOR_TABLE.metadata(path)


def table_rows(table: Mapping[str, Sequence[Any]]) -> list[dict[str, Any]]:
    """The estimate rows (:data:`~hipsim.rig.monitoring.monitor_fit.ESTIMATE_COLUMNS`) of a table's columns."""
    rows = []
    for k in range(len(table["cycle"])):
        row = {name: table[name][k] for name in ESTIMATE_COLUMNS}
        for name in _INTEGERS:
            row[name] = int(row[name])
        rows.append(row)
    return rows

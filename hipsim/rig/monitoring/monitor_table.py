"""The monitor's table as a file (CSV or Parquet by the suffix), keyed by its set-up's fingerprint so a rerun extends it.

One row a snapshot, sorted by cycle, columns :data:`COLUMNS`. The set-up's
fingerprints (:meth:`hipsim.rig.monitoring.monitor_fit.MonitorSetup.fingerprints`) are kept
with the rows: a Parquet file's key-value metadata (``hipsim``, JSON), a CSV
file's first line ``# hipsim monitor: {JSON}`` (pandas:
``read_csv(path, comment="#")``). A rerun of the same set-up keeps the rows of
the snapshots it already has (by file name and first cycle) and estimates only
the new ones; a rerun of another set-up into the file is refused
(:func:`previous_rows`). Numbers are written so that they read back to the same
bits (CSV: Python's shortest round-trip form; Parquet: float64), NaN as an
empty CSV cell.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ...exceptions import OutputError
from ...fingerprint import changed_parts
from ...result_table import ResultTable
from .monitor_fit import ESTIMATE_COLUMNS

__all__ = [
    "COLUMNS",
    "CSV_METADATA",
    "TEXT_COLUMNS",
    "check_out",
    "previous_rows",
    "read_metadata",
    "read_table",
    "write_table",
]

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
    *[
        name
        for name in ESTIMATE_COLUMNS
        if name not in ("cycle", "last_cycle", "file", "samples", "load_friction_mm", "load_friction_mm_std")
    ],
    "ewma_mm",
    "ucl_mm",
    "alarm",
)
#: Columns holding text.
TEXT_COLUMNS = ("file", "phase", "stations")
#: The monitor's table: its rows, the set-up beside them (:class:`hipsim.result_table.ResultTable`).
MONITOR_TABLE = ResultTable("monitor", TEXT_COLUMNS)
#: A CSV file's first line, a comment, holding the set-up (JSON follows).
CSV_METADATA = MONITOR_TABLE.csv_metadata
#: What each part of the fingerprint comes from, for a refusal.
PARTS = {
    "parameters": "the parameter file",
    "model": "the model options (cutoff, torque constant, tolerance)",
    "window": "--window",
    "estimator": "the estimator (another hipsim version)",
}


def _format(path: str | Path) -> str:
    return MONITOR_TABLE.format(path)


def check_out(path: str | Path) -> Path:
    """The table's path, checked before anything runs: a .csv/.parquet file in an existing folder."""
    out = Path(path)
    _format(out)
    if out.is_dir():
        raise OutputError(out, "is a folder; give a .csv or .parquet file name")
    folder = out.parent if str(out.parent) else Path(".")
    if not folder.is_dir():
        raise OutputError(out, f"cannot write, folder '{folder}' does not exist")
    return out


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


def previous_rows(out: Path | None, fingerprints: Mapping[str, str], restart: bool) -> list[dict[str, Any]]:
    """The estimate rows already in ``out`` (none when it does not exist, or with ``restart``); another set-up's file refused.

    Raises:
        OutputError: the file holds other columns, no set-up, or another set-up's rows.
    """
    if out is None or restart or not Path(out).exists():
        return []
    table = read_table(out)
    if tuple(table) != COLUMNS:
        raise OutputError(
            out, "holds other columns than a monitor's table: give another --out, or --restart to replace it"
        )
    recorded = (read_metadata(out) or {}).get("fingerprints")
    if not isinstance(recorded, dict):
        raise OutputError(
            out,
            "records no set-up, so its rows cannot be matched to this monitor's: give another --out, or --restart to replace it",
        )
    changed = changed_parts(recorded, fingerprints)
    if changed:
        differ = ", ".join(PARTS.get(name, name) for name in changed)
        raise OutputError(
            out,
            f"holds the rows of another set-up ({differ} differ{'s' if len(changed) == 1 else ''}): "
            "give another --out, or --restart to replace it",
        )
    rows = []
    for k in range(len(table["cycle"])):
        row = {name: table[name][k] for name in ESTIMATE_COLUMNS}
        for name in ("cycle", "last_cycle", "samples"):
            row[name] = int(row[name])
        rows.append(row)
    return rows

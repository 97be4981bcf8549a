"""The monitor's table as a file (CSV or Parquet by the suffix), keyed by its set-up's fingerprint so a rerun extends it.

One row a snapshot, sorted by cycle, columns :data:`COLUMNS`. The set-up's
fingerprints (:meth:`hipsim.rig.monitor_fit.MonitorSetup.fingerprints`) are kept
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

import csv
import io
import json
import math
from pathlib import Path
from typing import Any, Mapping, Sequence

from ..exceptions import FileRowError, MissingDependencyError, OutputError
from ..files import write_atomic
from ..fingerprint import changed_parts
from ..tables import MAX_LINE_BYTES, cells, data_lines, read_text_lines
from .monitor_fit import ESTIMATE_COLUMNS

__all__ = ["COLUMNS", "CSV_METADATA", "TEXT_COLUMNS", "check_out", "previous_rows", "read_metadata", "read_table", "write_table"]

#: The table's columns, in order.
COLUMNS = (
    "cycle", "last_cycle", "file", "samples", "phase",
    "load_friction_mm", "load_friction_mm_std", "hip_mu_change", "hip_mu_change_std",
    *[name for name in ESTIMATE_COLUMNS if name not in ("cycle", "last_cycle", "file", "samples", "load_friction_mm", "load_friction_mm_std")],
    "ewma_mm", "ucl_mm", "alarm",
)  # fmt: skip
#: Columns holding text.
TEXT_COLUMNS = ("file", "phase", "stations")
#: Suffixes and formats.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}
#: A CSV file's first line, a comment, holding the set-up (JSON follows).
CSV_METADATA = "# hipsim monitor: "
#: What each part of the fingerprint comes from, for a refusal.
PARTS = {"parameters": "the parameter file", "model": "the model options (cutoff, torque constant, tolerance)",
         "window": "--window", "estimator": "the estimator (another hipsim version)"}  # fmt: skip


def _format(path: str | Path) -> str:
    kind = FORMATS.get(Path(path).suffix.lower())
    if kind is None:
        raise OutputError(path, f"unknown suffix: give a {', '.join(FORMATS)} file")
    return kind


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


def _pyarrow():
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        raise MissingDependencyError("pyarrow", "sweep", "Parquet output") from None
    return pyarrow


def write_table(path: str | Path, columns: Mapping[str, Sequence[Any]], metadata: Mapping[str, Any]) -> Path:
    """Write the rows atomically with the set-up's description."""
    if _format(path) == "parquet":
        pa = _pyarrow()
        table = pa.table({
            name: pa.array([str(v) for v in values] if name in TEXT_COLUMNS else [float(v) for v in values],
                           type=pa.string() if name in TEXT_COLUMNS else pa.float64())
            for name, values in columns.items()
        })  # fmt: skip
        table = table.replace_schema_metadata({"hipsim": json.dumps(dict(metadata))})
        buffer = io.BytesIO()
        pa.parquet.write_table(table, buffer)
        return write_atomic(path, buffer.getvalue())
    buffer = io.StringIO()
    buffer.write(CSV_METADATA + json.dumps(dict(metadata), separators=(",", ":")) + "\n")
    writer = csv.writer(buffer, lineterminator="\n")
    names = list(columns)
    writer.writerow(names)
    for row in zip(*(columns[name] for name in names)):
        writer.writerow([v if name in TEXT_COLUMNS else ("" if math.isnan(float(v)) else repr(float(v))) for name, v in zip(names, row)])
    return write_atomic(path, buffer.getvalue())


def read_table(path: str | Path) -> dict[str, list[Any]]:
    """The columns of a file :func:`write_table` wrote.

    Raises:
        FileRowError: naming the file (line and column in a CSV) when it is not such a table.
    """
    source = str(path)
    if _format(path) == "parquet":
        pa = _pyarrow()
        try:
            return pa.parquet.read_table(path).to_pydict()
        except (OSError, pa.ArrowException) as error:
            raise FileRowError(f"not a Parquet table of a monitor ({error})", source) from None
    lines = data_lines(read_text_lines(path, "monitor table", FileRowError), ",")
    if not lines:
        raise FileRowError("empty: no header", source)
    number, text = lines[0]
    header = _cells(text, source, number)
    columns: dict[str, list[Any]] = {name: [] for name in header}
    for number, line in lines[1:]:
        row = _cells(line, source, number)
        if len(row) != len(header):
            raise FileRowError(f"{len(row)} cells, the header has {len(header)}", source, number)
        for name, cell in zip(header, row):
            if name in TEXT_COLUMNS:
                columns[name].append(cell)
                continue
            try:
                columns[name].append(float(cell) if cell.strip() else math.nan)
            except ValueError:
                raise FileRowError(f"expected a number, got '{cell}'", source, number, name) from None
    return columns


def _cells(line: str, source: str, number: int) -> list[str]:
    try:
        return cells(line, ",")
    except ValueError as error:
        raise FileRowError(str(error), source, number) from None


def read_metadata(path: str | Path) -> dict[str, Any] | None:
    """The set-up :func:`write_table` kept with the rows; None when the file holds none."""
    try:
        if _format(path) == "parquet":
            pa = _pyarrow()
            try:
                text = (pa.parquet.read_schema(path).metadata or {}).get(b"hipsim")
            except (OSError, pa.ArrowException):
                return None
        else:
            with open(path, "rb") as stream:
                first = stream.readline(MAX_LINE_BYTES).removeprefix(b"\xef\xbb\xbf").decode("utf-8")
            text = first[len(CSV_METADATA):] if first.startswith(CSV_METADATA) else None
        described = json.loads(text) if text else None
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    return described if isinstance(described, dict) else None


def previous_rows(out: Path | None, fingerprints: Mapping[str, str], restart: bool) -> list[dict[str, Any]]:
    """The estimate rows already in ``out`` (none when it does not exist, or with ``restart``); another set-up's file refused.

    Raises:
        OutputError: the file holds other columns, no set-up, or another set-up's rows.
    """
    if out is None or restart or not Path(out).exists():
        return []
    table = read_table(out)
    if tuple(table) != COLUMNS:
        raise OutputError(out, "holds other columns than a monitor's table: give another --out, or --restart to replace it")
    recorded = (read_metadata(out) or {}).get("fingerprints")
    if not isinstance(recorded, dict):
        raise OutputError(out, "records no set-up, so its rows cannot be matched to this monitor's: give another --out, or --restart to replace it")
    changed = changed_parts(recorded, fingerprints)
    if changed:
        differ = ", ".join(PARTS.get(name, name) for name in changed)
        raise OutputError(out, f"holds the rows of another set-up ({differ} differ{'s' if len(changed) == 1 else ''}): "
                          "give another --out, or --restart to replace it")  # fmt: skip
    rows = []
    for k in range(len(table["cycle"])):
        row = {name: table[name][k] for name in ESTIMATE_COLUMNS}
        for name in ("cycle", "last_cycle", "samples"):
            row[name] = int(row[name])
        rows.append(row)
    return rows

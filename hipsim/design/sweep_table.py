"""A sweep's results as a file: Apache Parquet or CSV (by the suffix), written atomically, read back to resume.

One row a variant, one column a swept key (its name as typed, unit in it)
or a metric (:func:`hipsim.design.sweep.metric_columns`). Numbers are
written so that they read back to the same bits (CSV: Python's shortest
round-trip form; Parquet: float64), NaN as an empty CSV cell.

The sweep's description (its set-up's fingerprints among it, so that a
rerun into the file can tell whether its rows are of the same set-up) is
kept with the rows: in a Parquet file's key-value metadata (``hipsim``, as
JSON), in a CSV file as its first line, a comment ``# hipsim sweep: {JSON}``
(pandas: ``read_csv(path, comment="#")``) (:func:`read_metadata`).
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
from ..tables import MAX_LINE_BYTES, cells, data_lines, read_text_lines
from .sweep import TEXT_COLUMNS

__all__ = ["CSV_METADATA", "FORMATS", "read_metadata", "read_table", "table_format", "write_table"]

#: Output formats by file suffix.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}
#: How a CSV file's first line, a comment, starts when it holds the sweep's description (JSON follows).
CSV_METADATA = "# hipsim sweep: "


def table_format(path: str | Path) -> str:
    """"parquet" or "csv" from the file's suffix.

    Raises:
        OutputError: any other suffix.
    """
    kind = FORMATS.get(Path(path).suffix.lower())
    if kind is None:
        raise OutputError(path, f"unknown suffix: give a {', '.join(FORMATS)} file")
    return kind


def _pyarrow():
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        raise MissingDependencyError("pyarrow", "sweep", "Parquet output") from None
    return pyarrow


def write_table(path: str | Path, columns: Mapping[str, Sequence[Any]], metadata: Mapping[str, Any] | None = None) -> Path:
    """Write the rows atomically; ``metadata`` goes into a Parquet file's key-value metadata (``hipsim``, as JSON).

    Args:
        path: a ``.parquet`` or ``.csv`` file.
        columns: column → values, all of one length; :data:`TEXT_COLUMNS` hold text, the rest numbers.
        metadata: plain data describing the sweep (Parquet: the ``hipsim``
            key-value metadata; CSV: a first line ``# hipsim sweep: {JSON}``).

    Raises:
        OutputError: an unknown suffix, or the file cannot be written.
    """
    kind = table_format(path)
    if kind == "parquet":
        pa = _pyarrow()
        table = pa.table({
            name: pa.array([str(v) for v in values] if name in TEXT_COLUMNS else [float(v) for v in values],
                           type=pa.string() if name in TEXT_COLUMNS else pa.float64())
            for name, values in columns.items()
        })  # fmt: skip
        table = table.replace_schema_metadata({"hipsim": json.dumps(dict(metadata or {}))})
        buffer = io.BytesIO()
        pa.parquet.write_table(table, buffer)
        return write_atomic(path, buffer.getvalue())
    buffer = io.StringIO()
    if metadata is not None:
        buffer.write(CSV_METADATA + json.dumps(dict(metadata), separators=(",", ":")) + "\n")
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    names = list(columns)
    for row in zip(*(columns[name] for name in names)):
        writer.writerow([v if name in TEXT_COLUMNS else ("" if math.isnan(v) else repr(float(v))) for name, v in zip(names, row)])
    return write_atomic(path, buffer.getvalue())


def read_table(path: str | Path) -> dict[str, list[Any]]:
    """The columns of a file :func:`write_table` wrote.

    Raises:
        FileRowError: naming the file (and line and column in a CSV) when it cannot be read as such a table.
    """
    source = str(path)
    if table_format(path) == "parquet":
        pa = _pyarrow()
        try:
            return pa.parquet.read_table(path).to_pydict()
        except (OSError, pa.ArrowException) as error:
            raise FileRowError(f"not a Parquet table of a sweep ({error})", source) from None
    lines = data_lines(read_text_lines(path, "sweep table", FileRowError), ",")  # the description's comment line left out
    if not lines:
        raise FileRowError("empty: no header", source)
    header_line, text = lines[0]
    header = _cells(text, source, header_line)
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
    """The description :func:`write_table` kept with the rows; None when the file holds none (another program's, an older hipsim's).

    Raises:
        OutputError: an unknown suffix.
    """
    try:
        if table_format(path) == "parquet":
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

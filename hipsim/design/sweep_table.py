"""A sweep's results as a file: Apache Parquet or CSV (by the suffix), written atomically, read back to resume.

One row a variant, one column a swept key (its name as typed, unit in it)
or a metric (:func:`hipsim.design.sweep.metric_columns`). Numbers are
written so that they read back to the same bits (CSV: Python's shortest
round-trip form; Parquet: float64), NaN as an empty CSV cell.
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
from .sweep import TEXT_COLUMNS

__all__ = ["FORMATS", "read_table", "table_format", "write_table"]

#: Output formats by file suffix.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}


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
        metadata: plain data describing the sweep (Parquet only; CSV has no place for it).

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
    try:
        with open(path, newline="", encoding="utf-8") as stream:
            lines = list(csv.reader(stream))
    except (OSError, UnicodeDecodeError) as error:
        raise FileRowError(f"cannot read ({getattr(error, 'strerror', None) or error})", source) from None
    if not lines:
        raise FileRowError("empty: no header", source)
    header, columns = lines[0], {name: [] for name in lines[0]}
    for number, row in enumerate(lines[1:], start=2):
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

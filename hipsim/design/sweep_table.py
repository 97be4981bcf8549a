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

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..result_table import FORMATS, ResultTable
from .sweep import TEXT_COLUMNS

__all__ = ["CSV_METADATA", "FORMATS", "SWEEP_TABLE", "read_metadata", "read_table", "table_format", "write_table"]

#: A sweep's table: its rows, the set-up beside them (:class:`hipsim.result_table.ResultTable`).
SWEEP_TABLE = ResultTable("sweep", tuple(TEXT_COLUMNS))
#: How a CSV file's first line, a comment, starts when it holds the sweep's description (JSON follows).
CSV_METADATA = SWEEP_TABLE.csv_metadata


def table_format(path: str | Path) -> str:
    """ "parquet" or "csv" from the file's suffix.

    Raises:
        OutputError: any other suffix.
    """
    return SWEEP_TABLE.format(path)


def write_table(
    path: str | Path, columns: Mapping[str, Sequence[Any]], metadata: Mapping[str, Any] | None = None
) -> Path:
    """Write the rows atomically; ``metadata`` goes into a Parquet file's key-value metadata (``hipsim``, as JSON).

    Args:
        path: a ``.parquet`` or ``.csv`` file.
        columns: column → values, all of one length; :data:`TEXT_COLUMNS` hold text, the rest numbers.
        metadata: plain data describing the sweep (Parquet: the ``hipsim``
            key-value metadata; CSV: a first line ``# hipsim sweep: {JSON}``).

    Raises:
        OutputError: an unknown suffix, or the file cannot be written.
    """
    return SWEEP_TABLE.write(path, columns, metadata)


def read_table(path: str | Path) -> dict[str, list[Any]]:
    """The columns of a file :func:`write_table` wrote.

    Raises:
        FileRowError: naming the file (and line and column in a CSV) when it cannot be read as such a table.
    """
    return SWEEP_TABLE.read(path)


def read_metadata(path: str | Path) -> dict[str, Any] | None:
    """The description :func:`write_table` kept with the rows; None when the file holds none (another program's, an older hipsim's).

    Raises:
        OutputError: an unknown suffix.
    """
    return SWEEP_TABLE.metadata(path)

"""A command's table of results as a file, Apache Parquet or CSV by the suffix, with the set-up that made it.

``hipsim sweep`` (a row a variant) and ``hipsim monitor`` (a row a snapshot)
write their rows here and read them back to resume. Numbers are written so
that they read back to the same bits (CSV: Python's shortest round-trip form;
Parquet: float64), NaN as an empty CSV cell; the columns named as text hold
text. The set-up's description (its fingerprints among it, so that a rerun
into the file can tell whether its rows are of the same set-up) is kept with
the rows: in a Parquet file's key-value metadata (``hipsim``, as JSON), in a
CSV file as its first line, a comment ``# hipsim WHAT: {JSON}`` (pandas:
``read_csv(path, comment="#")``).

Resuming (:meth:`ResultTable.resume`) is one rule for both: a rerun into an
existing file keeps its rows when the file holds the same columns and the
same set-up (its fingerprints, :mod:`hipsim.fingerprint`), and is refused,
naming what differs, otherwise; ``restart`` replaces the file.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .exceptions import FileRowError, MissingDependencyError, OutputError
from .files import write_atomic
from .fingerprint import changed_parts
from .tables import MAX_LINE_BYTES, cells, data_lines, read_text_lines

__all__ = ["FORMATS", "ResultTable"]

#: Output formats by file suffix.
FORMATS = {".parquet": "parquet", ".pq": "parquet", ".csv": "csv"}


def _pyarrow():
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        raise MissingDependencyError("pyarrow", "sweep", "Parquet output") from None
    return pyarrow


@dataclass(frozen=True)
class ResultTable:
    """The file format of one command's results.

    Attributes:
        what: the command's results, in messages and the CSV's first line ("sweep", "monitor").
        text_columns: the columns that hold text; the others hold numbers.
    """

    what: str
    text_columns: tuple[str, ...]

    @property
    def csv_metadata(self) -> str:
        """How a CSV file's first line starts when it holds the description (JSON follows)."""
        return f"# hipsim {self.what}: "

    def format(self, path: str | Path) -> str:
        """ "parquet" or "csv" from the file's suffix.

        Raises:
            OutputError: any other suffix.
        """
        kind = FORMATS.get(Path(path).suffix.lower())
        if kind is None:
            raise OutputError(path, f"unknown suffix: give a {', '.join(FORMATS)} file")
        return kind

    def write(
        self, path: str | Path, columns: Mapping[str, Sequence[Any]], metadata: Mapping[str, Any] | None = None
    ) -> Path:
        """Write the rows atomically, with ``metadata`` (plain data describing the set-up) beside them.

        Args:
            path: a ``.parquet`` or ``.csv`` file.
            columns: column → values, all of one length.
            metadata: the description; None for none (a CSV then has no comment line).

        Raises:
            OutputError: an unknown suffix, or the file cannot be written.
        """
        text = self.text_columns
        if self.format(path) == "parquet":
            pa = _pyarrow()
            table = pa.table(
                {
                    name: pa.array(
                        [str(v) for v in values] if name in text else [float(v) for v in values],
                        type=pa.string() if name in text else pa.float64(),
                    )
                    for name, values in columns.items()
                }
            )
            table = table.replace_schema_metadata({"hipsim": json.dumps(dict(metadata or {}))})
            binary = io.BytesIO()
            pa.parquet.write_table(table, binary)
            return write_atomic(path, binary.getvalue())
        buffer = io.StringIO()
        if metadata is not None:
            buffer.write(self.csv_metadata + json.dumps(dict(metadata), separators=(",", ":")) + "\n")
        writer = csv.writer(buffer, lineterminator="\n")
        names = list(columns)
        writer.writerow(names)
        for row in zip(*(columns[name] for name in names)):
            writer.writerow(
                [v if name in text else ("" if math.isnan(float(v)) else repr(float(v))) for name, v in zip(names, row)]
            )
        return write_atomic(path, buffer.getvalue())

    def read(self, path: str | Path) -> dict[str, list[Any]]:
        """The columns of a file :meth:`write` wrote.

        Raises:
            FileRowError: naming the file (and line and column in a CSV) when it cannot be read as such a table.
        """
        source = str(path)
        if self.format(path) == "parquet":
            pa = _pyarrow()
            try:
                return pa.parquet.read_table(path).to_pydict()
            except (OSError, pa.ArrowException) as error:
                raise FileRowError(f"not a Parquet table of a {self.what} ({error})", source) from None
        lines = data_lines(
            read_text_lines(path, f"{self.what} table", FileRowError), ","
        )  # the description's comment line left out
        if not lines:
            raise FileRowError("empty: no header", source)
        header_line, first = lines[0]
        header = _cells(first, source, header_line)
        columns: dict[str, list[Any]] = {name: [] for name in header}
        for number, line in lines[1:]:
            row = _cells(line, source, number)
            if len(row) != len(header):
                raise FileRowError(f"{len(row)} cells, the header has {len(header)}", source, number)
            for name, cell in zip(header, row):
                if name in self.text_columns:
                    columns[name].append(cell)
                    continue
                try:
                    columns[name].append(float(cell) if cell.strip() else math.nan)
                except ValueError:
                    raise FileRowError(f"expected a number, got '{cell}'", source, number, name) from None
        return columns

    def check_out(self, path: str | Path) -> Path:
        """The table's path, checked before anything runs: a known suffix, a file (not a folder) in an existing folder
        that can be written (a temporary file made and dropped there).

        Raises:
            OutputError: naming the path.
        """
        out = Path(path)
        self.format(out)
        if out.is_dir():
            raise OutputError(out, f"is a folder; give a {', '.join(FORMATS)} file name")
        folder = out.parent if str(out.parent) else Path(".")
        if not folder.is_dir():
            raise OutputError(out, f"cannot write, folder '{folder}' does not exist")
        import tempfile

        try:  # an unwritable folder refused before the run, not after it (permissions alone miss a read-only mount)
            with tempfile.TemporaryFile(dir=folder, prefix=".hipsim-probe-"):
                pass
        except OSError as error:
            raise OutputError(out, f"cannot write in folder '{folder}' ({error.strerror or error})") from None
        return out

    def resume(
        self,
        path: str | Path,
        names: Sequence[str],
        fingerprints: Mapping[str, str],
        restart: bool = False,
        parts: Mapping[str, str] | None = None,
    ) -> dict[str, list[Any]]:
        """The rows already in ``path`` to extend, by column; empty columns when it does not exist yet or with ``restart``.

        Args:
            path: the table.
            names: this run's columns, in order.
            fingerprints: this run's set-up, part by part (and whole, ``"setup"``).
            restart: replace the file: its rows are not kept.
            parts: what each part of the fingerprint comes from (an option, a file), for the refusal.

        Raises:
            OutputError: the file holds other columns, no set-up (another program's file, an older hipsim's), or
                another set-up's rows (naming the parts that differ).
            FileRowError: the file cannot be read as such a table.
        """
        out = Path(path)
        if restart or not out.exists():
            return {name: [] for name in names}
        again = "give another --out, or --restart to replace it"
        table = self.read(out)
        if list(table) != list(names):
            raise OutputError(
                out,
                f"holds other columns ({', '.join(list(table)[:4])}, …) than this {self.what}'s "
                f"({', '.join(list(names)[:4])}, …): {again}",
            )
        recorded = (self.metadata(out) or {}).get("fingerprints")
        if not isinstance(recorded, dict):
            raise OutputError(
                out,
                "records no set-up (another program's file, or an older hipsim's), so its rows cannot be matched to "
                f"this {self.what}'s: {again}",
            )
        changed = changed_parts(recorded, fingerprints)
        if changed:
            differ = ", ".join((parts or {}).get(name, name) for name in changed)
            raise OutputError(
                out, f"holds the rows of another set-up ({differ} differ{'s' if len(changed) == 1 else ''}): {again}"
            )
        return table

    def metadata(self, path: str | Path) -> dict[str, Any] | None:
        """The description :meth:`write` kept with the rows; None when the file holds none (another program's, an older hipsim's).

        Raises:
            OutputError: an unknown suffix.
        """
        try:
            if self.format(path) == "parquet":
                pa = _pyarrow()
                try:
                    text = (pa.parquet.read_schema(path).metadata or {}).get(b"hipsim")
                except (OSError, pa.ArrowException):
                    return None
            else:
                with open(path, "rb") as stream:
                    first = stream.readline(MAX_LINE_BYTES).removeprefix(b"\xef\xbb\xbf").decode("utf-8")
                text = first[len(self.csv_metadata) :] if first.startswith(self.csv_metadata) else None
            described = json.loads(text) if text else None
        except (OSError, UnicodeDecodeError, ValueError):
            return None
        return described if isinstance(described, dict) else None


def _cells(line: str, source: str, number: int) -> list[str]:
    try:
        return cells(line, ",")
    except ValueError as error:
        raise FileRowError(str(error), source, number) from None

"""Tables in files: the rules every reader of delimited text (CSV, semicolon- or tab-separated) follows, and the CSV and Parquet encodings writers share.

Reading: text is UTF-8, a spreadsheet's byte-order mark skipped, a byte
that is not UTF-8 named by its line (:func:`read_text`, :func:`open_text`);
a line longer than :data:`MAX_LINE_BYTES` is refused as soon as it is met,
before the rest of it is read (a table's line is never that long: a 12,000
column header is some 150 kB; a file of one 300 MB line is refused in
milliseconds, in a few MB); blank lines (only spaces and separators) and
lines starting with ``#`` are skipped (:func:`data_lines`); the separator is
the first of tab, semicolon, comma that splits the header and the first row
alike (:func:`detect_separator`); cells are split as Python's ``csv`` module
splits them (quotes honoured), a cell as long as its line allows
(:func:`cells`); a number is what a CSV writer would write, ``1_0`` refused,
a decimal comma read where asked (:func:`number`). Each problem is reported
by the caller's own error class (a :class:`~hipsim.exceptions.FileRowError`)
naming the file, so a reader adds its line and column.

Writing: CSV text with 12 significant digits (:func:`csv_header`,
:func:`csv_rows`); Parquet tables of float64 columns (:func:`parquet_table`),
written whole (:func:`parquet_bytes`) or in row groups (:func:`parquet_writer`).
pyarrow is loaded only when a Parquet file is read or written.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Collection, Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import FileRowError

__all__ = [
    "MAX_LINE_BYTES",
    "SEPARATORS",
    "blank",
    "cells",
    "csv_header",
    "csv_rows",
    "data_lines",
    "decimals",
    "detect_separator",
    "number",
    "open_parquet",
    "open_text",
    "parquet_bytes",
    "parquet_concat",
    "parquet_table",
    "parquet_writer",
    "read_text",
    "read_text_lines",
    "text_lines",
]

#: The separators a table may use, in the order they are tried (:func:`detect_separator`).
SEPARATORS = ("\t", ";", ",")
#: The message for a file that is not UTF-8, ``{what}`` the kind of file (a reader may give its own, :func:`read_text`).
NOT_TEXT = "not a text (UTF-8) {what}"
#: The longest line a table may have, in bytes: 4 MiB, some 25 times a 12,000-column header.
MAX_LINE_BYTES = 4 << 20
#: Bytes read at a time by :func:`read_text`.
_CHUNK = 4 << 20
_BOM = b"\xef\xbb\xbf"


# --------------------------------------------------------------------------- text files


def read_text(
    path: str | Path,
    what: str = "file",
    error: type[FileRowError] = FileRowError,
    *,
    not_text: str = NOT_TEXT,
    newline: str | None = None,
) -> str:
    """A text file's whole text (UTF-8, a byte-order mark skipped), or a one-line error naming it.

    Args:
        path: the file.
        what: the kind of file, for messages (``"trajectory file"``).
        error: the error class raised, called as ``error(message, source=path, line=n)``.
        not_text: the message for a file that is not UTF-8 (``{what}`` and
            ``{error}``, the decoding error, filled in); the line is named.
        newline: as :func:`open` has it: None turns ``\\r\\n`` and ``\\r`` into ``\\n``, ``""`` keeps them.

    Raises:
        error: the file is missing, a folder, unreadable or not UTF-8, or
            has a line longer than :data:`MAX_LINE_BYTES` (refused before
            more of it is read).
    """
    source = str(path)
    try:
        with Path(path).open("rb") as stream:
            data = _bounded_bytes(stream, source, what, error)
    except FileNotFoundError:
        raise error(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", source=source) from None
    except OSError as failure:
        raise error(f"cannot read ({failure.strerror})", source=source) from None
    data = data.removeprefix(_BOM)  # spreadsheets often start a "CSV UTF-8" file with a byte-order mark
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as failure:
        line = data.count(b"\n", 0, failure.start) + 1
        raise error(not_text.format(what=what, error=failure), source=source, line=line) from None
    if newline is None and "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


def _too_long(what: str) -> str:
    return f"a line longer than {MAX_LINE_BYTES >> 20} MiB: not a {what} (is it the right file?)"


def _bounded_bytes(stream, source: str, what: str, error: type[FileRowError]) -> bytes:
    """The stream's bytes, read a chunk at a time; a line longer than :data:`MAX_LINE_BYTES` refused once it is met.

    A line ends at ``\\n`` or ``\\r``; the line named is counted in ``\\n``.
    """
    chunks: list[bytes] = []
    lines = 1  # the line the current chunk starts in
    run = 0  # bytes of that line before the chunk
    while chunk := stream.read(_CHUNK):
        codes = np.frombuffer(chunk, dtype=np.uint8)
        ends = np.flatnonzero((codes == 10) | (codes == 13))
        # Lengths of the lines this chunk ends (the first one begun before it), and of the one it leaves open.
        starts = np.concatenate(([-1], ends))
        lengths = np.diff(np.concatenate((starts, [len(chunk)]))) - 1
        lengths[0] += run
        long = np.flatnonzero(lengths > MAX_LINE_BYTES)
        if long.size:
            at = int(starts[long[0]]) + 1  # where the long line starts in the chunk (0 when before it)
            raise error(_too_long(what), source=source, line=lines + chunk.count(b"\n", 0, max(at, 0)))
        run = int(lengths[-1])
        lines += chunk.count(b"\n")
        chunks.append(chunk)
    return b"".join(chunks)


def read_text_lines(path: str | Path, what: str = "file", error: type[FileRowError] = FileRowError) -> list[str]:
    """A text file's lines, without their ends (:func:`read_text`'s reading and errors)."""
    return read_text(path, what, error).split("\n")


def open_text(path: str | Path, what: str = "file", error: type[FileRowError] = FileRowError):
    """A text file opened to read line by line (a binary stream: :func:`text_lines` decodes it).

    Read it through :func:`text_lines`, which decodes UTF-8 (a byte-order
    mark skipped, line ends kept as written), names the line of a byte that
    is not UTF-8, and refuses a line longer than :data:`MAX_LINE_BYTES`
    before reading the rest of it. Errors as :func:`read_text`.
    """
    source = str(path)
    try:
        return open(path, "rb")
    except FileNotFoundError:
        raise error(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", source=source) from None
    except OSError as failure:
        raise error(f"cannot read ({failure.strerror})", source=source) from None


def text_lines(stream, source: str, what: str = "file", error: type[FileRowError] = FileRowError) -> Iterator[str]:
    """The lines of a stream from :func:`open_text`, ends kept; a byte that is not UTF-8 or an over-long line raised as ``error`` naming the line."""
    for number, raw in enumerate(iter(lambda: stream.readline(MAX_LINE_BYTES + 1), b""), start=1):
        if len(raw) > MAX_LINE_BYTES:
            raise error(_too_long(what), source=source, line=number)
        try:
            yield (raw.removeprefix(_BOM) if number == 1 else raw).decode("utf-8")
        except UnicodeDecodeError:
            raise error(NOT_TEXT.format(what=what), source=source, line=number) from None


def blank(line: str, separators: str = ",;") -> bool:
    """True for a line of nothing but spaces, tabs, line ends and ``separators`` (a spreadsheet's empty row)."""
    return not line.strip(" \t\r\n" + separators)


def data_lines(lines: Iterable[str], separators: str = ",;") -> list[tuple[int, str]]:
    """(1-based line number, line) of the lines that hold something: blank lines and ``#`` comments left out."""
    return [
        (k, line)
        for k, line in enumerate(lines, start=1)
        if not blank(line, separators) and not line.lstrip().startswith("#")
    ]


# --------------------------------------------------------------------------- cells and numbers


def cells(line: str, separator: str = ",", width: int | None = None) -> list[str]:
    """A line's cells, split as Python's ``csv`` module splits them (quotes honoured), a cell of any length.

    Args:
        line: one line of the table.
        separator: the separator, one character.
        width: None to keep every cell; else blank cells at the end are
            dropped down to ``width`` cells (a spreadsheet's trailing separators).

    Raises:
        ValueError: a line the ``csv`` module cannot split (e.g. a NUL byte in a quoted cell).
    """
    if '"' not in line and "\r" not in line and "\n" not in line:
        row = (
            line.split(separator) if line else []
        )  # what csv gives for a line without quotes, without its field size limit
    else:
        limit = csv.field_size_limit()
        try:
            csv.field_size_limit(max(limit, len(line) + 1))  # a cell is as long as its line allows (MAX_LINE_BYTES)
            row = next(csv.reader([line], delimiter=separator), [])
        except csv.Error as failure:
            raise ValueError(f"cannot split the line into cells ({failure})") from None
        finally:
            csv.field_size_limit(limit)
    if width is not None:
        while len(row) > width and not row[-1].strip():
            row.pop()
    return row


def detect_separator(header: str, first_row: str | None) -> str:
    """Tab, semicolon or comma: the first that splits the header into columns, and the first row into as many.

    A separator that splits the header but not the first row alike is kept
    as a fallback; comma when none splits the header.

    Raises:
        ValueError: a cell of the header longer than the field size limit (:func:`cells`).
    """
    fallback = None
    for separator in SEPARATORS:
        n = len(cells(header, separator, 0))
        if n < 2:
            continue
        if first_row is None or _count(first_row, separator) == n:
            return separator
        fallback = fallback or separator
    return fallback or ","


def _count(row: str, separator: str) -> int:
    """The row's cells (as :func:`cells` with width 0), -1 when it cannot be split: the row's own reading reports that."""
    try:
        return len(cells(row, separator, 0))
    except ValueError:
        return -1


def number(cell: str, decimal_comma: bool = False) -> float:
    """A cell's number; ValueError if it is not one (as a CSV writer would have written it)."""
    text = cell.strip()
    if "_" in text:  # Python's float() reads "1_0" as 10; a CSV writer would not mean that
        raise ValueError(cell)
    if decimal_comma and "." not in text and text.count(",") == 1:
        text = text.replace(",", ".")
    return float(text)


def decimals(cell: str) -> int | None:
    """Digits after the decimal mark of a plainly written number (None with an exponent)."""
    text = cell.strip()
    if "e" in text.lower():
        return None
    for mark in (".", ","):
        if mark in text:
            return len(text) - text.index(mark) - 1
    return 0


# --------------------------------------------------------------------------- CSV text out


def csv_header(names) -> str:
    """The CSV header line of these column names."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(names)
    return buffer.getvalue()


def csv_rows(columns: Mapping[str, np.ndarray]) -> str:
    """The rows of named columns as CSV text, 12 significant digits, each row ending in a newline."""
    if not columns:
        return ""
    line = ",".join(["%.12g"] * len(columns))
    rows = np.column_stack(list(columns.values())).tolist()
    return "".join([line % tuple(row) + "\n" for row in rows])


# --------------------------------------------------------------------------- Parquet


def open_parquet(path: str | Path, what: str = "file", error: type[FileRowError] = FileRowError):
    """A Parquet file opened to read (a ``pyarrow.parquet.ParquetFile``), or a one-line error naming it.

    Raises:
        error: the file is missing, a folder, or not Parquet (pyarrow's reason in brackets).
    """
    import pyarrow.parquet as pq  # loaded only when a Parquet file is read

    source = str(path)
    try:
        return pq.ParquetFile(path)
    except FileNotFoundError:
        raise error(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", source=source) from None
    except Exception as failure:  # pyarrow's own errors for a file that is not Parquet
        raise error(f"not a Parquet file ({failure})", source=source) from None


def parquet_table(columns: Mapping[str, Any], metadata: Mapping[str, str] | None = None, text: Collection[str] = ()):
    """Named columns as an Arrow table: float64 columns, strings for the names in ``text``.

    Args:
        columns: column name → values, all of one length.
        metadata: text key-value metadata of the table's schema (None: none).
        text: the names of the columns that hold text.
    """
    import pyarrow as pa  # loaded only when a Parquet file is written

    table = pa.table(
        {
            name: pa.array([str(v) for v in values], type=pa.string())
            if name in text
            else np.asarray(values, dtype=float)
            for name, values in columns.items()
        }
    )
    return table if metadata is None else table.replace_schema_metadata(dict(metadata))


def parquet_bytes(table) -> bytes:
    """A whole Arrow table encoded as a Parquet file (pyarrow's default options), to write atomically."""
    import pyarrow.parquet as pq

    buffer = io.BytesIO()
    pq.write_table(table, buffer)
    return buffer.getvalue()


def parquet_concat(tables: list):
    """Arrow tables of one schema as one table (their rows one after the other)."""
    import pyarrow as pa

    return pa.concat_tables(tables)


def parquet_writer(path: str | Path, schema):
    """A ``pyarrow.parquet.ParquetWriter`` of tables with ``schema``, to write row group by row group.

    No dictionary encoding: measured floats hardly repeat, and trying costs 4x the write.
    """
    import pyarrow.parquet as pq

    return pq.ParquetWriter(str(path), schema, use_dictionary=False)

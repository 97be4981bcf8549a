"""A rig log's text rows: the header found, blocks of lines parsed into numbers (NumPy's loadtxt where every line is
a row of numbers, else cell by cell naming the line and column), comments and blank lines left out.

The rules are :mod:`hipsim.tables`' (separators, decimal commas in tab- or ``;``-separated files, ``1_0`` refused);
:class:`hipsim.rig.logs.reader.RigLogFile` scans a file with them.
"""

from __future__ import annotations

import io

import numpy as np

from ...exceptions import TrajectoryError
from ...tables import blank, cells, detect_separator
from ...tables import number as parse_number

__all__ = ["data_rows", "header_of", "parse_block", "parse_lines"]


def header_of(rows, source: str) -> tuple[list[str], int, str, tuple[int, str] | None]:
    """The header, its line number, the separator and the first row (tab, ';' or ',': :func:`hipsim.tables.detect_separator`); a repeated name refused."""
    first = next(rows, None)
    if first is None:
        raise TrajectoryError("the file is empty", source=source)
    number, text = first
    row = next(rows, None)
    try:
        separator = detect_separator(text, row[1] if row is not None else None)
        header = [cell.strip() for cell in cells(text.rstrip("\r\n"), separator, 0)]
    except ValueError as error:
        raise TrajectoryError(str(error), source=source, line=number) from None
    seen = set()
    for name in header:
        if name in seen:
            raise TrajectoryError(f"column '{name}' appears twice", source=source, line=number, column=name)
        seen.add(name)
    return header, number, separator, row


def parse_block(
    block: list[tuple[int, str]], header: list[str], separator: str, source: str
) -> tuple[np.ndarray, np.ndarray]:
    """Values (M, C) and file lines (M,) of a block of (line number, line)."""
    decimal_comma = separator != ","  # as in a trajectory file: 1,5 is 1.5 in a tab- or semicolon-separated log
    numbers = np.array([number for number, _ in block], dtype=np.int64)
    if not block:  # a block of comments and blank lines: NumPy's loadtxt would warn of no data
        return np.empty((0, len(header))), numbers
    # The fast path: no "_" in a number (Python's float() would read "1_0" as 10; the slow path below refuses it by line).
    if not any("_" in line for _, line in block):
        text = "".join(line if line.endswith("\n") else line + "\n" for _, line in block)
        if decimal_comma:
            text = text.replace(",", ".")
        try:
            values = np.loadtxt(io.StringIO(text), delimiter=separator, ndmin=2, dtype=float)
        except ValueError:
            values = None
        if values is not None and values.shape == (len(block), len(header)):
            return values, numbers
    values = np.empty((len(block), len(header)))
    for k, (number, line) in enumerate(block):
        try:
            row = cells(line.rstrip("\r\n"), separator, len(header))
        except ValueError as error:
            raise TrajectoryError(str(error), source=source, line=number) from None
        if len(row) != len(header):
            hint = (
                " (decimal commas? a comma-separated log needs decimal points)"
                if separator == "," and len(row) > len(header)
                else ""
            )
            raise TrajectoryError(f"{len(row)} cells, the header has {len(header)}{hint}", source=source, line=number)
        for c, (name, cell) in enumerate(zip(header, row)):
            try:
                values[k, c] = parse_number(cell, decimal_comma)
            except ValueError:
                raise TrajectoryError(
                    f"'{cell.strip()}' is not a number", source=source, line=number, column=name
                ) from None
    return values, numbers


def parse_lines(
    number: int, lines: list[str], header: list[str], separator: str, source: str
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`parse_block` of consecutive lines from line ``number``: at once when every one is a row of numbers."""
    text = "\n".join(lines) + "\n"
    # Not for empty lines alone: NumPy's loadtxt would warn of no data.
    if "#" not in text and "_" not in text and any(lines):
        try:
            values = np.loadtxt(
                io.StringIO(text.replace(",", ".") if separator != "," else text),
                delimiter=separator,
                ndmin=2,
                dtype=float,
            )
        except ValueError:
            values = None
        if values is not None and values.shape == (len(lines), len(header)):  # a blank line would be one row less
            return values, np.arange(number, number + len(lines), dtype=np.int64)
    return parse_block(data_rows(number, lines), header, separator, source)


def data_rows(number: int, lines: list[str]) -> list[tuple[int, str]]:
    """(line number, line) of a block's lines that hold something: blank lines and ``#`` comments left out."""
    return [(number + k, line) for k, line in enumerate(lines) if not blank(line) and not line.lstrip().startswith("#")]

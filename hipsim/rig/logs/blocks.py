"""The rig-log reader's bytes: a file read in large blocks, hashed as it passes, split into lines and decoded a block
at a time (:mod:`hipsim.rig.logs.reader` parses them).

A block that is not UTF-8 or holds a line longer than :data:`~hipsim.tables.MAX_LINE_BYTES` raises :class:`Reread`;
:func:`line_blocks` then reads the file again line by line through :func:`~hipsim.tables.text_lines`, which names the
line of the fault.
"""

from __future__ import annotations

import hashlib
import io
from collections.abc import Iterator
from itertools import islice

from ...exceptions import TrajectoryError
from ...tables import MAX_LINE_BYTES, text_lines

__all__ = ["Hashed", "Reread", "line_blocks", "text_blocks"]

_BOM = b"\xef\xbb\xbf"


class Hashed(io.RawIOBase):
    """A binary file read in large blocks that hashes them as they pass: the file's SHA-256 costs no second read."""

    def __init__(self, stream):
        self.stream, self.digest, self.size = stream, hashlib.sha256(), 0

    def readable(self) -> bool:
        return True

    def readinto(self, buffer) -> int:
        n = self.stream.readinto(buffer)
        if n:
            self.digest.update(memoryview(buffer)[:n])
            self.size += n
        return n


def text_blocks(stream, source: str, size: int = 1 << 22) -> Iterator[tuple[int, list[str]]]:
    """The file's lines in blocks: (the first's 1-based line number, the lines without their ``\n``).

    Bytes are split at ``\n`` and decoded a block at a time, which is what :func:`hipsim.tables.text_lines`
    does line by line (``\n`` never occurs inside a UTF-8 character). A block that is not UTF-8, or a line
    longer than :data:`~hipsim.tables.MAX_LINE_BYTES`, raises :class:`Reread`: the caller then reads the file
    again line by line from its start, so that the error names the line as :func:`~hipsim.tables.text_lines` does.
    """
    number, carry, first = 1, b"", True
    while True:
        chunk = stream.read(size)
        if first and chunk.startswith(_BOM):
            chunk = chunk[len(_BOM) :]
        first = False
        data = carry + chunk
        if not chunk:
            if data:
                if len(data) > MAX_LINE_BYTES:
                    raise Reread
                yield number, [_decoded(data)]
            return
        end = data.rfind(b"\n") + 1
        carry = data[end:]
        if len(carry) > MAX_LINE_BYTES:
            raise Reread
        if end:
            lines = _decoded(data[: end - 1]).split("\n")
            # A line with its "\n" longer than MAX_LINE_BYTES, as text_lines counts; 4-byte characters first by length.
            if max(map(len, lines)) >= MAX_LINE_BYTES // 4:
                if max(len(line.encode("utf-8")) for line in lines) >= MAX_LINE_BYTES:
                    raise Reread
            yield number, lines
            number += len(lines)


def line_blocks(stream, source: str, size: int, stop: float) -> Iterator[tuple[int, list[str]]]:
    """:func:`text_blocks` read line by line through :func:`~hipsim.tables.text_lines` (which names the line of a
    byte that is not UTF-8 or of an over-long line), ``size`` lines at a time; no line read from ``stop`` on."""
    lines = text_lines(stream, source, "log file", TrajectoryError)
    number = 1
    while number < stop:
        group = [line.removesuffix("\n") for line in islice(lines, int(min(size, stop - number)))]
        if not group:
            return
        yield number, group
        number += len(group)


class Reread(Exception):
    """A block the fast reading cannot take: read the file again line by line for the exact error."""


def _decoded(data: bytes) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise Reread from None

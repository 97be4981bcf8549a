"""hipsim.rig.logs.blocks pinned on small byte streams: lines split and numbered across block edges, the file's
SHA-256 and size from one read, and the reread (line by line) for a block the fast path cannot take.
"""

from __future__ import annotations

import hashlib
import io

import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.rig.logs.blocks import Hashed, Reread, line_blocks, text_blocks
from hipsim.tables import MAX_LINE_BYTES

DATA = "t_s,Fe_N\n0.0,1\n0.001,2\n\n# note\nµ,3\n0.003,4".encode()


def test_hashed_reads_hash_and_count_every_byte():
    stream = Hashed(io.BytesIO(DATA))
    assert stream.readable()
    read = io.BufferedReader(stream, 8).read()
    assert read == DATA
    assert stream.digest.hexdigest() == hashlib.sha256(DATA).hexdigest() and stream.size == len(DATA)


@pytest.mark.parametrize("size", [1, 3, 7, 16, 1 << 22])
def test_lines_in_blocks_of_any_size(size):
    # Whatever the block size, the lines (without their "\n") and their numbers are the file's; the last line has
    # no "\n"; "µ" (two bytes) may fall across a block's edge.
    blocks = list(text_blocks(io.BytesIO(DATA), "d.csv", size))
    lines = [line for _, group in blocks for line in group]
    assert lines == DATA.decode().split("\n")
    numbers = [number for number, _ in blocks]
    assert numbers[0] == 1
    for (number, group), after in zip(blocks, numbers[1:]):
        assert after == number + len(group)


def test_a_bom_opens_the_file_only():
    bom = b"\xef\xbb\xbf"
    (block,) = text_blocks(io.BytesIO(bom + b"a\n" + bom + b"b\n"), "b.csv")
    assert block == (1, ["a", "\ufeffb"])
    # A file of nothing but its BOM has no lines; an empty one neither.
    assert list(text_blocks(io.BytesIO(bom), "e.csv")) == []
    assert list(text_blocks(io.BytesIO(b""), "e.csv")) == []


def test_numbers_after_a_last_line_without_its_end():
    assert list(text_blocks(io.BytesIO(b"a\nb"), "e.csv", 1 << 22)) == [(1, ["a"]), (2, ["b"])]
    assert list(text_blocks(io.BytesIO(b"a\nb\nc"), "e.csv", 3)) == [(1, ["a"]), (2, ["b"]), (3, ["c"])]


@pytest.mark.parametrize(
    "data",
    [
        b"a\n\xff\nb\n",  # not UTF-8
        b"a\n" + b"x" * MAX_LINE_BYTES + b"\n",  # a line longer than the longest a table may have
        b"a\n" + b"x" * (MAX_LINE_BYTES + 1),  # the same as the file's last line
    ],
)
def test_the_fast_path_asks_for_a_reread(data):
    with pytest.raises(Reread):
        list(text_blocks(io.BytesIO(data), "r.csv", 1 << 20))


@pytest.mark.parametrize("size", [1 << 20, 1 << 22])
def test_the_longest_line_is_read(size):
    # MAX_LINE_BYTES with its "\n", as tables.text_lines counts, read in blocks smaller or larger than it.
    line = b"x" * (MAX_LINE_BYTES - 1)
    blocks = list(text_blocks(io.BytesIO(b"a\n" + line + b"\nb"), "r.csv", size))
    assert [len(x) for _, group in blocks for x in group] == [1, MAX_LINE_BYTES - 1, 1]
    # Four-byte characters count by their bytes: a line of MAX_LINE_BYTES/4 of them is MAX_LINE_BYTES bytes.
    wide = "😀".encode() * (MAX_LINE_BYTES // 4)
    with pytest.raises(Reread):
        list(text_blocks(io.BytesIO(b"a\n" + wide + b"\nb"), "r.csv", 1 << 22))


def test_the_reread_names_the_line():
    with pytest.raises(TrajectoryError) as refused:
        list(line_blocks(io.BytesIO(b"a\nb\n\xff\n"), "r.csv", 2, float("inf")))
    assert refused.value.line == 3 and refused.value.source == "r.csv"
    assert str(refused.value) == "r.csv, line 3: not a text (UTF-8) log file"


def test_the_reread_in_groups_up_to_a_line():
    data = b"\xef\xbb\xbfa\nb\nc\nd\ne\n"
    assert list(line_blocks(io.BytesIO(data), "r.csv", 2, float("inf"))) == [
        (1, ["a", "b"]),
        (3, ["c", "d"]),
        (5, ["e"]),
    ]
    # Nothing read from line `stop` on: lines 1 to 3 only.
    assert list(line_blocks(io.BytesIO(data), "r.csv", 2, 4)) == [(1, ["a", "b"]), (3, ["c"])]
    assert list(line_blocks(io.BytesIO(data), "r.csv", 10, 1)) == []


def test_hashed_counts_every_small_read():
    stream = Hashed(io.BytesIO(DATA))
    parts = iter(lambda: stream.read(5), b"")
    assert b"".join(parts) == DATA
    assert stream.size == len(DATA) and stream.digest.hexdigest() == hashlib.sha256(DATA).hexdigest()


def test_a_bom_in_a_later_block_is_text():
    # Blocks of 3 bytes: the second starts with the BOM's bytes, which are then a character of line 2.
    bom = b"\xef\xbb\xbf"
    lines = [line for _, group in text_blocks(io.BytesIO(b"ab\n" + bom + b"c\n"), "b.csv", 3) for line in group]
    assert lines == ["ab", "\ufeffc"]


@pytest.mark.parametrize("size", [1 << 20, 1 << 22])
def test_a_last_line_of_the_longest_without_its_end_is_read(size):
    blocks = list(text_blocks(io.BytesIO(b"a\n" + b"x" * MAX_LINE_BYTES), "r.csv", size))
    assert [len(x) for _, group in blocks for x in group] == [1, MAX_LINE_BYTES]

"""A rig log's text rows (hipsim.rig.logs.text_rows): the header, blocks parsed at once or cell by cell, and the
refusals naming line and column. The whole reader on files: test_reader_laws.py."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.exceptions import TrajectoryError
from hipsim.rig.logs.text_rows import data_rows, header_of, parse_block, parse_lines

HEADER = ["t", "a", "b"]


def test_the_header_its_line_its_separator_and_the_first_row():
    rows = iter([(3, "t;a;b\n"), (4, "0;1,5;2\n")])
    header, line, separator, first = header_of(rows, "log")
    assert (header, line, separator, first) == (HEADER, 3, ";", (4, "0;1,5;2\n"))
    header, _, separator, first = header_of(iter([(1, " t ,a, b\r\n")]), "log")
    assert header == HEADER and separator == "," and first is None  # a header alone


def test_an_empty_file_and_a_repeated_column_are_refused():
    with pytest.raises(TrajectoryError, match="log: the file is empty"):
        header_of(iter([]), "log")
    with pytest.raises(TrajectoryError) as caught:
        header_of(iter([(2, "t,a,t\n")]), "log")
    assert (caught.value.line, caught.value.column) == (2, "t") and "appears twice" in str(caught.value)


def test_a_block_of_numbers_with_decimal_commas_in_a_tab_separated_log():
    values, lines = parse_block([(5, "0\t1,5\t-2\n"), (6, "0,1\t2\t3e-3")], HEADER, "\t", "log")
    np.testing.assert_array_equal(values, [[0.0, 1.5, -2.0], [0.1, 2.0, 0.003]])
    assert lines.tolist() == [5, 6] and lines.dtype == np.int64


def test_an_empty_block_has_no_rows_and_the_headers_columns():
    values, lines = parse_block([], HEADER, ",", "log")
    assert values.shape == (0, 3) and lines.shape == (0,)


@pytest.mark.parametrize(
    ("line", "message", "column"),
    [
        ("1,1_0,2", "'1_0' is not a number", "a"),  # Python's float() reads 10: refused
        ("1,2,x", "'x' is not a number", "b"),
        ("1,2", "2 cells, the header has 3", None),
        ("1,2,3,4", "4 cells, the header has 3 (decimal commas?", None),
    ],
)
def test_a_bad_row_is_named_by_its_line_and_column(line, message, column):
    with pytest.raises(TrajectoryError) as caught:
        parse_block([(7, "0,0,0\n"), (8, line + "\n")], HEADER, ",", "log")
    assert message in str(caught.value) and caught.value.line == 8 and caught.value.column == column


def test_too_few_cells_in_a_semicolon_log_has_no_decimal_comma_hint():
    with pytest.raises(TrajectoryError) as caught:
        parse_block([(2, "1;2;3;4\n")], HEADER, ";", "log")
    assert str(caught.value) == "log, line 2: 4 cells, the header has 3"


def test_lines_with_comments_and_blanks_keep_their_file_lines():
    lines = ["0,1,2", "# a note", "", "3,4,5"]
    values, numbers = parse_lines(10, lines, HEADER, ",", "log")
    np.testing.assert_array_equal(values, [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]])
    assert numbers.tolist() == [10, 13]
    values, numbers = parse_lines(10, ["0,1,2", "3,4,5"], HEADER, ",", "log")  # at once
    assert numbers.tolist() == [10, 11] and values[1, 2] == 5.0
    assert data_rows(1, ["  # indented note", " ", "1,2,3"]) == [(3, "1,2,3")]


def test_the_decimal_comma_hint_only_for_more_cells_than_the_header():
    with pytest.raises(TrajectoryError) as caught:
        parse_block([(8, "1,2\n")], HEADER, ",", "log")
    assert str(caught.value) == "log, line 8: 2 cells, the header has 3"  # fewer cells: no decimal commas to blame

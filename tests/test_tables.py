"""Tests of hipsim.tables: the rules for reading delimited text, and the CSV and Parquet encodings."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from hipsim.exceptions import CatalogueError, FileRowError, TrajectoryError
from hipsim.tables import (
    blank,
    cells,
    csv_header,
    csv_rows,
    data_lines,
    decimals,
    detect_separator,
    number,
    open_parquet,
    open_text,
    parquet_bytes,
    parquet_table,
    read_text,
    read_text_lines,
    text_lines,
)

# --------------------------------------------------------------------------- text files


def test_read_text_skips_a_byte_order_mark_and_turns_line_ends_into_newlines(tmp_path):
    path = tmp_path / "a.csv"
    path.write_bytes(b"\xef\xbb\xbfa,b\r\n1,2\r3,4\n")
    assert read_text(path) == "a,b\n1,2\n3,4\n"
    assert read_text(path, newline="") == "a,b\r\n1,2\r3,4\n"
    assert read_text_lines(path) == ["a,b", "1,2", "3,4", ""]


def test_read_text_names_the_file_with_the_callers_error(tmp_path):
    with pytest.raises(TrajectoryError, match=r"x\.csv: no such trajectory file$"):
        read_text(tmp_path / "x.csv", "trajectory file", TrajectoryError)
    with pytest.raises(FileRowError, match="is a folder, not a file$"):
        read_text(tmp_path)
    latin = tmp_path / "latin.csv"
    latin.write_bytes("t;é\n".encode("latin-1"))
    with pytest.raises(TrajectoryError, match=r"latin\.csv, line 1: not a text \(UTF-8\) log$"):
        read_text_lines(latin, "log", TrajectoryError)
    with pytest.raises(CatalogueError, match=r"latin\.csv, line 1: not a UTF-8 text file$"):
        read_text(latin, "motor catalogue", CatalogueError, not_text="not a UTF-8 text file")
    with pytest.raises(FileRowError, match=r"latin\.csv, line 1: cannot read \('utf-8' codec can't decode byte 0xe9"):
        read_text(latin, not_text="cannot read ({error})")


def test_open_text_streams_lines_and_names_a_decoding_error(tmp_path):
    path = tmp_path / "log.csv"
    path.write_bytes(b"\xef\xbb\xbft,x\r\n0,1\r\n")
    with open_text(path, "log file", TrajectoryError) as stream:
        assert list(text_lines(stream, str(path), "CSV file", TrajectoryError)) == ["t,x\r\n", "0,1\r\n"]
    path.write_bytes(b"t,x\r\n" + "2,é\n".encode("latin-1"))
    with open_text(path, "log file", TrajectoryError) as stream:
        with pytest.raises(TrajectoryError, match=r"log\.csv, line 2: not a text \(UTF-8\) CSV file$"):
            list(text_lines(stream, str(path), "CSV file", TrajectoryError))
    with pytest.raises(TrajectoryError, match="no such log file$"):
        open_text(tmp_path / "missing.csv", "log file", TrajectoryError)


def test_blank_lines_and_comments_are_left_out_with_their_numbers_kept():
    lines = ["# a comment", "t,x", "", " ; , \t", "  # indented comment", "0,1", ",,"]
    assert data_lines(lines) == [(2, "t,x"), (6, "0,1")]
    assert blank(";;") and not blank(";;", separators=",")
    assert blank(" ,\r\n", separators=",")


# --------------------------------------------------------------------------- cells and numbers


def test_cells_honour_quotes_and_drop_trailing_blanks_down_to_a_width():
    assert cells('a,"b,c",d') == ["a", "b,c", "d"]
    assert cells("a;b;;", ";") == ["a", "b", "", ""]
    assert cells("a;b;;", ";", 0) == ["a", "b"]
    assert cells("a;b;;", ";", 3) == ["a", "b", ""]


def test_a_cell_beyond_the_csv_modules_field_size_limit_is_read_whole_quoted_or_not():
    limit = csv.field_size_limit()
    huge = "1" * (limit + 1)
    assert cells(f"0,{huge}") == ["0", huge]
    assert cells(f'0,"{huge},2"') == ["0", huge + ",2"]
    assert csv.field_size_limit() == limit  # the module's limit is left as it was
    assert detect_separator("t;x;y", f"0;{huge};1") == ";"
    assert detect_separator(f"t,{huge}", None) == ","


@pytest.mark.parametrize(
    ("header", "row", "separator"),
    [
        ("t,x,y", "0,1,2", ","),
        ("t;x;y", "0;1,5;2", ";"),
        ("t\tx\ty", "0\t1,5\t2", "\t"),
        ("t;x;y", None, ";"),
        ("t;x;y", "0;1", ";"),  # splits the header but not the row: kept as the fallback
        ("t,x;y", "0,1;2,5", ";"),  # semicolon before comma: it splits both into two
        ("t", "0", ","),
    ],
)
def test_the_separator_is_the_first_that_splits_header_and_first_row_alike(header, row, separator):
    assert detect_separator(header, row) == separator


def test_numbers_as_a_csv_writer_writes_them():
    assert number(" 1.5 ") == 1.5 and number("-2e3") == -2000.0
    assert number("1,5", decimal_comma=True) == 1.5
    assert math.isnan(number("nan"))
    for text in ("1_0", "1,5", "abc", ""):
        with pytest.raises(ValueError, match="1_0|could not convert"):
            number(text)
    with pytest.raises(ValueError, match="could not convert string to float: '1,000,5'"):
        number("1,000,5", decimal_comma=True)
    assert [decimals(c) for c in ("0.125", "1,50", "12", "1e-3")] == [3, 2, 0, None]


# --------------------------------------------------------------------------- writing


def test_csv_text_has_twelve_significant_digits():
    columns = {"t [s]": np.array([0.0, 1 / 3]), "x, y": np.array([1e-20, 2.0])}
    assert csv_header(columns) == 't [s],"x, y"\n'
    assert csv_rows(columns) == "0,1e-20\n0.333333333333,2\n"
    assert csv_rows({}) == ""


def test_parquet_round_trips_numbers_text_and_metadata(tmp_path):
    path = tmp_path / "t.parquet"
    table = parquet_table({"name": ["a", "b"], "x [mm]": [1, math.nan]}, {"hipsim": "{}"}, text={"name"})
    path.write_bytes(parquet_bytes(table))
    read = open_parquet(path).read()
    assert read.schema.metadata == {b"hipsim": b"{}"}
    assert read.column("name").to_pylist() == ["a", "b"]
    x = read.column("x [mm]").to_numpy()
    assert x.dtype == np.float64 and x[0] == 1.0 and math.isnan(x[1])


def test_open_parquet_names_the_file(tmp_path):
    with pytest.raises(TrajectoryError, match="no such trajectory file$"):
        open_parquet(tmp_path / "x.parquet", "trajectory file", TrajectoryError)
    (tmp_path / "text.parquet").write_text("t_s\n0\n")
    with pytest.raises(FileRowError, match=r"text\.parquet: not a Parquet file \("):
        open_parquet(tmp_path / "text.parquet")

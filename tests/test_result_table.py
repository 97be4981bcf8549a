"""hipsim.result_table by hand: a CSV written as the text below, read back to the same bits, Parquet alike, and the one
resume rule (same columns and set-up keep the rows; anything else is refused, naming what differs)."""

from __future__ import annotations

import math
from typing import Any

import pytest

from hipsim.exceptions import FileRowError, OutputError
from hipsim.result_table import ResultTable

TABLE = ResultTable("sweep", ("name",))
ROWS: dict[str, list[Any]] = {"name": ["v1", "v,2"], "x": [0.1 + 0.2, math.nan]}
SETUP: dict[str, dict[str, str]] = {"fingerprints": {"setup": "s1", "drive": "d1", "trajectory": "t1"}}


def test_a_csv_is_its_description_then_its_rows(tmp_path):
    path = TABLE.write(tmp_path / "a.csv", ROWS, SETUP)
    assert path.read_text() == (
        '# hipsim sweep: {"fingerprints":{"setup":"s1","drive":"d1","trajectory":"t1"}}\n'
        "name,x\n"
        "v1,0.30000000000000004\n"  # the shortest form that reads back to the same bits
        '"v,2",\n'  # NaN: an empty cell; a comma in text: quoted
    )
    back = TABLE.read(path)
    assert back["name"] == ["v1", "v,2"]
    assert back["x"][0] == 0.1 + 0.2 and math.isnan(back["x"][1])
    assert TABLE.metadata(path) == SETUP
    TABLE.write(tmp_path / "b.csv", ROWS)
    assert (tmp_path / "b.csv").read_text().startswith("name,x\n") and TABLE.metadata(tmp_path / "b.csv") is None


def test_a_parquet_table_reads_back_to_the_same_bits(tmp_path):
    path = TABLE.write(tmp_path / "a.PQ", ROWS, SETUP)  # the suffix in any case
    back = TABLE.read(path)
    assert back["name"] == ["v1", "v,2"] and back["x"][0] == 0.1 + 0.2 and math.isnan(back["x"][1])
    assert TABLE.metadata(path) == SETUP


def test_formats_by_suffix():
    assert TABLE.format("a.parquet") == TABLE.format("b.pq") == "parquet"
    assert TABLE.format("c.CSV") == "csv"
    with pytest.raises(OutputError, match="unknown suffix: give a .parquet, .pq, .csv file"):
        TABLE.format("d.txt")


def test_a_bad_csv_is_named_by_line_and_column(tmp_path):
    short = tmp_path / "short.csv"
    short.write_text("name,x\nv1,1.0\nv2\n")
    with pytest.raises(FileRowError, match="line 3.*1 cells, the header has 2"):
        TABLE.read(short)
    words = tmp_path / "words.csv"
    words.write_text("name,x\nv1,one\n")
    with pytest.raises(FileRowError, match="line 2.*column 'x'.*expected a number, got 'one'"):
        TABLE.read(words)
    empty = tmp_path / "empty.csv"
    empty.write_text("# hipsim sweep: {}\n")
    with pytest.raises(FileRowError, match="empty: no header"):
        TABLE.read(empty)


def test_resuming_keeps_the_rows_of_the_same_set_up_only(tmp_path):
    path = tmp_path / "a.csv"
    names = ["name", "x"]
    prints = SETUP["fingerprints"]
    assert TABLE.resume(path, names, prints) == {"name": [], "x": []}  # no file yet
    TABLE.write(path, ROWS, SETUP)
    assert TABLE.resume(path, names, prints)["name"] == ["v1", "v,2"]
    assert TABLE.resume(path, names, prints, restart=True) == {"name": [], "x": []}
    with pytest.raises(OutputError, match="holds other columns"):
        TABLE.resume(path, ["name", "y"], prints)
    other = {**prints, "setup": "s2", "drive": "d2"}
    with pytest.raises(OutputError, match=r"another set-up \(--drive differs\)"):
        TABLE.resume(path, names, other, parts={"drive": "--drive"})
    with pytest.raises(OutputError, match=r"another set-up \(drive, trajectory differ\)"):
        TABLE.resume(path, names, {**other, "trajectory": "t2"})
    TABLE.write(path, ROWS)  # no description: another program's file
    with pytest.raises(OutputError, match="records no set-up"):
        TABLE.resume(path, names, prints)


def test_an_output_is_checked_before_the_run(tmp_path):
    assert TABLE.check_out(tmp_path / "out.csv") == tmp_path / "out.csv"
    with pytest.raises(OutputError, match="unknown suffix"):
        TABLE.check_out(tmp_path)  # the suffix is checked first
    (tmp_path / "rows.csv").mkdir()
    with pytest.raises(OutputError, match="is a folder"):
        TABLE.check_out(tmp_path / "rows.csv")
    with pytest.raises(OutputError, match="folder '.*missing' does not exist"):
        TABLE.check_out(tmp_path / "missing" / "out.csv")

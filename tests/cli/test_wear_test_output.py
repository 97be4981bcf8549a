"""The wear test's output helpers (hipsim.cli.wear_test_output): which platform a station is, a confidence interval
in words. The outputs through the command line: cli/test_wear_test.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hipsim.cli.main import main
from hipsim.cli.wear_test_output import _ci, _station_number, motion_errors
from hipsim.exceptions import FileRowError
from hipsim.tables import parquet_table

ERRORS = ("err_alpha_1_deg", "err_beta_1_deg", "err_gamma_1_deg")


def test_a_stations_platform_from_its_motion_or_its_name():
    args = SimpleNamespace(station=["A=run/stations.csv:2", "B=snapshots", "C=x.csv:3"])
    assert _station_number(args, "A") == 2  # the platform its motion file names
    assert _station_number(args, "B") is None  # snapshots name no platform
    assert _station_number(args, "C") is None  # 3 is no platform
    assert _station_number(SimpleNamespace(station=None), "1") == 1  # a station named 1 or 2 is that platform
    assert _station_number(SimpleNamespace(station=["1=a.csv:2"]), "1") == 2  # its motion wins over its name


def test_a_confidence_interval_or_a_dash():
    assert _ci((1.23456, 2.5)) == "[1.235, 2.5]"
    assert _ci((math.nan, 2.0)) == "–" and _ci((0.0, math.inf)) == "–"


def _stations_csv(path, errors: bool = True, bad: str | None = None):
    """One cycle of a platform's motion at 100 Hz (smooth, made here), with its error columns when ``errors``;
    ``bad`` is written in err_gamma_1_deg's cell at t = 0.4 s (line 42)."""
    header = "t_s,alpha_1_deg,beta_1_deg,gamma_1_deg,Fe_N" + (
        ",err_alpha_1_deg,err_beta_1_deg,err_gamma_1_deg" * errors
    )
    rows = [header]
    for k in range(101):
        s, c = math.sin(2 * math.pi * k / 100), math.cos(2 * math.pi * k / 100)
        gamma = bad if bad is not None and k == 40 else "0.03"
        rows.append(f"{k / 100},{25 * s},{7 * c},{10 * s},{1500 + 1000 * s}" + (f",0.01,-0.02,{gamma}" * errors))
    path.write_text("\n".join(rows) + "\n")
    return path


def test_a_stations_outputs_error_columns_or_not_known(tmp_path):
    table = motion_errors(str(_stations_csv(tmp_path / "st.csv")), ERRORS)
    assert table is not None and table.shape == (101, 3)
    assert np.all(table == [0.01, -0.02, 0.03])
    assert motion_errors(str(_stations_csv(tmp_path / "plain.csv", errors=False)), ERRORS) is None  # not known


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda text: text.replace(",0.03\n", ",nan\n", 1), ["line 2", "column 'err_gamma_1_deg'", "finite"]),
        (lambda text: text.replace("err_gamma_1_deg", "err_gamma_2_deg"), ["line 1", "no column err_gamma_1_deg"]),
    ],
)
def test_a_malformed_error_column_is_refused_by_file_and_place(tmp_path, edit, words):
    path = _stations_csv(tmp_path / "st.csv")
    path.write_text(edit(path.read_text()))
    with pytest.raises(FileRowError) as refused:
        motion_errors(str(path), ERRORS)
    assert str(refused.value).startswith(str(path)) and all(word in str(refused.value) for word in words)


def test_a_parquet_stations_outputs_error_columns(tmp_path):
    import pyarrow.parquet as pq

    good = {"t_s": np.arange(3.0), "err_alpha_1_deg": np.full(3, 0.1), "err_beta_1_deg": np.zeros(3)}
    pq.write_table(parquet_table({**good, "err_gamma_1_deg": np.array([0.0, -0.2, 0.3])}), tmp_path / "a.parquet")
    table = motion_errors(str(tmp_path / "a.parquet"), ERRORS)
    assert table is not None and table[:, 2].tolist() == [0.0, -0.2, 0.3]
    pq.write_table(parquet_table({**good, "err_gamma_1_deg": np.array([0.0, np.inf, 0.3])}), tmp_path / "b.parquet")
    with pytest.raises(FileRowError, match="column 'err_gamma_1_deg': expected a finite number, got inf at row 2"):
        motion_errors(str(tmp_path / "b.parquet"), ERRORS)
    pq.write_table(parquet_table(good), tmp_path / "c.parquet")
    with pytest.raises(FileRowError, match="no column err_gamma_1_deg beside err_alpha_1_deg, err_beta_1_deg"):
        motion_errors(str(tmp_path / "c.parquet"), ERRORS)
    pq.write_table(parquet_table({"t_s": np.arange(3.0)}), tmp_path / "d.parquet")
    assert motion_errors(str(tmp_path / "d.parquet"), ERRORS) is None


def test_a_malformed_stations_output_is_refused_in_one_line_nothing_written(tmp_path, capsys, monkeypatch):
    """``hipsim wear --weighings --station 1=FILE:1`` with a cell of FILE's error columns not a number: one line
    naming the file, line and column, exit 2, no table of stops (it was read as "motion error not known")."""
    monkeypatch.chdir(tmp_path)
    _stations_csv(tmp_path / "st.csv", bad="x")
    (tmp_path / "w.csv").write_text(
        "cycle,station,mass_mg\n0,1,30000\n0,soak,29000\n500000,1,29990\n500000,soak,29000.5\n"
        "1000000,1,29981\n1000000,soak,29000.7\n"
    )
    status = main(["wear", "--cup-grid", "12x24", "--weighings", "w.csv", "--station", "1=st.csv:1", "--out", "t.csv"])
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "st.csv, line 42, column 'err_gamma_1_deg': expected a number, got 'x'" in err
    assert sorted(path.name for path in tmp_path.iterdir()) == ["st.csv", "w.csv"]

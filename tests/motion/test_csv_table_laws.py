"""Laws of the CSV reader (hipsim.motion.csv_table) and its header scan (hipsim.motion.headers), on tiny tables.

Each table is written here as text, eight rows at 100 Hz with angles and loads that are whole numbers, so
every value read back, every message and every place it names is known by hand.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from hipsim import TrajectoryError
from hipsim.motion.build import SampledMotion, TrajectoryWarning
from hipsim.motion.columns import Column, ColumnMap
from hipsim.motion.csv_table import _read_csv_table, load_trajectory_csv
from hipsim.motion.headers import _column_indices, suggest_mapping, table_columns
from hipsim.motion.load_file import LoadCurve

N = 8
T = [k / 100 for k in range(N)]
ALPHA = [10 + k for k in range(N)]  # [deg]
BETA = [2 * k for k in range(N)]
GAMMA = [-k for k in range(N)]
LOAD = [1000 + 100 * k for k in range(N)]  # [N]
HEADER = "t_s,alpha_deg,beta_deg,gamma_deg,Fe_N"


def rows(separator=",", decimal=".", load=True) -> list[str]:
    out = []
    for k in range(N):
        cells = [f"{T[k]:.2f}", f"{ALPHA[k]}.5", f"{BETA[k]}", f"{GAMMA[k]}"] + ([f"{LOAD[k]}"] if load else [])
        out.append(separator.join(cell.replace(".", decimal) for cell in cells))
    return out


def write(path, lines) -> str:
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def with_cell(lines, index, column, value, separator=","):
    out = list(lines)
    cells = out[index].split(separator)
    cells[column] = value
    out[index] = separator.join(cells)
    return out


def error_of(call) -> TrajectoryError:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrajectoryWarning)
        with pytest.raises(TrajectoryError) as info:
            call()
    return info.value


def quiet(call):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TrajectoryWarning)
        return call()


def expected_q():
    return np.radians(np.column_stack([np.array(ALPHA) + 0.5, BETA, GAMMA]).astype(float))


# --------------------------------------------------------------------------- the table as read


def test_the_table_holds_the_files_numbers_lines_and_time_resolution(tmp_path):
    path = write(tmp_path / "a.csv", ["# a comment", HEADER, "", *rows()])
    table = _read_csv_table(path, path, None, None)
    assert table.source == path
    np.testing.assert_array_equal(table.lines, [2 + 2 + k for k in range(N)])  # comment, header, a blank line
    np.testing.assert_array_equal(table.time, T)
    np.testing.assert_array_equal(table.angles, np.column_stack([np.array(ALPHA) + 0.5, BETA, GAMMA]))
    np.testing.assert_array_equal(table.load, LOAD)
    assert table.time_quantum == pytest.approx(0.01, rel=1e-15)
    assert table.columns.time == Column("t_s", "s")
    assert [c.name for c in table.columns.angles] == ["alpha_deg", "beta_deg", "gamma_deg"]
    assert table.columns.load == Column("Fe_N", "N")


def test_the_time_resolution_is_the_finest_printed_and_none_for_an_exponent(tmp_path):
    lines = [HEADER, *rows()]
    lines[3] = lines[3].replace("0.02,", "0.020,", 1)
    path = write(tmp_path / "a.csv", lines)
    assert _read_csv_table(path, path, None, None).time_quantum == pytest.approx(0.001, rel=1e-15)
    lines = [HEADER, *rows()]
    lines[3] = lines[3].replace("0.02,", "2e-2,", 1)
    path = write(tmp_path / "b.csv", lines)
    assert _read_csv_table(path, path, None, None).time_quantum == 0.0
    whole = [HEADER] + [f"{k},{ALPHA[k]},{BETA[k]},{GAMMA[k]},{LOAD[k]}" for k in range(N)]
    path = write(tmp_path / "c.csv", whole)
    assert _read_csv_table(path, path, None, None).time_quantum == 1.0


def test_a_mapped_table_reads_only_its_columns_and_zero_angles(tmp_path):
    lines = ["Note;Time;FE;Force"] + [f"x{k};{T[k]};{ALPHA[k]};{LOAD[k]}" for k in range(N)]
    path = write(tmp_path / "a.csv", lines)
    mapping = ColumnMap(
        Column("Time", "s"), (Column("FE", "deg"), Column("zero"), Column("zero")), False, Column("Force", "N")
    )
    table = _read_csv_table(path, path, mapping, None)
    np.testing.assert_array_equal(table.angles, np.column_stack([ALPHA, np.zeros(N), np.zeros(N)]))
    np.testing.assert_array_equal(table.time, T)
    np.testing.assert_array_equal(table.load, LOAD)
    assert table.columns is mapping
    # Without a load column the table has none.
    lines = ["Time;FE;AA;IE"] + [f"{T[k]};{ALPHA[k]};{BETA[k]};{GAMMA[k]}" for k in range(N)]
    path = write(tmp_path / "b.csv", lines)
    mapping = ColumnMap(Column("Time", "s"), (Column("FE"), Column("AA"), Column("IE")))
    table = _read_csv_table(path, path, mapping, None)
    assert table.load is None
    np.testing.assert_array_equal(table.angles[:, 2], GAMMA)


# --------------------------------------------------------------------------- Excel's sep= line


@pytest.mark.parametrize(
    ("declared", "separator"), [("sep=;", ";"), ("SEP=\\t", "\t"), ("Sep=\t", "\t"), ("sep=,", ",")]
)
def test_excels_separator_line_names_the_separator(tmp_path, declared, separator):
    decimal = "," if separator != "," else "."
    path = write(tmp_path / "x.csv", [declared, HEADER.replace(",", separator), *rows(separator, decimal)])
    trajectory = load_trajectory_csv(path)
    np.testing.assert_allclose(trajectory.q, expected_q(), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.Fe, LOAD)
    np.testing.assert_array_equal(trajectory.lines, [3 + k for k in range(N)])


def test_the_declared_separator_wins_over_the_guess(tmp_path):
    # Declared ';' with a header that a comma would split: read by ';' the header is one name.
    path = write(tmp_path / "x.csv", ["sep=;", HEADER, *rows()])
    error = error_of(lambda: load_trajectory_csv(path))
    assert error.line == 2
    assert "no time column 't_s'" in str(error)


def test_a_file_of_only_the_separator_line_or_nothing_is_named(tmp_path):
    path = write(tmp_path / "x.csv", ["sep=;"])
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}: the file holds only Excel's 'sep=' line"
    path = write(tmp_path / "y.csv", ["# only a comment"])
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}: the file is empty"


def test_a_sep_line_that_names_no_separator_is_a_header(tmp_path):
    path = write(tmp_path / "x.csv", ["sep=|", HEADER, *rows()])
    error = error_of(lambda: load_trajectory_csv(path))
    assert error.line == 1


# --------------------------------------------------------------------------- cells


def test_too_few_rows_ragged_rows_and_bad_cells_are_named_exactly(tmp_path):
    path = write(tmp_path / "a.csv", [HEADER, *rows()[:5]])
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}: 5 samples; at least 6 are needed"
    lines = [HEADER, *rows()]
    lines[4] += ",7"
    path = write(tmp_path / "b.csv", lines)
    assert str(error_of(lambda: load_trajectory_csv(path))) == (
        f"{path}, line 5: 6 cells, the header has 5 (decimal commas? a comma-separated file needs decimal points)"
    )
    lines = [HEADER.replace(",", ";"), *rows(";", ",")]
    lines[4] += ";7"
    path = write(tmp_path / "c.csv", lines)
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 5: 6 cells, the header has 5"
    lines = [HEADER, *rows()]
    lines[3] = lines[3].rsplit(",", 1)[0]
    path = write(tmp_path / "d.csv", lines)
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 4: 4 cells, the header has 5"
    lines = with_cell([HEADER, *rows()], 6, 3, " x ")
    path = write(tmp_path / "e.csv", lines)
    assert (
        str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 7, column 'gamma_deg': 'x' is not a number"
    )
    lines = with_cell([HEADER, *rows()], 2, 3, " inf ")
    path = write(tmp_path / "f.csv", lines)
    assert (
        str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 3, column 'gamma_deg': 'inf' is not finite"
    )


def test_cells_of_unmapped_columns_are_not_read(tmp_path):
    lines = ["Note,Time,FE,AA,IE"] + [f"n/a,{T[k]},{ALPHA[k]},{BETA[k]},{GAMMA[k]}" for k in range(N)]
    path = write(tmp_path / "a.csv", lines)
    trajectory = quiet(lambda: load_trajectory_csv(path, columns="time=Time,alpha=FE,beta=AA,gamma=IE"))
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(ALPHA), rtol=0, atol=1e-15)


# --------------------------------------------------------------------------- the builder's arguments


def test_each_keyword_reaches_the_builder(tmp_path):
    path = write(tmp_path / "a.csv", [HEADER, *rows()])
    base = load_trajectory_csv(path)
    np.testing.assert_array_equal(base.t, T)
    assert not base.periodic
    # frequency 2 Hz: the eight samples (one step added: the file does not close) last half a second.
    fast = quiet(lambda: load_trajectory_csv(path, frequency=2.0))
    np.testing.assert_allclose(fast.t, np.arange(N) / 16.0, rtol=0, atol=1e-15)
    slow = quiet(lambda: load_trajectory_csv(path, period=4.0))
    np.testing.assert_allclose(slow.t, np.arange(N) * 0.5, rtol=0, atol=1e-15)
    resampled = load_trajectory_csv(path, resample=200.0)
    np.testing.assert_allclose(resampled.t, np.arange(15) / 200.0, rtol=0, atol=1e-15)
    lazy = load_trajectory_csv(path, lazy=True)
    assert isinstance(lazy, SampledMotion)
    np.testing.assert_array_equal(lazy.trajectory().q, base.q)
    filtered = load_trajectory_csv(path, cutoff=10.0)
    assert np.abs(filtered.q - base.q).max() > 1e-4
    error = error_of(lambda: load_trajectory_csv(path, periodic=True))
    assert "periodic was asked for" in str(error)
    error = error_of(lambda: load_trajectory_csv(path, body_weight=700.0))
    assert str(error) == f"{path}, column 'Fe_N': a body weight was given, but the load is in N"
    curve = LoadCurve(np.array([-1.0, 1.0]), np.array([0.0, 2000.0]), np.array([2, 3]), "l.csv", "F")
    without = write(tmp_path / "b.csv", [HEADER.rsplit(",", 1)[0], *rows(load=False)])
    loaded = load_trajectory_csv(without, load_curve=curve)
    np.testing.assert_allclose(loaded.Fe, 1000.0 * (np.array(T) + 1.0), rtol=1e-15)


def test_a_load_column_and_a_percent_body_weight(tmp_path):
    lines = ["t_s,alpha_deg,beta_deg,gamma_deg,Fz"] + rows()
    path = write(tmp_path / "a.csv", lines)
    trajectory = load_trajectory_csv(path, load_column="Fz", body_weight=50.0)
    np.testing.assert_allclose(trajectory.Fe, np.array(LOAD) / 2.0, rtol=1e-15)
    path = write(
        tmp_path / "b.csv", ["t_s,alpha_deg,beta_deg,gamma_deg,Fz"] + [r.rsplit(",", 1)[0] + ",-1" for r in rows()]
    )
    trajectory = load_trajectory_csv(path, load_column="-Fz:kN")
    np.testing.assert_array_equal(trajectory.Fe, np.full(N, 1000.0))


# --------------------------------------------------------------------------- hipsim's own header


def test_a_radian_header_is_read_in_radians(tmp_path):
    lines = ["t_s,alpha_rad,beta_rad,gamma_rad"] + [f"{T[k]},{0.1 * k},{0.05 * k},{-0.02 * k}" for k in range(N)]
    path = write(tmp_path / "a.csv", lines)
    trajectory = quiet(lambda: load_trajectory_csv(path))
    np.testing.assert_allclose(trajectory.q[:, 0], 0.1 * np.arange(N), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory.Fe, np.zeros(N))


@pytest.mark.parametrize(
    ("header", "problem", "column"),
    [
        ("t_s,alpha_deg,beta_deg,alpha_deg,Fe_N", "column 'alpha_deg' appears twice", "alpha_deg"),
        ("time,alpha_deg,beta_deg,gamma_deg,Fe_N", "no time column 't_s'; the header has", None),
        (
            "t_s,alpha_deg,beta_rad,gamma_deg,Fe_N",
            "expected angle columns alpha_deg, beta_deg, gamma_deg (or all three in _rad), not a mix of _deg and _rad;",
            None,
        ),
        (
            "t_s,alpha,beta,gamma,Fe_N",
            "expected angle columns alpha_deg, beta_deg, gamma_deg (or all three in _rad); the header has",
            None,
        ),
        ("t_s,alpha_rad,beta_rad,gamma,Fe_N", "missing angle column 'gamma_rad'; the header has", None),
        (
            "t_s,alpha_deg,beta_deg,gamma_deg,Fe_kN",
            "unknown column (expected t_s, alpha_deg, beta_deg, gamma_deg, optionally Fe_N; map the columns to read any others)",
            "Fe_kN",
        ),
    ],
)
def test_hipsims_own_header_is_checked_strictly(tmp_path, header, problem, column):
    path = write(tmp_path / "a.csv", [header, *rows()])
    error = error_of(lambda: load_trajectory_csv(path))
    place = f"{path}, line 1" + (f", column '{column}'" if column else "")
    assert str(error).startswith(f"{place}: {problem}"), str(error)
    assert error.line == 1 and error.column == column


def test_the_mismatch_lists_the_header_and_suggests_a_mapping():
    header = ["time", "alpha_deg", "beta_deg", "gamma_deg"]
    with pytest.raises(TrajectoryError) as info:
        table_columns(header, None, None, "f.csv", 3)
    assert str(info.value) == (
        "f.csv, line 3: no time column 't_s'; the header has 'time', 'alpha_deg', 'beta_deg', 'gamma_deg': "
        "map the columns to read, e.g. time=time,alpha=alpha_deg,beta=beta_deg,gamma=gamma_deg"
    )


def test_a_load_column_beside_fe_n_is_refused_and_else_replaces_it():
    header = ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N", "Fz"]
    with pytest.raises(TrajectoryError) as info:
        table_columns(header, None, Column("Fz", "N"), "f.csv", 2)
    assert str(info.value) == "f.csv, line 2: both 'Fe_N' and the load column 'Fz' are given: which is the load?"
    mapping, index = table_columns(
        ["t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fz"], None, Column("Fz", "kN"), "f", 1
    )
    assert mapping.load == Column("Fz", "kN")
    assert index == {"time": 0, "alpha": 1, "beta": 2, "gamma": 3, "load": 4}
    mapping, index = table_columns(["gamma_rad", "t_s", "alpha_rad", "beta_rad"], None, None, "f", 1)
    assert mapping == ColumnMap(
        Column("t_s", "s"), (Column("alpha_rad", "rad"), Column("beta_rad", "rad"), Column("gamma_rad", "rad"))
    )
    assert index == {"time": 1, "alpha": 2, "beta": 3, "gamma": 0}


# --------------------------------------------------------------------------- a mapping's columns


def test_a_mapped_column_is_found_exactly_else_ignoring_case_and_spaces():
    mapping = ColumnMap(Column("Time"), (Column("Hip FE"), Column("AA"), Column("zero")), False, Column("F z"))
    header = ["time", "hipfe", "Hip FE", "aa", "F Z", "x"]
    assert _column_indices(header, mapping, "f", 1) == {"time": 0, "alpha": 2, "beta": 3, "load": 4}
    with pytest.raises(TrajectoryError) as info:
        _column_indices(["TIME", "time", "Hip FE", "AA"], mapping, "f", 4)
    assert str(info.value) == "f, line 4, column 'Time': column 'Time' appears 2 times"
    assert info.value.column == "Time"


def test_a_missing_mapped_column_names_the_header_twelve_at_most():
    mapping = ColumnMap(Column("Time"), (Column("FE"), Column("AA"), Column("IE")))
    header = ["Time", "FE", "AA"] + [f"c{k}" for k in range(10)]
    with pytest.raises(TrajectoryError) as info:
        _column_indices(header, mapping, "f", 2)
    shown = ", ".join(f"'{name}'" for name in header[:12])
    assert str(info.value) == f"f, line 2: no column 'IE' (mapped to gamma); the header has {shown} and 1 more"
    with pytest.raises(TrajectoryError) as info:
        _column_indices(header[:12], mapping, "f", 2)
    assert str(info.value) == f"f, line 2: no column 'IE' (mapped to gamma); the header has {shown}"


# --------------------------------------------------------------------------- a suggested mapping


@pytest.mark.parametrize(
    ("header", "suggestion"),
    [
        (["Time", "FE", "AA", "IE", "Fz"], "time=Time,alpha=FE,beta=AA,gamma=IE,load=Fz"),
        (["t", "alpha", "beta", "gamma"], "time=t,alpha=alpha,beta=beta,gamma=gamma"),
        (["x", "y"], "time=<column>,alpha=<column>,beta=<column>,gamma=<column>"),
        (
            ["Zeit [ms]", "Flexion", "Abduction", "Rotation", "Kraft [kN]"],
            "time=Zeit [ms]:ms,alpha=Flexion,beta=Abduction,gamma=Rotation,load=Kraft [kN]:kN",
        ),
        (
            ["Gait cycle %", "Sagittal", "Frontal", "Transverse", "F"],
            "time=Gait cycle %:%,alpha=Sagittal,beta=Frontal,gamma=Transverse,load=F",
        ),
        (
            ["% cycle", "flex (rad)", "add (rad)", "int/ext rot (rad)"],
            "time=% cycle:%,alpha=flex (rad):rad,beta=add (rad):rad,gamma=int/ext rot (rad):rad",
        ),
        (["time [s]", "fe", "aa", "ie", "Fz [%BW]"], "time=time [s],alpha=fe,beta=aa,gamma=ie,load=Fz [%BW]:%BW"),
        (
            ["time", "hip flexion", "hip adduction", "hip rotation"],
            "time=time,flexion=hip flexion,adduction=hip adduction,rotation=hip rotation",
        ),
        (["time", "hip flexion", "AA", "hip rotation"], "time=time,alpha=hip flexion,beta=AA,gamma=hip rotation"),
        (["T", " Flex ", "coronal", "transv", "load"], "time=T,alpha= Flex ,beta=coronal,gamma=transv,load=load"),
        (["t (s)", "rot", "Fres"], "time=t (s),alpha=<column>,beta=<column>,gamma=rot,load=Fres"),
        (["Percent", "f (N)"], "time=Percent,alpha=<column>,beta=<column>,gamma=<column>,load=f (N)"),
        (["time", "FE", "AA", "IE", "Fz_kN"], "time=time,alpha=FE,beta=AA,gamma=IE,load=Fz_kN:kN"),
        (["Gang [%]", "FE", "AA", "IE"], "time=Gang [%]:%,alpha=FE,beta=AA,gamma=IE"),
        (["% Gang", "FE", "AA", "IE"], "time=% Gang:%,alpha=FE,beta=AA,gamma=IE"),
        # A name that starts with the initials wins over one that holds them later, whatever the order.
        (["t", "hip fe", "fe", "hip aa", "aa", "hip ie", "ie"], "time=t,alpha=fe,beta=aa,gamma=ie"),
        (["t", "hip fe", "hip aa", "hip ie"], "time=t,flexion=hip fe,adduction=hip aa,rotation=hip ie"),
        (["t", "FE", "AA", "int ext", "Force"], "time=t,alpha=FE,beta=AA,gamma=int ext,load=Force"),
        (["t", "flex rot", "x"], "time=t,alpha=flex rot,beta=<column>,gamma=<column>"),  # one column, one quantity
        (["t", "FE", "AA", "IE", "f_res"], "time=t,alpha=FE,beta=AA,gamma=IE,load=f_res"),
        (["t", "FE", "AA", "IE", "F [kN]"], "time=t,alpha=FE,beta=AA,gamma=IE,load=F [kN]:kN"),
    ],
)
def test_the_suggested_mapping_by_hand(header, suggestion):
    assert suggest_mapping(header) == suggestion


def test_a_time_in_percent_is_suggested_only_without_a_bracketed_unit():
    assert suggest_mapping(["Cycle [%]", "FE", "AA", "IE"]) == "time=Cycle [%]:%,alpha=FE,beta=AA,gamma=IE"
    assert suggest_mapping(["time (s) %", "FE", "AA", "IE"]) == "time=time (s) %,alpha=FE,beta=AA,gamma=IE"


def test_hip_angles_are_turned_into_the_machines_by_the_suggested_mapping(tmp_path):
    lines = ["time,hip flexion,hip adduction,hip rotation"] + [f"{T[k]},{ALPHA[k]},0,0" for k in range(N)]
    path = write(tmp_path / "a.csv", lines)
    trajectory = quiet(lambda: load_trajectory_csv(path, columns=suggest_mapping(lines[0].split(","))))
    # Flexion alone is a rotation about Z: α = flexion (hipsim.motion.hip_angles).
    np.testing.assert_allclose(trajectory.q[:, 0], np.radians(ALPHA), rtol=0, atol=1e-12)
    assert math.isclose(float(np.abs(trajectory.q[:, 1:]).max()), 0.0, abs_tol=1e-12)


# --------------------------------------------------------------------------- survivors of the first run


def test_the_source_names_a_load_given_twice_and_a_missing_file(tmp_path):
    path = write(tmp_path / "a.csv", [HEADER, *rows()])
    mapping = "time=t_s,alpha=alpha_deg,beta=beta_deg,gamma=gamma_deg,load=Fe_N"
    error = error_of(lambda: load_trajectory_csv(path, columns=mapping, load_column="Fe_N"))
    assert str(error) == f"{path}: the load column is named twice (in the column mapping and on its own)"
    missing = str(tmp_path / "none.csv")
    assert str(error_of(lambda: load_trajectory_csv(missing))) == f"{missing}: no such trajectory file"


def test_the_separator_is_judged_on_the_header_and_the_first_row(tmp_path):
    # By ';' the header has two cells and the rows one: the comma, which splits both into five, wins.
    mapping = "time=t_s,alpha=alpha_deg,beta=beta_deg,gamma=gamma_deg"
    header = "t_s,alpha_deg,beta_deg,gamma_deg,note; remark"
    path = write(tmp_path / "a.csv", [header] + [r.rsplit(",", 1)[0] + ",x" for r in rows()])
    trajectory = quiet(lambda: load_trajectory_csv(path, columns=mapping))
    np.testing.assert_allclose(trajectory.q, expected_q(), rtol=0, atol=1e-15)
    # So with a single row too: the header is read by commas, and the row count is what is wrong.
    path = write(tmp_path / "b.csv", [header, rows()[0].rsplit(",", 1)[0] + ",x"])
    assert (
        str(error_of(lambda: load_trajectory_csv(path, columns=mapping))) == f"{path}: 1 samples; at least 6 are needed"
    )


def test_a_quoted_decimal_comma_in_a_comma_separated_file_is_not_a_number(tmp_path):
    lines = with_cell([HEADER, *rows()], 3, 2, '"2,5"')
    path = write(tmp_path / "a.csv", lines)
    assert (
        str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 4, column 'beta_deg': '2,5' is not a number"
    )


def test_a_line_that_cannot_be_split_is_named_at_its_line(tmp_path, monkeypatch):
    # The csv module refuses only a line end inside an unquoted cell, which reading the text turns into a
    # line break; the reader still names such a refusal at its line (here a stand-in splitter refuses "?").
    import hipsim.motion.csv_table as csv_table

    def cells(line, separator, width=None):
        if "?" in line:
            raise ValueError("cannot split the line into cells (?)")
        return line.split(separator)

    def detect_separator(header, first_row):
        if "?" in header:
            raise ValueError("cannot split the header (?)")
        return ","

    monkeypatch.setattr(csv_table, "cells", cells)
    monkeypatch.setattr(csv_table, "detect_separator", detect_separator)
    path = write(tmp_path / "a.csv", ["# x", HEADER + "?", *rows()])
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 2: cannot split the header (?)"
    path = write(tmp_path / "b.csv", ["sep=,", HEADER + ",?", *rows()])
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 2: cannot split the line into cells (?)"
    lines = [HEADER, *rows()]
    lines[5] += "?"
    path = write(tmp_path / "c.csv", lines)
    assert str(error_of(lambda: load_trajectory_csv(path))) == f"{path}, line 6: cannot split the line into cells (?)"


def test_a_mapped_name_is_found_without_its_spaces_and_case():
    mapping = ColumnMap(Column("Time"), (Column("HipFE"), Column("hip aa"), Column("zero")))
    assert _column_indices(["TIME", "Hip  FE", "HIPAA"], mapping, "f", 1) == {"time": 0, "alpha": 1, "beta": 2}


def test_a_suggested_hip_chain_keeps_names_with_an_equals_sign_and_the_load():
    header = ["time", "hip flex=1", "hip add", "hip rot", "Force"]
    assert suggest_mapping(header) == "time=time,flexion=hip flex=1,adduction=hip add,rotation=hip rot,load=Force"


def test_a_spreadsheets_trailing_separators_are_dropped(tmp_path):
    lines = [HEADER + ",,", *rows()]
    lines[3] += ",,"
    path = write(tmp_path / "a.csv", lines)
    trajectory = load_trajectory_csv(path)
    np.testing.assert_allclose(trajectory.q, expected_q(), rtol=0, atol=1e-15)

"""hipsim.rig.logs.reader pinned on tiny logs written here line by line: each column's unit, which columns count, the
checks' bounds (both sides), every message whole with its file, line and column, windows of lines (fast and line by
line), blocks of any size, the file's SHA-256 and size, and the times from the sample index (``rate``).

Each expected value is worked out by hand from the text written (e.g. 25.5 N·mm is 0.0255 N·m), not read back from the
code.
"""

from __future__ import annotations

import gc
import hashlib
import math
import warnings

import numpy as np
import pytest
from support import given

from hipsim.exceptions import ArgumentError, TrajectoryError
from hipsim.motion.build import TrajectoryWarning
from hipsim.rig.logs import text_rows
from hipsim.rig.logs.reader import (
    CURRENT_COLUMNS,
    HEIGHT_COLUMNS,
    MAX_HEIGHT_MM,
    MAX_TORQUE_NMM,
    TORQUE_COLUMNS,
    RigLog,
    RigLogFile,
    read_rig_log,
)

HEADER = "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg"


def row(k: int, sep: str = ",", **change) -> str:
    """Sample k of the plain log (100 Hz): load 1000 + k N, torques 100 + k, −50 − k, 25.5 N·mm, angles 10, −2, 3°."""
    cells = {
        "t": f"{k / 100:.2f}",
        "Fe": f"{1000 + k}",
        "tau1": f"{100 + k}",
        "tau2": f"{-50 - k}",
        "tau3": "25.5",
        "a": "10",
        "b": "-2",
        "g": "3",
    }
    cells.update(change)
    return sep.join(cells.values())


def rows(n: int, sep: str = ",") -> list[str]:
    return [row(k, sep) for k in range(n)]


def write(tmp_path, lines, name: str = "log.csv"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def refused(path, message: str, **options) -> TrajectoryError:
    """The reader's one error for ``path``, its message whole (the file's path in front)."""
    with pytest.raises(TrajectoryError) as error:
        RigLogFile(path, **options)
    assert str(error.value) == (f"{path}{message}" if message.startswith(":") else f"{path}, {message}")
    return error.value


def test_the_column_names():
    assert TORQUE_COLUMNS == ("tau_1_Nmm", "tau_2_Nmm", "tau_3_Nmm")
    assert CURRENT_COLUMNS == ("current_1_A", "current_2_A", "current_3_A")
    assert HEIGHT_COLUMNS == ("L_11_mm", "L_12_mm", "L_13_mm")
    assert (MAX_TORQUE_NMM, MAX_HEIGHT_MM) == (1e9, 1e5)


# --- Columns and their units ---------------------------------------------------------------------


def test_every_column_in_si_with_angles_and_heights(tmp_path):
    header = "temp_C,t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg,L_11_mm,L_12_mm,L_13_mm,note"
    lines = [header] + [
        f"21,{k / 100:.2f},{1000 + k},{100 + k},-50,25.5,90,-45,180,600,610.5,{590 + k},7" for k in range(6)
    ]
    scanned = RigLogFile(write(tmp_path, lines))
    log = scanned.read()
    assert len(scanned) == len(log) == 6 and scanned.has_heights and scanned.torque_constant is None
    np.testing.assert_array_equal(log.t, [0.0, 0.01, 0.02, 0.03, 0.04, 0.05])
    np.testing.assert_array_equal(log.Fe, [1000.0, 1001.0, 1002.0, 1003.0, 1004.0, 1005.0])
    np.testing.assert_allclose(log.tau[3], [0.103, -0.05, 0.0255], rtol=1e-15)
    np.testing.assert_allclose(given(log.angles)[5], [math.pi / 2, -math.pi / 4, math.pi], rtol=1e-15)
    np.testing.assert_allclose(given(log.heights)[5], [0.6, 0.6105, 0.595], rtol=1e-15)
    np.testing.assert_array_equal(log.lines, [2, 3, 4, 5, 6, 7])
    assert (log.torque_from, log.ignored, log.angle_unit, log.source) == (
        "torques",
        ("temp_C", "note"),
        "deg",
        str(tmp_path / "log.csv"),
    )
    assert log.rate == pytest.approx(100.0, rel=1e-12) and scanned.rate == log.rate


def test_heights_alone_and_angles_in_radians(tmp_path):
    header = "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,L_11_mm,L_12_mm,L_13_mm"
    lines = [header] + [f"{k / 100:.2f},800,1,2,3,600,{610 + k},590" for k in range(4)]
    log = read_rig_log(write(tmp_path, lines))
    assert log.angles is None and log.angle_unit is None and log.ignored == ()
    np.testing.assert_allclose(given(log.heights)[:, 1], [0.61, 0.611, 0.612, 0.613], rtol=1e-15)
    np.testing.assert_allclose(given(log.heights)[:, 0], 0.6, rtol=1e-15)
    header = "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_rad,beta_rad,gamma_rad"
    lines = [header] + [f"{k / 100:.2f},800,1,2,3,0.5,-1.5,3.14159" for k in range(4)]
    scanned = RigLogFile(write(tmp_path, lines, "rad.csv"))
    log = scanned.read()
    assert log.heights is None and log.angle_unit == "rad" and not scanned.has_heights and log.ignored == ()
    np.testing.assert_array_equal(given(log.angles)[2], [0.5, -1.5, 3.14159])  # as written: no conversion


def test_currents_times_the_torque_constant(tmp_path):
    header = "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg"
    path = write(tmp_path, [header] + [f"{k / 100:.2f},800,1,-2,0.5,1,2,3" for k in range(4)])
    scanned = RigLogFile(path, torque_constant=0.25)
    np.testing.assert_array_equal(scanned.read().tau[1], [0.25, -0.5, 0.125])
    assert (scanned.torque_from, scanned.torque_constant, scanned.read().torque_from) == ("currents", 0.25, "currents")
    whole = RigLogFile(path, torque_constant=2)  # a whole number is a constant too, kept as a float
    assert whole.torque_constant == 2.0 and type(whole.torque_constant) is float
    np.testing.assert_array_equal(whole.read().tau[0], [2.0, -4.0, 1.0])


def test_torques_and_currents_both_take_the_torques(tmp_path):
    header = "current_1_A,t_s,current_2_A,current_3_A,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg,x"
    path = write(tmp_path, [header] + [f"9,{k / 100:.2f},9,9,800,4,5,6,1,2,3,0" for k in range(3)])
    scanned = RigLogFile(path, torque_constant=0.5)
    np.testing.assert_array_equal(scanned.read().tau[0], [0.004, 0.005, 0.006])
    assert scanned.torque_from == "torques" and scanned.torque_constant is None
    # The unused columns in the header's order, then the currents the torques made unneeded.
    assert scanned.ignored == ("x", "current_1_A", "current_2_A", "current_3_A")


@pytest.mark.parametrize("constant", [-1.0, 0.0, 0, math.nan, math.inf, True, "0.25", [0.25]])
def test_a_torque_constant_that_is_no_positive_number(tmp_path, constant):
    header = "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg"
    path = write(tmp_path, [header] + [f"{k / 100:.2f},800,1,-2,0.5,1,2,3" for k in range(4)])
    refused(
        path, f": the torque constant must be a positive number in N·m/A, got {constant!r}", torque_constant=constant
    )


def test_currents_without_a_torque_constant(tmp_path):
    header = "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg"
    path = write(tmp_path, [header] + [f"{k / 100:.2f},800,1,-2,0.5,1,2,3" for k in range(4)])
    refused(
        path,
        ": the log gives motor currents (current_1_A …) but no torque constant in N·m/A was given to turn them into "
        "torques: give --torque-constant NM_PER_A (torque_constant= in Python)",
    )


# --- Which columns are missing, and what is said of them ----------------------------------------------------------


@pytest.mark.parametrize(
    ("header", "message"),
    [
        ("t_ms,Fe_N", "missing time column 't_s' (the file has 't_ms': check the name and its unit)"),
        ("t_s,Fe", "missing load column 'Fe_N'"),  # 'Fe' is too far from 'Fe_N' (0.67 < 0.7) to be named
        ("t_s,F_N", "missing load column 'Fe_N' (the file has 'F_N': check the name and its unit)"),
        # Of two names as close, difflib's choice: the later in order.
        (
            "t_s,Fe_N,tau_1_Nmm,tau_3_Nmm",
            "missing torque column 'tau_2_Nmm' (the file has 'tau_3_Nmm': check the name and its unit)",
        ),
        (
            "t_s,Fe_N,tau_3_Nmm",
            "missing torque column 'tau_1_Nmm' (the file has 'tau_3_Nmm': check the name and its unit)",
        ),
        (
            "t_s,Fe_N,current_2_A,x",
            "missing current column 'current_1_A' (the file has 'current_2_A': check the name and its unit)",
        ),
        (
            "t_s,Fe_N,tau_1_N,tau_2_N,tau_3_N",
            "missing torque columns: expected tau_1_Nmm, tau_2_Nmm, tau_3_Nmm, or current_1_A … with a torque constant "
            "(the file has 'tau_1_N', 'tau_2_N', 'tau_3_N': check the names and units)",
        ),
        (
            "t_s,Fe_N,tau1",
            "missing torque columns: expected tau_1_Nmm, tau_2_Nmm, tau_3_Nmm, or current_1_A … with a torque constant",
        ),  # 0.62 < 0.7
        (
            "t_s,Fe_N,torque",
            "missing torque columns: expected tau_1_Nmm, tau_2_Nmm, tau_3_Nmm, or current_1_A … with a torque constant",
        ),
        (
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,x,y",
            "no motion: expected the platform angles alpha_deg, beta_deg, gamma_deg (attitude sensor) "
            "or platform 1's slider heights L_11_mm, L_12_mm, L_13_mm (motor encoders)",
        ),
        (
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_rad",
            "angle columns mix _deg and _rad: give all three in one unit",
        ),
        ("t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_rad,gamma_rad", "missing angle column 'beta_rad'"),
        (
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_rad,beta_rad,gamma_ra",
            "missing angle column 'gamma_rad' (the file has 'gamma_ra': check the name and its unit)",
        ),
        (
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,L_11_mm,L_13_mm",
            "missing slider height column 'L_12_mm' (the file has 'L_13_mm': check the name and its unit)",
        ),
        (
            "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,alpha_deg,beta_deg,gamma_deg,L_12_mm",
            "missing slider height column 'L_11_mm' (the file has 'L_12_mm': check the name and its unit)",
        ),
    ],
)
def test_a_missing_column_named_on_the_headers_line(tmp_path, header, message):
    width = header.count(",") + 1
    path = write(tmp_path, ["  # a rig log", "", header] + [",".join(["1"] * width)] * 3)
    error = refused(path, f"line 3: {message}")
    assert (error.line, error.column) == (3, None)


def test_a_repeated_column_and_a_header_that_cannot_be_split(tmp_path):
    error = refused(
        write(tmp_path, ["#", HEADER + ",Fe_N", row(0) + ",1"]), "line 2, column 'Fe_N': column 'Fe_N' appears twice"
    )
    assert (error.line, error.column) == (2, "Fe_N")
    message = "cannot split the line into cells (new-line character seen in unquoted field - do you need to open the file in universal-newline mode?)"
    refused(write(tmp_path, ["", "t_s,Fe\rN,x", row(0)], "cr.csv"), f"line 2: {message}")


def test_empty_files_and_no_samples(tmp_path):
    refused(write(tmp_path, ["", "# only a comment", " ,, "]), ": the file is empty")
    refused(write(tmp_path, ["# a header alone", HEADER], "header.csv"), ": no samples below the header")
    refused(write(tmp_path, [HEADER, "# no rows", ""], "comments.csv"), ": no samples below the header")
    refused(write(tmp_path, [HEADER, row(0)], "one.csv"), ": 1 sample; a log needs many")


# --- Separators, decimal commas, spaces, line ends --------------------------------------------------------------


def plain(log):
    """The plain log's values, by hand: (t, Fe, τ in N·m, angles in rad) of samples 0 … n−1."""
    k = np.arange(len(log))
    tau = np.column_stack([(100 + k) * 1e-3, (-50 - k) * 1e-3, np.full(k.size, 0.0255)])
    return k / 100, 1000.0 + k, tau, np.tile(np.radians([10.0, -2.0, 3.0]), (k.size, 1))


def assert_plain(log, n: int, lines):
    assert len(log) == n
    t, Fe, tau, angles = plain(log)
    np.testing.assert_allclose(log.t, t, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(log.Fe, Fe)
    np.testing.assert_allclose(log.tau, tau, rtol=1e-15)
    np.testing.assert_allclose(log.angles, angles, rtol=1e-15)
    np.testing.assert_array_equal(log.lines, lines)


def decimal_commas(line: str, sep: str) -> str:
    return line.replace(",", sep).replace(".", ",")


@pytest.mark.parametrize("sep", ["\t", ";"])
def test_decimal_commas_in_tab_and_semicolon_logs(tmp_path, sep):
    lines = [HEADER.replace(",", sep)] + [decimal_commas(line, sep) for line in rows(6)]
    assert "0,01" in lines[2] and "25,5" in lines[1]
    assert_plain(read_rig_log(write(tmp_path, lines)), 6, [2, 3, 4, 5, 6, 7])
    # With a comment among the rows (its block read without the comment), with trailing separators on a row (a
    # spreadsheet's empty cells, each cell then read alone): the same values.
    lines.insert(3, "# a note")
    lines[5] += sep + sep
    assert_plain(read_rig_log(write(tmp_path, lines, "b.csv")), 6, [2, 3, 5, 6, 7, 8])
    # Decimal points are read too.
    lines = [HEADER.replace(",", sep)] + [line.replace(",", sep) for line in rows(6)]
    assert_plain(read_rig_log(write(tmp_path, lines, "c.csv")), 6, [2, 3, 4, 5, 6, 7])


def test_the_first_row_decides_the_separator(tmp_path):
    """A header that ';' splits too (a name holding one) is split as its first row is: by ','."""
    log = read_rig_log(write(tmp_path, [HEADER + ",a;b,flag_X", *(line + ",1,0" for line in rows(4))]))
    assert_plain(log, 4, [2, 3, 4, 5])
    assert log.ignored == ("a;b", "flag_X")


def test_spaces_around_names_and_crlf_line_ends(tmp_path):
    header = " " + HEADER.replace(",", " , ")
    path = tmp_path / "crlf.csv"
    path.write_bytes(("\r\n".join([header, *rows(5)]) + "\r\n").encode())
    assert_plain(read_rig_log(path), 5, [2, 3, 4, 5, 6])
    # A row with a trailing comma (one cell too many, and blank), and one with a spreadsheet's empty cells at the end.
    lines = [HEADER, *rows(5)]
    lines[2] += ","
    lines[4] += ",, "
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode())
    assert_plain(read_rig_log(path), 5, [2, 3, 4, 5, 6])
    # A spreadsheet's empty cells after the header's names are no columns.
    log = read_rig_log(write(tmp_path, [HEADER + ",,", *(line + ",," for line in rows(4))], "sheet.csv"))
    assert_plain(log, 4, [2, 3, 4, 5])
    assert log.ignored == ()


def test_a_block_of_plain_numbers_is_read_at_once(tmp_path, monkeypatch):
    """Rows of numbers only, decimal commas included, are parsed a block at once, not cell by cell."""
    calls = []

    def counted(cell, decimal_comma=False):
        calls.append(cell)
        return float(cell)

    loads = []
    loadtxt = np.loadtxt

    def loaded(*args, **kwargs):
        loads.append(1)
        return loadtxt(*args, **kwargs)

    monkeypatch.setattr(text_rows, "parse_number", counted)
    monkeypatch.setattr(np, "loadtxt", loaded)
    # Two reads each: the first row (read with the header, to tell the separator), then the rest of the block.
    assert_plain(read_rig_log(write(tmp_path, [HEADER, *rows(5)])), 5, [2, 3, 4, 5, 6])
    assert len(loads) == 2
    tab = [HEADER.replace(",", "\t")] + [decimal_commas(line, "\t") for line in rows(5)]
    assert_plain(read_rig_log(write(tmp_path, tab, "tab.csv")), 5, [2, 3, 4, 5, 6])
    assert len(loads) == 4
    semi = [HEADER.replace(",", ";")] + [decimal_commas(line, ";") for line in rows(5)]
    semi.insert(2, "# a comment among the rows")  # the block's rows without it, still at once
    assert_plain(read_rig_log(write(tmp_path, semi, "semi.csv")), 5, [2, 4, 5, 6, 7])
    assert len(loads) == 6 and calls == []
    # Two rows: the second is a block of one row, read at once too.
    assert len(RigLogFile(write(tmp_path, [HEADER, *rows(2)], "two.csv"))) == 2
    assert len(loads) == 8 and calls == []


# --- A row's cells ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("line", "message"),
    [
        (row(3, tau2="abc"), "line 5, column 'tau_2_Nmm': 'abc' is not a number"),
        (row(3, tau2=" x1 "), "line 5, column 'tau_2_Nmm': 'x1' is not a number"),
        (row(3, Fe="1_000"), "line 5, column 'Fe_N': '1_000' is not a number"),  # float() would read 1000
        (row(3, g="3X"), "line 5, column 'gamma_deg': '3X' is not a number"),  # the last cell as written
        (row(0, a="ten"), "line 2, column 'alpha_deg': 'ten' is not a number"),  # the first row, read with the header
        (
            row(3, g="3,5"),
            "line 5: 9 cells, the header has 8 (decimal commas? a comma-separated log needs decimal points)",
        ),
        (row(3)[: row(3).rindex(",")], "line 5: 7 cells, the header has 8"),
        (
            "0.03,1\r0,1,1,1,1,1,1",
            "line 5: cannot split the line into cells (new-line character seen in unquoted field - do you need to open the file in universal-newline mode?)",
        ),
    ],
)
def test_a_bad_row_named_by_line_and_column(tmp_path, line, message):
    lines = [HEADER, *rows(6)]
    lines[int(message.split()[1].rstrip(",:")) - 1] = line  # the line the message names
    refused(write(tmp_path, lines), message)


def test_too_many_cells_in_a_semicolon_log_has_no_hint(tmp_path):
    lines = [HEADER.replace(",", ";")] + [line.replace(",", ";") for line in rows(4)]
    lines[2] += ";7"
    refused(write(tmp_path, lines), "line 3: 9 cells, the header has 8")


@pytest.mark.parametrize("block", [1, 2, 100])
def test_the_first_value_that_is_not_finite(tmp_path, block):
    lines = [HEADER, *rows(8)]
    lines[3] = row(2, tau3="inf", b="nan")  # the first of the row's two, by column
    lines[6] = row(5, Fe="nan")
    lines[7] = row(6, tau1="2e12")  # not finite comes first, before the checks of sizes
    refused(write(tmp_path, lines), "line 4, column 'tau_3_Nmm': 'inf' is not finite", block=block)
    lines[3] = row(2, b="-inf")
    refused(write(tmp_path, lines), "line 4, column 'beta_deg': '-inf' is not finite", block=block)


# --- Sizes beyond any machine, both sides of each bound ------------------------------------------------------------


def one_changed(tmp_path, name="log.csv", n=6, header=HEADER, **change):
    lines = [header, *rows(n)]
    lines[3] = row(2, **change)
    return write(tmp_path, lines, name)


def test_a_torque_beyond_any_motor(tmp_path):
    assert len(RigLogFile(one_changed(tmp_path, tau2="-1e9"))) == 6  # 1e9 N·mm itself is allowed
    refused(
        one_changed(tmp_path, tau2="-1000000001"),
        "line 4, column 'tau_2_Nmm': -1e+09 is beyond any motor of this machine (1e+09 N·mm): a unit slip?",
    )


def test_the_largest_torque_is_named_where_it_first_is(tmp_path):
    for block in (1, 3, 100):
        lines = [HEADER, *rows(8)]
        lines[2] = row(1, tau1="3e12")
        lines[4] = row(3, tau3="-4e12", tau2="4e12")  # the largest: the first of the row's two equal ones
        lines[7] = row(6, tau1="4e12")  # as large, later
        refused(
            write(tmp_path, lines),
            "line 5, column 'tau_2_Nmm': 4e+12 is beyond any motor of this machine (1e+09 N·mm): a unit slip?",
            block=block,
        )


def test_a_current_beyond_any_motor_through_its_constant(tmp_path):
    header = "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg"
    lines = [header] + [f"{k / 100:.2f},800,1,-2,0.5,1,2,3" for k in range(4)]
    lines[2] = "0.01,800,1,4e6,0.5,1,2,3"  # 4e6 A × 0.25 N·m/A = 1e6 N·m = 1e9 N·mm: the bound itself
    assert len(RigLogFile(write(tmp_path, lines), torque_constant=0.25)) == 4
    lines[2] = "0.01,800,1,-4.1e6,0.5,1,2,3"
    refused(
        write(tmp_path, lines),
        "line 3, column 'current_2_A': -4.1e+06 is beyond any motor of this machine (1e+09 N·mm): a unit slip?",
        torque_constant=0.25,
    )
    # The same current with a constant 10 times smaller is within the bound.
    assert len(RigLogFile(write(tmp_path, lines), torque_constant=0.025)) == 4


def test_angles_beyond_a_turn(tmp_path):
    assert len(RigLogFile(one_changed(tmp_path, a="-360", g="360"))) == 6
    refused(one_changed(tmp_path, b="-360.5"), "line 4, column 'beta_deg': -360.5 deg is more than a full turn")
    radians = [HEADER.replace("_deg", "_rad")] + [row(k, a="0.1", b="-0.2", g="0.3") for k in range(6)]
    radians[3] = row(2, g="-3.14159", a="3.14159", b="0")
    assert len(RigLogFile(write(tmp_path, radians))) == 6
    radians[3] = row(2, g="-3.2", a="0", b="0")
    refused(
        write(tmp_path, radians),
        "line 4, column 'gamma_rad': -3.2 rad is more than half a turn: these look like degrees; label the columns _deg",
    )


def test_heights_beyond_any_machine(tmp_path):
    header = "t_s,Fe_N,tau_1_Nmm,tau_2_Nmm,tau_3_Nmm,L_11_mm,L_12_mm,L_13_mm"
    lines = [header] + [f"{k / 100:.2f},800,1,2,3,600,610,590" for k in range(4)]
    lines[3] = "0.02,800,1,2,3,600,610,-100000"
    assert len(RigLogFile(write(tmp_path, lines))) == 4
    lines[3] = "0.02,800,1,2,3,600,610,-100001"
    refused(
        write(tmp_path, lines), "line 4, column 'L_13_mm': -100001 mm is beyond any machine of this kind: a unit slip?"
    )


def test_loads_below_zero_and_beyond_a_unit_slip(tmp_path):
    assert RigLogFile(one_changed(tmp_path, Fe="0")).read().Fe[2] == 0.0
    assert RigLogFile(one_changed(tmp_path, Fe="1e9")).read().Fe[2] == 1e9
    refused(one_changed(tmp_path, Fe="-0.5"), "line 4, column 'Fe_N': load -0.5 N is negative (F_e is a magnitude)")
    refused(one_changed(tmp_path, Fe="2e9"), "line 4, column 'Fe_N': load 2e+09 N is beyond 1e+09 N (a unit slip?)")


@pytest.mark.parametrize("block", [1, 2, 100])
def test_the_least_and_largest_loads_are_named_where_they_first_are(tmp_path, block):
    lines = [HEADER, *rows(8)]
    lines[3], lines[5], lines[7] = row(2, Fe="-2"), row(4, Fe="-3"), row(6, Fe="-3")
    refused(write(tmp_path, lines), "line 6, column 'Fe_N': load -3 N is negative (F_e is a magnitude)", block=block)
    lines[3], lines[5], lines[7] = row(2, Fe="3e9"), row(4, Fe="4e9"), row(6, Fe="4e9")
    refused(write(tmp_path, lines), "line 6, column 'Fe_N': load 4e+09 N is beyond 1e+09 N (a unit slip?)", block=block)


# --- Time ---------------------------------------------------------------------------------------------------------


def test_times_that_do_not_increase_or_are_uneven(tmp_path):
    lines = [HEADER, *rows(8)]
    lines[5] = row(4, t="0.03")
    refused(write(tmp_path, lines), "line 6, column 't_s': time 0.03 s does not increase (previous 0.03 s)")
    lines[5] = row(4, t="0.041")  # a tenth of a step off: more than a thousandth of one
    refused(
        write(tmp_path, lines),
        "line 6, column 't_s': uneven time step: 0.011 s here, 0.01 s elsewhere (a dropped or repeated sample, or clock "
        "jitter): resample the data onto an even grid",
    )


def test_milliseconds_under_t_s_are_refused(tmp_path):
    lines = [HEADER] + [row(k, t=str(k)) for k in range(60)]  # 59 "s" of a gait at 1 Hz: 59 ms in fact
    path = write(tmp_path, lines)
    with pytest.raises(TrajectoryError) as error:
        RigLogFile(path)
    assert str(error.value).startswith(f"{path}, column 't_s': the times look like milliseconds: a sample every 1 s")
    assert (error.value.line, error.value.column) == (None, "t_s")


def test_epoch_stamps_are_read_from_the_first(tmp_path):
    lines = [HEADER] + [row(k, t=f"{1_733_000_000 + k / 100:.2f}") for k in range(5)]
    path = write(tmp_path, lines)
    with pytest.warns(TrajectoryWarning) as record:
        log = read_rig_log(path)
    (message,) = [str(r.message) for r in record if issubclass(r.category, TrajectoryWarning)]
    assert message.startswith(f"{path}: column 't_s': the times are Unix time stamps (from 2024-11-30")
    np.testing.assert_allclose(log.t, np.arange(5) / 100, rtol=0, atol=2.0**-22)
    assert log.t[0] == 0.0


def test_times_from_the_sample_index(tmp_path):
    """rate: t₀ + k/rate for stamps too coarse to order the samples (here 1 kHz stamped to 10 ms)."""
    lines = [HEADER] + [row(k, t=f"{5 + k / 1000:.2f}") for k in range(101)]  # 5.00 … 5.10 s, each stamp ten times
    path = write(tmp_path, lines)
    with pytest.raises(TrajectoryError, match="does not increase"):
        RigLogFile(path)
    scanned = RigLogFile(path, rate=1000.0)
    np.testing.assert_array_equal(scanned.t, 5.0 + np.arange(101) / 1000.0)
    assert scanned.rate == pytest.approx(1000.0, rel=1e-9) and scanned.read().t[100] == 5.1
    assert len(RigLogFile(path, rate=1009)) == 101  # a span of 0.1 s for 0.0991 s: within 1 %
    assert len(RigLogFile(path, rate=991)) == 101  # 0.1009 s: within 1 %
    tail = "column 't_s': the times span 0.1 s, the 101 samples at {} Hz {} s: is the sample rate the log's?"
    refused(path, tail.format(1011, 0.098912), rate=1011)  # 100/1011 s: 1.1 % shorter
    refused(path, tail.format(989, 0.101112), rate=989)  # 100/989 s: 1.1 % longer
    lines[40] = row(39, t="5.03")  # after 5.04
    refused(write(tmp_path, lines), "line 41, column 't_s': time 5.03 s decreases (previous 5.04 s)", rate=1000.0)


def test_times_from_the_index_at_the_edge_of_the_span(tmp_path):
    """Stamps in whole 10 ms of 1002 samples at 1 kHz from 5.009 s: 5.00, 5.01 (the first two differ) … 6.00, 6.01
    (so do the last two): a span of 1.01 s. At 985 Hz, 1001 samples span 1.01624 s: within 1 % of 1.01 s (not of
    1.00 s, the span from the second stamp or to the one but last)."""
    lines = [HEADER] + [row(k, t=f"{(5009 + k) // 10 / 100:.2f}") for k in range(1002)]
    path = write(tmp_path, lines)
    scanned = RigLogFile(path, rate=985)
    assert len(scanned) == 1002 and scanned.t[0] == 5.0 and scanned.t[1] == 5.0 + 1 / 985
    refused(
        path,
        "column 't_s': the times span 1.01 s, the 1002 samples at 1030 Hz 0.971845 s: is the sample rate the log's?",
        rate=1030,
    )


def test_times_from_the_index_below_one_hertz(tmp_path):
    lines = [HEADER] + [row(k, t=f"{2 * k}") for k in range(20)]  # 0.5 Hz for 38 s
    scanned = RigLogFile(write(tmp_path, lines), rate=0.5)
    np.testing.assert_array_equal(scanned.t, 2.0 * np.arange(20))


def test_the_time_that_decreases_and_the_one_before_it(tmp_path):
    lines = [HEADER] + [row(k, t=f"{k / 1000:.4f}") for k in range(10)]
    lines[5] = row(4, t="0.0025")  # after 0.003, before 0.005
    refused(write(tmp_path, lines), "line 6, column 't_s': time 0.0025 s decreases (previous 0.003 s)", rate=1000)


@pytest.mark.parametrize("rate", [0.0, -1000.0, math.nan, math.inf, True, "1000"])
def test_a_rate_that_is_no_positive_number(tmp_path, rate):
    refused(
        write(tmp_path, [HEADER, *rows(4)]),
        f": the sample rate must be a positive number in Hz, got {rate!r}",
        rate=rate,
    )


# --- Blocks, windows, the bytes read -----------------------------------------------------------------------------


def numbered(n: int, comment_at=(), blank_at=(), sheet_at=()):
    """The plain log with a cycle counter (k // 10), comments, empty lines and a spreadsheet's empty rows at those file
    lines."""
    lines = [HEADER + ",cycle"]
    k = 0
    while k < n:
        number = len(lines) + 1
        if number in comment_at:
            lines.append(("  " if number % 2 else "") + f"# note on line {number}")  # some indented
        elif number in blank_at:
            lines.append("")
        elif number in sheet_at:
            lines.append(" ,, ")
        else:
            lines.append(row(k) + f",{k // 10}")
            k += 1
    return lines


def sample_lines(lines, first=1, stop=math.inf):
    return [
        number
        for number, line in enumerate(lines, start=1)
        if number > 1 and first <= number < stop and line[:1].isdigit()
    ]


@pytest.mark.parametrize("block", [1, 2, 3, 7, 10_000])
def test_blocks_of_any_size_give_the_same_log(tmp_path, block):
    lines = numbered(30, comment_at=(2, 9, 10, 11, 12), blank_at=(3, 20), sheet_at=(21,))
    scanned = RigLogFile(write(tmp_path, lines), block=block, keep=("cycle", "absent"))
    log = scanned.read()
    assert_plain(log, 30, sample_lines(lines))
    assert list(scanned.kept) == ["cycle"]
    np.testing.assert_array_equal(scanned.kept["cycle"], np.arange(30) // 10)


@pytest.mark.parametrize("block", [1, 3])
def test_a_block_of_comments_or_empty_lines_is_read_without_a_numpy_warning(tmp_path, block):
    # Blocks of three lines after the first row's (line 2): lines 6–8 are comments, 9–11 empty.
    lines = numbered(12, comment_at=(6, 7, 8), blank_at=(9, 10, 11))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scanned = RigLogFile(write(tmp_path, lines), block=block)
    assert [str(w.message) for w in caught if w.category is UserWarning] == []
    assert scanned.lines.tolist() == sample_lines(lines)


@pytest.mark.parametrize("block", [1, 4, 10_000])
@pytest.mark.parametrize(("first", "stop"), [(1, 12), (2, 12), (3, 13), (5, 19), (14, 17), (20, 10**9), (1, math.inf)])
def test_a_window_of_lines(tmp_path, block, first, stop):
    lines = numbered(30, comment_at=(9, 10), blank_at=(15,), sheet_at=(25,))
    path = write(tmp_path, lines)
    wanted = sample_lines(lines, first, stop)
    scanned = RigLogFile(path, block=block, keep=("cycle",), lines=(first, stop))
    assert scanned.lines.tolist() == wanted
    k = np.array([int(lines[n - 1].split(",")[-1]) for n in wanted])
    np.testing.assert_array_equal(scanned.kept["cycle"], k)
    log = scanned.read()
    np.testing.assert_array_equal(log.Fe, [float(lines[n - 1].split(",")[1]) for n in wanted])
    data = path.read_bytes()  # a small file is read whole, in one block
    assert (scanned.sha256, scanned.size) == (hashlib.sha256(data).hexdigest(), len(data))


def test_a_window_parses_nothing_after_it_and_nothing_before_it(tmp_path):
    lines = numbered(30)
    lines[20] = row(19, Fe="oops") + ",1"  # line 21
    lines[5] = row(4, Fe="-1") + ",0"  # line 6
    path = write(tmp_path, lines)
    refused(path, "line 21, column 'Fe_N': 'oops' is not a number")
    refused(path, "line 6, column 'Fe_N': load -1 N is negative (F_e is a magnitude)", lines=(1, 21), block=3)
    assert RigLogFile(path, lines=(7, 21), block=3).lines.tolist() == list(range(7, 21))
    refused(path, "line 21, column 'Fe_N': 'oops' is not a number", lines=(7, 22), block=3)
    refused(path, ": no samples below the header", lines=(40, 50))
    refused(path, ": 1 sample; a log needs many", lines=(7, 8))
    # A window that ends on the first row's line, or just after it (the rest of its block not read).
    refused(path, ": no samples below the header", lines=(1, 2))
    refused(path, ": 1 sample; a log needs many", lines=(1, 3))
    assert len(RigLogFile(path, lines=(1, 4))) == 2  # two samples are a log


def long_file(tmp_path, lines, size: int, name="long.csv", encoding="utf-8"):
    """The lines, then comments of 100 bytes up to ``size`` bytes: a long file whose tail costs nothing to parse."""
    head = ("\n".join(lines) + "\n").encode(encoding)
    comment = b"#" + b"c" * 98 + b"\n"
    path = tmp_path / name
    path.write_bytes(head + comment * ((size - len(head)) // 100 + 1))
    return path, path.read_bytes()


def test_a_window_reads_its_block_alone(tmp_path):
    """Of a file larger than a block (64 KiB for small ``block``, 100 bytes a line of ``block`` up to 4 MiB), a window
    near the start reads and hashes that block alone; a whole read hashes every byte."""
    path, data = long_file(tmp_path, [HEADER] + rows(30), 4_300_000)
    for block, size in ((5, 1 << 16), (1000, 100_000), (10_000, 1_000_000), (100_000, 1 << 22)):
        window = RigLogFile(path, block=block, lines=(10, 20))
        assert (window.size, window.sha256) == (size, hashlib.sha256(data[:size]).hexdigest())
        assert window.lines.tolist() == list(range(10, 20))
    # A window that ends where the second block starts reads the first alone.
    stop = data[: 1 << 16].count(b"\n") + 1
    assert RigLogFile(path, block=5, lines=(10, stop)).size == 1 << 16
    whole = RigLogFile(path)
    assert (whole.size, whole.sha256, len(whole)) == (len(data), hashlib.sha256(data).hexdigest(), 30)


def test_a_log_of_currents_read_again_keeps_its_torque_constant(tmp_path):
    header = "t_s,Fe_N,current_1_A,current_2_A,current_3_A,alpha_deg,beta_deg,gamma_deg"
    lines = [header] + [f"{k / 100:.2f},800,1,-2,0.5,1,2,3" for k in range(6)] + ["# caf\xe9"]
    path = tmp_path / "c.csv"
    path.write_bytes(("\n".join(lines) + "\n").encode("latin-1"))
    window = RigLogFile(path, torque_constant=0.25, lines=(1, 8))
    assert window.torque_from == "currents" and len(window) == 6
    np.testing.assert_array_equal(window.read().tau[5], [0.25, -0.5, 0.125])


def test_a_window_before_a_fault_read_again_reads_a_mebibyte(tmp_path):
    lines = [HEADER] + rows(20) + ["# caf\xe9"]  # line 22
    path, data = long_file(tmp_path, lines, 1_500_000, encoding="latin-1")
    window = RigLogFile(path, block=5, lines=(1, 22))
    assert (len(window), window.size, window.sha256) == (20, 1 << 20, hashlib.sha256(data[: 1 << 20]).hexdigest())


def test_a_window_before_a_fault_is_read_line_by_line(tmp_path):
    """A byte that is not UTF-8 sends the scan back to the file's start, line by line (``block`` lines at a time): the
    window before it reads; the file whole, or a window that reaches it, is refused on its line."""
    lines = numbered(30, comment_at=(2,), blank_at=(3,))
    lines[22] = "# caf\xe9"  # line 23, written in Latin-1 below
    path = tmp_path / "latin.csv"
    path.write_bytes(("\n".join(lines) + "\n").encode("latin-1"))
    data = path.read_bytes()
    refused(path, "line 23: not a text (UTF-8) log file")
    for block in (1, 2, 50):
        window = RigLogFile(path, block=block, keep=("cycle",), lines=(1, 23))
        assert window.lines.tolist() == sample_lines(lines, 1, 23)
        np.testing.assert_array_equal(window.read().Fe, [1000.0 + k for k in range(len(window))])
        np.testing.assert_array_equal(window.kept["cycle"], np.arange(len(window)) // 10)
        assert (window.sha256, window.size) == (hashlib.sha256(data).hexdigest(), len(data))  # 1 MiB at a time
        assert RigLogFile(path, block=block, lines=(10, 23)).lines.tolist() == sample_lines(lines, 10, 23)
        refused(path, "line 23: not a text (UTF-8) log file", block=block, lines=(10, 24))


# --- A scanned log read back in pieces ---------------------------------------------------------------------------


def test_pieces_of_a_scanned_log(tmp_path):
    lines = [HEADER + ",L_11_mm,L_12_mm,L_13_mm,x"] + [row(k) + f",600,{610 + k},590,7" for k in range(10)]
    scanned = RigLogFile(write(tmp_path, lines))
    piece = scanned.piece(3, 6)
    assert isinstance(piece, RigLog) and len(piece) == 3
    np.testing.assert_array_equal(piece.t, [0.03, 0.04, 0.05])
    np.testing.assert_array_equal(piece.Fe, [1003.0, 1004.0, 1005.0])
    np.testing.assert_allclose(piece.tau[:, 0], [0.103, 0.104, 0.105], rtol=1e-15)
    np.testing.assert_allclose(given(piece.angles)[2], np.radians([10.0, -2.0, 3.0]), rtol=1e-15)
    np.testing.assert_allclose(given(piece.heights)[:, 1], [0.613, 0.614, 0.615], rtol=1e-15)
    np.testing.assert_array_equal(piece.lines, [5, 6, 7])
    assert (piece.source, piece.torque_from, piece.ignored, piece.angle_unit) == (
        str(tmp_path / "log.csv"),
        "torques",
        ("x",),
        "deg",
    )
    whole = scanned.piece(-5, 99)  # clipped to the log
    assert len(whole) == 10 and whole.lines[0] == 2 and whole.lines[-1] == 11
    np.testing.assert_array_equal(whole.Fe, scanned.read().Fe)
    scanned.close()
    with pytest.raises(ValueError, match="closed file"):
        scanned.piece(0, 1)  # the store is dropped


def test_a_rig_log_checks_its_shapes():
    t = np.arange(4) / 100
    log = RigLog(t, np.ones(4), np.zeros((4, 3)), None, np.zeros((4, 3)), np.arange(2, 6), "x.csv")
    assert len(log) == 4 and log.rate == pytest.approx(100.0, rel=1e-12) and log.angle_unit is None
    with pytest.raises(ArgumentError, match=r"RigLog.tau: expected shape \(4, 3\), got shape \(4, 2\)"):
        RigLog(t, np.ones(4), np.zeros((4, 2)), None, None, np.arange(4), "x.csv")
    with pytest.raises(ArgumentError, match=r"RigLog.angles"):
        RigLog(t, np.ones(4), np.zeros((4, 3)), np.zeros((3, 3)), None, np.arange(4), "x.csv")
    with pytest.raises(ArgumentError, match=r"RigLog.heights"):
        RigLog(t, np.ones(4), np.zeros((4, 3)), None, np.zeros((4, 2)), np.arange(4), "x.csv")
    with pytest.raises(ArgumentError, match=r"RigLog.lines"):
        RigLog(t, np.ones(4), np.zeros((4, 3)), None, None, np.arange(5), "x.csv")
    with pytest.raises(ArgumentError, match=r"RigLog.Fe"):
        RigLog(t, np.ones(3), np.zeros((4, 3)), None, None, np.arange(4), "x.csv")


def test_read_rig_log_is_the_file_read_whole(tmp_path):
    path = write(tmp_path, [HEADER, *rows(5)])
    log, scanned = read_rig_log(path, torque_constant=0.5), RigLogFile(path)
    for name in ("t", "Fe", "tau", "angles", "lines"):
        np.testing.assert_array_equal(getattr(log, name), getattr(scanned.read(), name))
    refused(
        write(tmp_path, [HEADER.replace("tau", "current").replace("Nmm", "A"), *rows(5)], "c.csv"),
        ": the torque constant must be a positive number in N·m/A, got -1",
        torque_constant=-1,
    )
    header = HEADER.replace("tau", "current").replace("Nmm", "A")
    np.testing.assert_array_equal(
        read_rig_log(write(tmp_path, [header, *rows(3)], "d.csv"), 2.0).tau[0], [200.0, -100.0, 51.0]
    )


def test_a_refused_log_leaves_no_temporary_store_open(tmp_path):
    """The scan's temporary store is closed when the file is refused after it (here: no samples in the window)."""
    path = write(tmp_path, [HEADER] + [row(k) for k in range(5)])
    gc.collect()  # earlier tests' garbage is not this test's
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        for _ in range(3):
            with pytest.raises(TrajectoryError):
                RigLogFile(path, lines=(100, 200))
        gc.collect()
    assert not [r for r in record if issubclass(r.category, ResourceWarning)]


def test_a_reread_closes_the_first_tries_store(tmp_path):
    """A byte that is not UTF-8 past the first 64 KiB read starts the scan again line by line: the first try's
    temporary store (made once its first block was parsed) is closed then, and the second's on the refusal."""
    comments = ["#" + "c" * 98] * 700  # 70 kB: the bad byte in the second block read
    path = tmp_path / "latin.csv"
    path.write_bytes(("\n".join([HEADER, *rows(20), *comments, "# caf\xe9"]) + "\n").encode("latin-1"))
    gc.collect()  # earlier tests' garbage is not this test's
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        for _ in range(3):
            with pytest.raises(TrajectoryError, match="line 722: not a text"):
                RigLogFile(path, block=5)
        gc.collect()
    assert not [r for r in record if issubclass(r.category, ResourceWarning)]
